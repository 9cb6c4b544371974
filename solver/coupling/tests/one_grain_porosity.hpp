#pragma once
// Test support: one grain at rest, and the porosity field of a scheme once
// that grain is mapped to the mesh (floor 0.1, the diffused scheme's default
// smoothing length of one cell).
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

}  // namespace fdem::test_support
