// The coupled step's sort point (simulation.cpp, step 3): the DEM puts its
// grains in cell order (DemEngine::sort_in_cell_order) after the subcycles,
// the mean drag moves with its grains, and the mapping, porosity and source
// term are then built in the new order. A run that sorts after every fluid
// step matches one that never sorts, grain by grain (by id), up to the
// rounding of sums taken in another order; and a checkpoint written right
// after a sort restarts bit for bit (its porosity, rebuilt on load from the
// saved order, is the saved one).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "coupling/simulation.hpp"
#include "coupling/tests/checkpoint_in_memory.hpp"
#include "coupling/tests/simulation_state_comparison.hpp"
#include "scene/tests/uniform_lattice_of_grains.hpp"

namespace fdem {
namespace {

using checkpoint_test::checkpoint_bytes;
using checkpoint_test::expect_bitwise_same_state;
using checkpoint_test::load_checkpoint_bytes;

// Two-way coupled: 3 x 3 x 4 cells of 1.5 mm, water driven in through x_min
// and out at x_max, 8 x 8 x 4 = 256 grains of 0.50-0.56 mm on a 0.56 mm
// lattice settling in it: grain contacts, walls, drag, a source term.
Scene coupled_cloud() {
  Scene s;
  s.source_file = "test_grain_sort_point";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(4.5e-3, 4.5e-3, 6e-3);
  s.cells = {3, 3, 4};
  s.effects.coupling = CouplingMode::two_way;
  s.contact.normal_stiffness = 50.0;
  s.contact.restitution = 0.5;
  s.fluid.faces[0].condition = FaceCondition::inlet;
  s.fluid.faces[0].velocity = Vec3(0.02, 0.0, 0.0);
  s.fluid.faces[1].condition = FaceCondition::outlet;
  s.particles.push_back(scene_test::uniform_lattice_of_grains(
      "grains", {Vec3(0.0, 0.0, 1e-3), Vec3(4.5e-3, 4.5e-3, 3.24e-3)}, {8, 8, 4}, {0.50e-3, 0.56e-3}, 2650.0,
      Vec3(0.01, 0.0, -0.02), 5));
  s.time.fluid_step = 1e-3;
  s.time.dem_step = 1e-5;
  s.time.end_time = 1.0;
  s.coupling.source_form = SourceForm::conservative;
  return s;
}

// Sorted after every fluid step (100 DEM steps), whatever the grain count.
Simulation sorting_run(const Scene& scene) {
  Simulation sim(scene);
  sim.set_grain_sort_policy({.interval = 100, .min_particles = 1});
  return sim;
}

std::vector<double> by_id(const Particles& p, std::span<const double> v) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[static_cast<std::size_t>(p.id[i])] = v[i];
  return out;
}

double relative_difference(std::span<const double> a, std::span<const double> b) {
  return checkpoint_test::relative_difference(a, b);
}

TEST(GrainSortPoint, SortedCoupledRunMatchesTheUnsortedOneGrainByGrain) {
  const Scene scene = coupled_cloud();
  Simulation sorted = sorting_run(scene);
  Simulation plain(scene);
  plain.set_grain_sort_policy({.interval = 0});
  constexpr int kSteps = 8;
  for (int k = 0; k < kSteps; ++k) {
    sorted.step();
    plain.step();
  }
  const Particles &p = sorted.particles(), &q = plain.particles();
  ASSERT_EQ(p.size(), q.size());
  EXPECT_GE(sorted.diagnostics().dem.grain_sorts, 1u);
  EXPECT_EQ(plain.diagnostics().dem.grain_sorts, 0u);
  EXPECT_NE(p.id, q.id) << "the sorted run's grains are in another order";
  ASSERT_GT(sorted.diagnostics().dem.contacts + sorted.diagnostics().dem.wall_contacts, 0u);
  ASSERT_GT(sorted.diagnostics().drag_on_particles.norm(), 0.0);
  // Differences: sums over grains (porosity, source term) and a grain's
  // contact sum in another order, i.e. rounding, carried through the
  // fluid's iterative solve, whose tolerance (relative residual 1e-10,
  // solution error up to ~1e-6 relative, test_checkpoint.cpp) bounds what
  // the fluid passes on. A grain whose mean drag stayed in the old order
  // would put drag into other elements: an O(1) relative difference in the
  // source term. Measured (relative): x 1.9e-14, vz 1.8e-13, porosity
  // 1.1e-16, source term 4.0e-14, fluid velocity 9.6e-16.
  const double dx = relative_difference(by_id(p, p.x), by_id(q, q.x));
  const double dvz = relative_difference(by_id(p, p.vz), by_id(q, q.vz));
  const double porosity = relative_difference(sorted.porosity(), plain.porosity());
  const double source = relative_difference(sorted.source_term(), plain.source_term());
  const double fluid = relative_difference(sorted.fluid_velocity(), plain.fluid_velocity());
  std::printf("sorted - unsorted (relative): x %.3g, vz %.3g, porosity %.3g, source %.3g, fluid %.3g\n", dx, dvz,
              porosity, source, fluid);
  EXPECT_LT(porosity, 1e-14);
  EXPECT_LT(fluid, 1e-6);
  EXPECT_LT(source, 1e-6);
  EXPECT_LT(dvz, 1e-6);
  EXPECT_LT(dx, 1e-9);
}

TEST(GrainSortPoint, CheckpointWrittenRightAfterASortRestartsBitwise) {
  const Scene scene = coupled_cloud();
  Simulation writer = sorting_run(scene);
  constexpr int kSteps = 6;
  std::string bytes;
  for (int k = 0; k < kSteps; ++k) {
    const std::size_t sorts = writer.diagnostics().dem.grain_sorts;
    writer.step();
    if (bytes.empty() && writer.diagnostics().dem.grain_sorts > sorts) bytes = checkpoint_bytes(writer);
  }
  ASSERT_FALSE(bytes.empty()) << "no step reordered the grains";
  Simulation resumed = sorting_run(scene);
  load_checkpoint_bytes(resumed, bytes);
  while (resumed.step_index() < kSteps) resumed.step();
  expect_bitwise_same_state(writer, resumed);
}

}  // namespace
}  // namespace fdem
