#pragma once
// Test support for the porosity tests: one grain at rest and the porosity
// field of a scheme once that grain is mapped to the mesh (floor 0.1, the
// diffused scheme's default smoothing length of one cell); random grains.
#include <random>

#include "core/particles.hpp"
#include "core/types.hpp"
#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "mesh/box_mesh.hpp"

namespace fdem::test_support {

inline Particles one_particle(const Vec3& x, double d) {
  Particles p;
  p.add(x.x(), x.y(), x.z(), d, 2650.0);  // at rest, mass rho V
  return p;
}

/// The field after one update with a grain of diameter d at x; `element`
/// (when given) receives the element holding its centre.
inline PorosityField porosity_of_one_grain(const BoxMesh& mesh, PorosityScheme scheme, const Vec3& x, double d,
                                           Index* element = nullptr) {
  PorosityField field(mesh, scheme, 0.1);
  ParticleMapping map;
  const Particles p = one_particle(x, d);
  map.update(mesh, p);
  field.update(p, map);
  if (element) *element = map.element[0];
  return field;
}

/// n grains of 0.2-0.8 mm uniformly in [0, upper] (centres; grains may stick
/// out of the box), the sum of their volumes in *solid.
inline Particles random_particles(int n, const Vec3& upper, unsigned seed, double* solid) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Particles p;
  *solid = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = 2e-4 + 6e-4 * u(rng);
    p.x.push_back(upper.x() * u(rng));
    p.y.push_back(upper.y() * u(rng));
    p.z.push_back(upper.z() * u(rng));
    p.diameter.push_back(d);
    *solid += sphere_volume(d);
  }
  return p;
}

}  // namespace fdem::test_support
