// The intersection porosity scheme and the diffused scheme's smoothing length
// resolved from a scene (coupling/porosity.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"

namespace fdem {
namespace {

double solid_volume(const BoxMesh& mesh, const PorosityField& field) {
  double s = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) s += mesh.element_volume(e) * (1.0 - field[e]);
  return s;
}

// Random grains of 0.5-1.5 mm wholly inside a box of 3 mm cells: the solid
// the field holds is the grains' volume to round-off (each grain's volumes
// over the tetrahedra it touches tile it exactly), at cell / d = 2-6.
TEST(PorosityIntersection, HoldsEveryGrainsVolumeExactly) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.012, 0.012, 0.015), {4, 4, 5});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Particles p;
  double solid = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double d = 0.5e-3 + 1e-3 * u(rng), r = 0.5 * d;
    p.add(r + (0.012 - d) * u(rng), r + (0.012 - d) * u(rng), r + (0.015 - d) * u(rng), d, 2500.0);
    solid += sphere_volume(d);
  }
  ParticleMapping map;
  map.update(mesh, p);
  PorosityField field(mesh, PorosityScheme::intersection, 1e-6);
  const PorosityUpdate upd = field.update(p, map);
  EXPECT_EQ(upd.floored_elements, 0);
  EXPECT_NEAR(solid_volume(mesh, field) / solid, 1.0, 1e-12);
}

// grain_means (the deposit's transpose, model A's pressure force) sums the
// overlaps update() found instead of recomputing the sphere-tetrahedron
// volumes: the same bits as the recomputation (a field that has seen no
// update() recomputes them), and after the grains move, update() refreshes them.
TEST(PorosityIntersection, GrainMeansFromTheUpdatesOverlapsEqualRecomputedOnes) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.012, 0.012, 0.015), {4, 4, 5});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Particles p;
  for (int i = 0; i < 100; ++i) {
    const double d = 0.5e-3 + 1e-3 * u(rng), r = 0.5 * d;
    p.add(r + (0.012 - d) * u(rng), r + (0.012 - d) * u(rng), r + (0.015 - d) * u(rng), d, 2500.0);
  }
  std::vector<Vec3> f(static_cast<std::size_t>(mesh.num_elements()));
  for (Vec3& x : f) x = Vec3(u(rng) - 0.5, u(rng) - 0.5, 1.0 + u(rng));
  PorosityField cached(mesh, PorosityScheme::intersection, 1e-6);  // updated twice: its overlaps refreshed
  for (int moved = 0; moved < 2; ++moved) {
    if (moved == 1)
      for (std::size_t i = 0; i < p.size(); ++i) p.z[i] = std::min(p.z[i] + 0.7e-3, 0.015 - 0.5 * p.diameter[i]);
    ParticleMapping map;
    map.update(mesh, p);
    cached.update(p, map);
    PorosityField recomputing(mesh, PorosityScheme::intersection, 1e-6);
    std::vector<Vec3> a(p.size()), b(p.size());
    cached.grain_means(p, map, f, a);
    recomputing.grain_means(p, map, f, b);
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_EQ(a[i].x(), b[i].x()) << "grain " << i << " moved " << moved;
      EXPECT_EQ(a[i].z(), b[i].z()) << "grain " << i << " moved " << moved;
    }
    EXPECT_GT(a[0].z(), 0.0);
  }
}

// A grain sliding across the face between two cells moves its volume
// continuously: over 1 um steps (d / 1000) no element's solid fraction jumps
// by more than the grain's cross-section times the step over the element's
// volume (pi r^2 dx / V_e, the most a 1 um slice can carry), where the centre
// scheme moves the whole grain at once.
TEST(PorosityIntersection, GrainCrossingAFaceMovesItsVolumeContinuously) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.006, 0.003, 0.003), {2, 1, 1});
  const double d = 1e-3, r = 0.5 * d, dx = 1e-6;
  PorosityField field(mesh, PorosityScheme::intersection, 1e-6);
  ParticleMapping map;
  std::vector<double> previous;
  double largest_jump = 0.0, bound = 0.0;
  for (int k = 0; k <= 1000; ++k) {
    Particles p;
    p.add(0.0025 + k * dx, 0.0011, 0.0017, d, 2500.0);
    map.update(mesh, p);
    field.update(p, map);
    std::vector<double> now(field.values().begin(), field.values().end());
    if (!previous.empty())
      for (Index e = 0; e < mesh.num_elements(); ++e) {
        const auto i = static_cast<std::size_t>(e);
        largest_jump = std::max(largest_jump, std::abs(now[i] - previous[i]));
        bound = std::max(bound, pi * r * r * dx / mesh.element_volume(e));
      }
    previous = now;
  }
  EXPECT_GT(largest_jump, 0.0);
  EXPECT_LE(largest_jump, 1.01 * bound);  // 1 %: the second-order part of the swept volume
}

// The smoothing length: 2 d by default, the diameters or metres given, capped
// at max(one cell, thinnest non-spanning extent / 6).
TEST(PorosityIntersection, SmoothingLengthInDiametersCappedByTheBed) {
  const BoxMesh mesh(Vec3::Zero(), Vec3(0.012, 0.012, 0.060), {4, 4, 20});  // 3 mm cells
  // A bed filling the cross-section (wall to wall in x, y), 30 mm thick in z.
  Particles bed;
  for (int k = 0; k < 30; ++k)
    for (int j = 0; j < 12; ++j)
      for (int i = 0; i < 12; ++i) bed.add(0.5e-3 + i * 1e-3, 0.5e-3 + j * 1e-3, 0.0155 + k * 1e-3, 1e-3, 2500.0);
  CouplingSpec c;
  c.porosity = PorosityScheme::diffused;
  SmoothingLength s = resolve_smoothing_length(c, mesh, bed);
  EXPECT_DOUBLE_EQ(s.requested, 2e-3);  // kDefaultSmoothingDiameters x d
  EXPECT_DOUBLE_EQ(s.cap, 5e-3);        // 30 mm / 6 (x and y span the duct: not counted)
  EXPECT_DOUBLE_EQ(s.length, 2e-3);
  c.porosity_smoothing_diameters = 8.0;
  s = resolve_smoothing_length(c, mesh, bed);
  EXPECT_DOUBLE_EQ(s.length, 5e-3);  // 8 mm asked, the 30 mm bed allows 5 mm
  c.porosity_smoothing_diameters.reset();
  c.porosity_smoothing_length = 4e-3;
  EXPECT_DOUBLE_EQ(resolve_smoothing_length(c, mesh, bed).length, 4e-3);
  EXPECT_DOUBLE_EQ(PorosityField(mesh, c, bed).smoothing_length(), 4e-3);
  // A thin column (1 mm wide) allows no more than one cell (3 mm > 1 mm / 6).
  Particles thin;
  for (int k = 0; k < 6; ++k) thin.add(0.006, 0.006, 0.0205 + k * 1e-3, 1e-3, 2500.0);
  c.porosity_smoothing_length = 10e-3;
  s = resolve_smoothing_length(c, mesh, thin);
  EXPECT_DOUBLE_EQ(s.cap, 3e-3);
  EXPECT_DOUBLE_EQ(s.length, 3e-3);
}

}  // namespace
}  // namespace fdem
