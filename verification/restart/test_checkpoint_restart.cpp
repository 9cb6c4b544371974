// Crash safety: a run checkpointed and restarted gives the same result as the
// uninterrupted run, bit for bit at the same thread count
// (Simulation::save_checkpoint / load_checkpoint), and a checkpoint that does
// not fit the scene, or is cut short, is refused with a clear error.
#include <gtest/gtest.h>

#include <string>

#include "coupling/simulation.hpp"
#include "coupling/tests/checkpoint_in_memory.hpp"
#include "coupling/tests/simulation_state_comparison.hpp"
#include "restart_scene.hpp"
#include "scene/scene_loader.hpp"

namespace fdem {
namespace {

using checkpoint_test::checkpoint_bytes;
using checkpoint_test::expect_bitwise_same_state;
using checkpoint_test::load_checkpoint_bytes;
using checkpoint_test::relative_difference;
using checkpoint_test::restarted_run;
using checkpoint_test::resumed_from;
using checkpoint_test::straight_run;

Scene coupled_scene() { return load_scene_from_string(restart::coupled_scene_yaml(), "restart.yaml"); }

TEST(CheckpointRestart, TwoRunsOfTheSceneAreBitwiseIdentical) {
  // Shows: the precondition of a bitwise restart: the same scene, same thread count, run twice, gives the same bits.
  const Scene scene = coupled_scene();
  Simulation a(scene), b(scene);
  for (int k = 0; k < 12; ++k) {
    a.step();
    b.step();
  }
  expect_bitwise_same_state(a, b);
}

// Note on the fluid: its ILUT preconditioner is reused across steps and refactored only
// when a solve gets slow; writing or reading a checkpoint makes the next step refactor
// (fluid/fluid_solver.hpp). So the run a restart reproduces bit for bit is the
// uninterrupted run that wrote the same checkpoint (what `fdem run` with
// output.checkpoint_interval does); a run that never wrote one agrees to the linear
// solver's tolerance (next test).
TEST(CheckpointRestart, CoupledRunRestartedHalfwayEqualsTheUninterruptedRunBitwise) {
  // Shows: a run that checkpoints at step 6 and goes on to 12 == a fresh Simulation loading that checkpoint and stepping to 12 (bitwise).
  const Scene scene = coupled_scene();
  Simulation uninterrupted(scene);
  for (int k = 0; k < 6; ++k) uninterrupted.step();
  EXPECT_GT(uninterrupted.diagnostics().dem.contacts, 0u) << "grain-grain contacts (slip history) live at the checkpoint";
  const std::string checkpoint = checkpoint_bytes(uninterrupted);
  for (int k = 0; k < 6; ++k) uninterrupted.step();

  Simulation resumed = resumed_from(scene, checkpoint);
  EXPECT_EQ(resumed.step_index(), 6);
  for (int k = 0; k < 6; ++k) resumed.step();
  expect_bitwise_same_state(uninterrupted, resumed);
}

TEST(CheckpointRestart, RestartAgreesWithARunThatNeverCheckpointedToTheLinearTolerance) {
  // Shows: against a run that wrote no checkpoint (other ILUT refactor points) the restart differs by < 1e-5 relative.
  const Scene scene = coupled_scene();
  const Simulation never_saved = straight_run(scene, 12);
  const Simulation resumed = restarted_run(scene, 6, 6);
  // Each step stops its Picard iteration at a relative update of 1e-8 and each linear solve
  // at a residual of 1e-10, here with other preconditioners than the never-saved run's; the
  // pressure (a Lagrange multiplier) amplifies that most. Measured after 6 steps: 5.5e-9 and,
  // after a fluid-solver revision, 6.5e-7 (pressure), 1.5e-7 (particles). 1e-5 keeps room for
  // solver revisions; a restart that dropped state (BDF2 history, slip, F^n) differs at first
  // order in the step, orders of magnitude above it.
  const Particles &p = never_saved.particles(), &q = resumed.particles();
  ASSERT_EQ(p.size(), q.size());
  for (auto field : {&Particles::x, &Particles::y, &Particles::z, &Particles::vx, &Particles::vy, &Particles::vz,
                     &Particles::wx, &Particles::wy, &Particles::wz})
    EXPECT_LT(relative_difference(p.*field, q.*field), 1e-5);
  EXPECT_LT(relative_difference(never_saved.fluid_velocity(), resumed.fluid_velocity()), 1e-5);
  EXPECT_LT(relative_difference(never_saved.fluid_pressure(), resumed.fluid_pressure()), 1e-5);
}

TEST(CheckpointRestart, DryDemRunWithSlipHistoryRestartsBitwise) {
  // Shows: a dry bed with tangential contact and rotation, restarted after 300 of 600 DEM steps, equals the straight run.
  std::string yaml = restart::coupled_scene_yaml();
  yaml.replace(yaml.find("fluid: true, coupling: two_way"), std::string("fluid: true, coupling: two_way").size(),
               "fluid: false, coupling: off, buoyancy: false");
  Scene scene = load_scene_from_string(yaml, "restart_dry.yaml");
  scene.time.fluid_step = 0.0;  // one DEM step per Simulation::step
  expect_bitwise_same_state(straight_run(scene, 600), restarted_run(scene, 300, 300));
}

TEST(CheckpointRestart, SaveLoadSaveGivesTheSameBytes) {
  // Shows: a checkpoint read back and written again is byte-identical (nothing lost or re-derived differently).
  const auto [first, rewritten] = checkpoint_test::checkpoint_read_back_and_rewritten(coupled_scene(), 3);
  EXPECT_EQ(rewritten, first);
}

TEST(CheckpointRestart, CheckpointOfAnotherSceneOrCutShortIsRefused) {
  // Shows: loading a checkpoint from a scene with other particles, or a truncated one, throws (no silent garbage).
  const Scene scene = coupled_scene();
  Simulation sim(scene);
  sim.step();
  const std::string bytes = checkpoint_bytes(sim);
  ASSERT_GT(bytes.size(), 100u);

  std::string other_yaml = restart::coupled_scene_yaml();
  other_yaml.replace(other_yaml.find("lattice: [4, 4, 3]"), std::string("lattice: [4, 4, 3]").size(),
                     "lattice: [4, 4, 2]");
  Simulation other(load_scene_from_string(other_yaml, "other.yaml"));
  EXPECT_ANY_THROW(load_checkpoint_bytes(other, bytes)) << "32 grains cannot take a 48-grain checkpoint";

  Simulation target(scene);
  EXPECT_ANY_THROW(load_checkpoint_bytes(target, bytes.substr(0, bytes.size() / 2)))
      << "a checkpoint cut in half must be refused";
}

}  // namespace
}  // namespace fdem
