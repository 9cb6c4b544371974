// Hard case: a particle exactly on a face, an edge and a vertex of the mesh,
// on the box's own boundary, and one that leaves the domain.
// Mapping policy (mesh/box_mesh.hpp): a point on a cell face belongs to the
// cell above it (the last cell on the box's upper faces); a point on the
// central tetrahedron's boundary belongs to the central tetrahedron.
// Domain policy (dem/dem_engine.cpp): with walls on, a particle is reflected
// by the wall; with walls off, a particle whose centre leaves the box is
// removed and counted (DemDiagnostics::particles_removed), the others keep
// their original ids.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "coupling/particle_mapping.hpp"
#include "coupling/porosity.hpp"
#include "coupling/simulation.hpp"
#include "dem/dem_engine.hpp"
#include "hard_scenes.hpp"
#include "mesh/box_mesh.hpp"

// A namespace of its own: the executable compiles its files as one unit.
namespace fdem::mesh_boundaries_test {
namespace {

constexpr double kCell = 1e-3;  // cell size [m]

BoxMesh three_cubed() { return BoxMesh(Vec3::Zero(), Vec3::Constant(3 * kCell), {3, 3, 3}); }

// An arbitrary smooth nodal field (not linear, so the element matters unless the point is shared).
double field(const Vec3& x) { return std::sin(1234.0 * x.x()) + x.y() * x.z() * 1e6 + std::exp(700.0 * x.z()); }

double interpolate(const BoxMesh& mesh, Index e, const Vec3& p) {
  const Eigen::Vector4d lambda = mesh.volume_coordinates(e, p);
  double v = 0.0;
  for (int a = 0; a < 4; ++a) v += lambda[a] * field(mesh.node(mesh.element_nodes(e)[static_cast<std::size_t>(a)]));
  return v;
}

struct Location {
  const char* what;
  Vec3 point;
};

// Points exactly on shared mesh entities, built from node coordinates so they are exact.
std::vector<Location> shared_locations(const BoxMesh& m) {
  const Vec3 n111 = m.node(m.node_index(1, 1, 1)), n211 = m.node(m.node_index(2, 1, 1));
  const Vec3 n121 = m.node(m.node_index(1, 2, 1)), n112 = m.node(m.node_index(1, 1, 2));
  const Vec3 n222 = m.node(m.node_index(2, 2, 2)), n333 = m.node(m.node_index(3, 3, 3));
  const Vec3 n000 = m.node(m.node_index(0, 0, 0)), n303 = m.node(m.node_index(3, 0, 3));
  return {
      {"interior vertex", n111},
      {"interior cell edge (midpoint)", 0.5 * (n111 + n211)},
      {"interior cell face (off-diagonal point)", Vec3(n111.x(), n111.y() + 0.3 * kCell, n111.z() + 0.6 * kCell)},
      {"interior face diagonal (edge of the 5-tet split)", 0.5 * (n111 + Vec3(n111.x(), n121.y(), n112.z()))},
      {"cell centre of the middle cell", 0.5 * (n111 + n222)},
      {"box lower corner", n000},
      {"box upper corner", n333},
      {"box upper edge", 0.5 * (n303 + n333)},
  };
}

TEST(MeshBoundaries, PointOnFaceEdgeVertexMapsToOneDeterministicElementThatHoldsIt) {
  // Shows: each shared point maps to one valid element, the same on every call, with coordinates in [0,1] summing to 1.
  const BoxMesh mesh = three_cubed();
  for (const auto& [what, p] : shared_locations(mesh)) {
    const Index e = mesh.locate_element(p);
    ASSERT_GE(e, 0) << what;
    ASSERT_LT(e, mesh.num_elements()) << what;
    for (int repeat = 0; repeat < 3; ++repeat) EXPECT_EQ(mesh.locate_element(p), e) << what;
    const Eigen::Vector4d lambda = mesh.volume_coordinates(e, p);
    // Round-off of the volume coordinates of a point on a vertex/edge/face: a few ulp of 1.
    EXPECT_GE(lambda.minCoeff(), -1e-12) << what;
    EXPECT_LE(lambda.maxCoeff(), 1.0 + 1e-12) << what;
    EXPECT_NEAR(lambda.sum(), 1.0, 1e-12) << what;
  }
}

TEST(MeshBoundaries, InterpolationAtASharedPointIsTheSameFromEveryElementHoldingIt) {
  // Shows: whichever element the tie rule picks, P1 interpolation there is continuous (conforming mesh), so the choice is harmless.
  const BoxMesh mesh = three_cubed();
  for (const auto& [what, p] : shared_locations(mesh)) {
    const double chosen = interpolate(mesh, mesh.locate_element(p), p);
    int holders = 0;
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      if (mesh.volume_coordinates(e, p).minCoeff() < -1e-12) continue;
      ++holders;
      // Field values are O(10); the P1 sums agree to round-off.
      EXPECT_NEAR(interpolate(mesh, e, p), chosen, 1e-12 * 64.0) << what << ", element " << e;
    }
    EXPECT_GE(holders, 1) << what;
  }
}

TEST(MeshBoundaries, ParticleOnAVertexCountsOnceInPorosityForBothSchemes) {
  // Shows: a grain centred on an interior vertex, face or edge is counted once: sum_e V_e (1 - eps_e) = V_p exactly.
  const BoxMesh mesh = three_cubed();
  const double d = 0.5e-3;
  for (const auto& [what, p] : shared_locations(mesh)) {
    Particles particles;
    particles.add(p.x(), p.y(), p.z(), d, 2650.0);
    ParticleMapping mapping;
    mapping.update(mesh, particles);
    ASSERT_EQ(mapping.outside, 0) << what;
    for (PorosityScheme scheme : {PorosityScheme::centre, PorosityScheme::shape_function}) {
      PorosityField eps(mesh, scheme, 1e-6);  // floor far below: no clamping
      eps.update(particles, mapping);
      double solid = 0.0;
      for (Index e = 0; e < mesh.num_elements(); ++e) solid += mesh.element_volume(e) * (1.0 - eps[e]);
      // Summing 135 element terms of 1e-10 m^3 each: relative round-off ~ 1e-13.
      EXPECT_NEAR(solid, sphere_volume(d), 1e-12 * sphere_volume(d) * 100.0) << what;
    }
  }
}

TEST(MeshBoundaries, ParticleThrownAtAWallIsReflectedAndKept) {
  // Shows: walls on, a grain thrown at 1 m/s into x_max bounces back (vx < 0, |v| <= 1 m/s), stays inside, none removed.
  Scene s = scene_test::dry_box_scene("hard_cases/wall", Vec3::Constant(3 * kCell));
  s.effects.gravity = false;
  s.contact.normal_stiffness = 1e3;
  s.contact.restitution = 0.9;
  s.time.dem_step = 1e-7;
  Particles p;
  p.add(2.5 * kCell, 1.5 * kCell, 1.5 * kCell, 0.5e-3, 2650.0, 1.0, 0.0, 0.0);
  DemEngine dem(p, s);
  dem.run(5000);  // 0.5 ms: reaches the wall after 0.25 mm (0.25 ms), contact 0.1 ms
  const DemDiagnostics d = dem.diagnostics();
  EXPECT_EQ(d.particles_removed, 0u);
  ASSERT_EQ(dem.particles().size(), 1u);
  EXPECT_LT(dem.particles().vx[0], 0.0);
  // Restitution 0.9 of the scene: rebound speed 0.9 m/s (a linear spring-dashpot's exact e);
  // 1 % for the explicit dashpot at dt = t_c / 1000.
  EXPECT_NEAR(-dem.particles().vx[0], 0.9, 0.01);
  EXPECT_LE(dem.particles().x[0], 3 * kCell);
}

TEST(MeshBoundaries, ParticleLeavingAnOpenBoxIsRemovedAndCountedInACoupledRun) {
  // Shows: walls off, a grain leaving through the floor is removed and counted; the others keep ids; the run stays finite.
  Scene s = hard::water_box(3, 3, 3, kCell);
  s.effects.walls = false;
  s.particles.push_back(hard::single_particle(Vec3(1.5 * kCell, 1.5 * kCell, 0.2 * kCell), 0.2e-3, 2650.0,
                                              Vec3(0.0, 0.0, -0.5)));
  ParticleSet stays = hard::single_particle(Vec3(1.5 * kCell, 1.5 * kCell, 2.0 * kCell), 0.2e-3, 2650.0);
  stays.name = "stays";
  s.particles.push_back(stays);
  s.contact = hard::soft_contact();
  s.time.fluid_step = 1e-3;
  s.time.dem_step = 1e-5;
  s.time.subcycles = 100;
  s.time.end_time = 5e-3;
  Simulation sim(s);
  // 0.2 mm down at 0.5 m/s, slowed by drag (response time ~ 3 ms at Re ~ 100): out within 1 ms.
  while (!sim.finished()) sim.step();
  const CouplingDiagnostics d = sim.diagnostics();
  EXPECT_EQ(d.dem.particles_removed, 1u);
  ASSERT_EQ(sim.particles().size(), 1u);
  ASSERT_EQ(sim.particles().id.size(), 1u);
  EXPECT_EQ(sim.particles().id[0], 1) << "the remaining grain keeps its original id";
  EXPECT_EQ(d.particles_outside_mesh, 0) << "a removed grain is not mapped";
  EXPECT_TRUE(d.drag_on_particles.allFinite());
  for (double u : sim.fluid_velocity()) ASSERT_TRUE(std::isfinite(u));
  // The staying grain sinks in still water for 5 ms: at most free fall, 9.81 * 5e-3 m/s.
  EXPECT_LE(std::abs(sim.particles().vz[0]), 9.81 * 5e-3);
}

}  // namespace
}  // namespace fdem::mesh_boundaries_test
