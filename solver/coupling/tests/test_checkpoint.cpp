// Checkpoint and restart (crash safety): a run saved at step N/2 and
// loaded into a fresh Simulation of the same scene continues exactly as the
// run that wrote the checkpoint, bit for bit (same thread count); a
// checkpoint of another scene, cut short or corrupt, is refused with a clear
// error and leaves the loading run untouched. Small scenes: each test runs
// in well under a second.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "coupling/checkpoint_format.hpp"
#include "coupling/simulation.hpp"
#include "coupling/tests/checkpoint_in_memory.hpp"
#include "coupling/tests/simulation_state_comparison.hpp"
#include "fluid/fluid_solver.hpp"
#include "mesh/box_mesh.hpp"
#include "scene/tests/dry_box_scene.hpp"
#include "scene/tests/uniform_lattice_of_grains.hpp"

namespace fdem {
namespace {

using checkpoint_test::bitwise_equal;
using checkpoint_test::checkpoint_bytes;
using checkpoint_test::expect_bitwise_same_state;
using checkpoint_test::load_checkpoint_bytes;
using scene_test::uniform_lattice_of_grains;

double max_speed(std::span<const double> u) {  // largest velocity component [m/s]
  double m = 0.0;
  for (double c : u) m = std::max(m, std::abs(c));
  return m;
}

// The grains of both scenes slide and roll, so a checkpoint must carry slip
// history and spins: tangential contact and rotation on, with a soft
// frictional spring that keeps contacts alive (contact time ~1.3e-4 s for the
// dry bed's 0.5 mm grains: 13 DEM steps of 1e-5 s).
void let_grains_slide_and_roll(Scene& s) {
  s.effects.tangential_contact = true;
  s.effects.rotation = true;
  s.contact.normal_stiffness = 50.0;
  s.contact.restitution = 0.5;
  s.contact.tangential_stiffness = 20.0;
  s.contact.friction = 0.4;
}

// A dry bed: 7 x 7 x 6 = 294 grains of 0.46-0.52 mm on a 0.5 mm lattice, so
// some neighbours overlap from the start, thrown sideways and falling onto
// the floor of a 3.5 mm box: 115-280 sliding, rolling contacts with slip
// history over the run (measured), and walls.
Scene dry_bed() {
  Scene s = scene_test::dry_box_scene("test_checkpoint_dry", Vec3(3.5e-3, 3.5e-3, 3.5e-3));
  let_grains_slide_and_roll(s);
  s.particles.push_back(uniform_lattice_of_grains("bed", {Vec3::Zero(), Vec3(3.5e-3, 3.5e-3, 3.0e-3)}, {7, 7, 6},
                                                  {0.46e-3, 0.52e-3}, 2650.0, Vec3(0.02, -0.01, -0.03), 7));
  s.time.dem_step = 1e-5;
  s.time.end_time = 1.0;
  return s;
}

// Two-way coupled: 3 x 3 x 3 cells of 1.5 mm (135 tetrahedra), water driven
// in through x_min above mid-height and out at x_max, over a bed of 6 x 6 x 2
// = 72 grains of 0.70-0.78 mm on a 0.75 mm lattice filling the floor: 20-50
// grain contacts and 15-40 wall contacts in every step (measured), with slip
// history; BDF2, tangential contact and rotation.
Scene coupled_box() {
  Scene s;
  s.source_file = "test_checkpoint_coupled";
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(4.5e-3, 4.5e-3, 4.5e-3);
  s.cells = {3, 3, 3};
  s.effects.coupling = CouplingMode::two_way;
  let_grains_slide_and_roll(s);
  s.fluid.faces[0].condition = FaceCondition::inlet;
  s.fluid.faces[0].velocity = Vec3(0.02, 0.0, 0.0);
  s.fluid.faces[0].inlet_above_m = 2.0e-3;
  s.fluid.faces[1].condition = FaceCondition::outlet;
  s.fluid.time_scheme = TimeScheme::bdf2;
  s.particles.push_back(uniform_lattice_of_grains("grains", {Vec3::Zero(), Vec3(4.5e-3, 4.5e-3, 1.5e-3)}, {6, 6, 2},
                                                  {0.70e-3, 0.78e-3}, 2650.0, Vec3(0.01, 0.0, -0.02), 3));
  s.time.fluid_step = 1e-3;
  s.time.dem_step = 1e-5;
  s.time.end_time = 1.0;
  s.coupling.source_form = SourceForm::conservative;
  return s;
}

TEST(Checkpoint, DryBedWithSlipHistoryRestartedHalfwayEqualsTheStraightRunBitwise) {
  const Scene scene = dry_bed();
  constexpr int kSteps = 1000;
  Simulation straight(scene);
  for (int k = 0; k < kSteps; ++k) straight.step();

  Simulation first_half(scene);
  for (int k = 0; k < kSteps / 2; ++k) first_half.step();
  // The restart must carry live contacts (slip history) and has to rebuild
  // the neighbour list at a time the straight run did not.
  ASSERT_GT(first_half.diagnostics().dem.contacts, 100u);
  const std::string bytes = checkpoint_bytes(first_half);

  Simulation resumed(scene);
  load_checkpoint_bytes(resumed, bytes);
  EXPECT_EQ(resumed.step_index(), kSteps / 2);
  for (int k = 0; k < kSteps / 2; ++k) resumed.step();
  ASSERT_GT(straight.diagnostics().dem.contacts, 100u);
  EXPECT_NE(straight.diagnostics().dem.neighbour_rebuilds, resumed.diagnostics().dem.neighbour_rebuilds)
      << "the resumed run's lists must have been built at other times for the test to show list independence";
  expect_bitwise_same_state(straight, resumed);
}

TEST(Checkpoint, CoupledRunRestartedHalfwayEqualsTheRunThatWroteTheCheckpointBitwise) {
  const Scene scene = coupled_box();
  constexpr int kSteps = 10;
  Simulation writer(scene);  // writes a checkpoint halfway and goes on
  Simulation straight(scene);  // never writes one
  std::string bytes;
  for (int k = 0; k < kSteps; ++k) {
    if (k == kSteps / 2) {
      ASSERT_GT(writer.diagnostics().drag_on_particles.norm(), 0.0);
      ASSERT_GT(writer.diagnostics().dem.contacts, 10u) << "live grain contacts (slip history) at the checkpoint";
      bytes = checkpoint_bytes(writer);
    }
    writer.step();
    straight.step();
  }
  Simulation resumed(scene);
  load_checkpoint_bytes(resumed, bytes);
  EXPECT_EQ(resumed.step_index(), kSteps / 2);
  for (int k = 0; k < kSteps / 2; ++k) resumed.step();
  ASSERT_GT(max_speed(writer.fluid_velocity()), 0.01);  // the inflow moves the fluid (0.02 m/s)
  expect_bitwise_same_state(writer, resumed);

  // Against the run that wrote no checkpoint, the one difference is the ILUT
  // preconditioner refactored at the checkpoint: equal to what the linear
  // solver tolerance allows (relative residual 1e-10 of the equilibrated
  // system; times a condition number up to ~1e4, a solution error up to
  // 1e-6 relative). Measured 1.0e-11 m/s (Release) and 7.2e-10 m/s
  // (RelWithDebInfo + ASan) after 5 steps; bound 1e-6 of the 0.02 m/s inflow.
  const auto u = straight.fluid_velocity(), v = resumed.fluid_velocity();
  ASSERT_EQ(u.size(), v.size());
  double diff = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) diff = std::max(diff, std::abs(u[i] - v[i]));
  EXPECT_LT(diff, 1e-6 * 0.02);
}

TEST(Checkpoint, RestartDuringAndAfterTheFreezeWithPicardAndShapeFunctionPorosityIsBitwise) {
  // Other branches of the state: particles frozen (no source term) until
  // 3 ms, Picard iterations (several solves per step), the smoother porosity
  // and the paper's source form. Checkpoints while frozen and after.
  Scene scene = coupled_box();
  scene.coupling.freeze_until = 3e-3;
  scene.fluid.linearization = FluidLinearization::picard;
  scene.coupling.porosity = PorosityScheme::shape_function;
  scene.coupling.source_form = SourceForm::paper;
  constexpr int kSteps = 8;
  Simulation writer(scene);
  std::string frozen_bytes, moving_bytes;
  for (int k = 0; k < kSteps; ++k) {
    if (k == 2) frozen_bytes = checkpoint_bytes(writer);
    if (k == 5) moving_bytes = checkpoint_bytes(writer);
    writer.step();
  }
  ASSERT_GT(max_speed(writer.source_term()), 0.0) << "the source term must be on after the freeze";
  for (const auto& [bytes, from] : {std::pair{frozen_bytes, 2}, std::pair{moving_bytes, 5}}) {
    Simulation resumed(scene);
    load_checkpoint_bytes(resumed, bytes);
    EXPECT_EQ(resumed.step_index(), from);
    while (resumed.step_index() < kSteps) {
      // A checkpoint is a refactor point of the fluid's preconditioner: the
      // resumed run writes the checkpoints the writer wrote after its start.
      if (resumed.step_index() == 5 && from < 5) (void)checkpoint_bytes(resumed);
      resumed.step();
    }
    SCOPED_TRACE(from);
    expect_bitwise_same_state(writer, resumed);
  }
}

TEST(Checkpoint, DryRunLosingParticlesThroughAnOpenFloorRestartsBitwiseWithIdsAndCounts) {
  // Without walls, grains falling through the floor are removed and counted
  // (DemDiagnostics::particles_removed); the checkpoint lands between losses.
  Scene scene = dry_bed();
  scene.effects.walls = false;
  scene.domain.lower.z() = 1.2e-3;  // the two lowest layers start below the floor and go at the first step
  scene.particles[0].velocity = Vec3(0.0, 0.0, -0.3);
  constexpr int kSteps = 600;
  Simulation straight(scene);
  Simulation first_half(scene);
  for (int k = 0; k < kSteps; ++k) straight.step();
  for (int k = 0; k < kSteps / 2; ++k) first_half.step();
  const std::size_t removed_at_checkpoint = first_half.diagnostics().dem.particles_removed;
  ASSERT_GT(removed_at_checkpoint, 0u);
  ASSERT_GT(straight.diagnostics().dem.particles_removed, removed_at_checkpoint) << "losses after the restart too";
  Simulation resumed(scene);
  load_checkpoint_bytes(resumed, checkpoint_bytes(first_half));
  EXPECT_EQ(resumed.diagnostics().dem.particles_removed, removed_at_checkpoint);
  for (int k = 0; k < kSteps / 2; ++k) resumed.step();
  EXPECT_EQ(resumed.diagnostics().dem.particles_removed, straight.diagnostics().dem.particles_removed);
  expect_bitwise_same_state(straight, resumed);
}

TEST(Checkpoint, CheckpointReadBackAndWrittenAgainIsByteIdentical) {
  const auto [first, rewritten] = checkpoint_test::checkpoint_read_back_and_rewritten(coupled_box(), 4);
  EXPECT_EQ(rewritten, first);
}

TEST(Checkpoint, CheckpointOfAnotherSceneIsRefusedNamingWhatDiffers) {
  Simulation sim(coupled_box());
  sim.step();
  const std::string bytes = checkpoint_bytes(sim);

  Scene stiffer = coupled_box();
  stiffer.contact.normal_stiffness = 60.0;
  Simulation other(stiffer);
  try {
    load_checkpoint_bytes(other, bytes);
    FAIL() << "a checkpoint of another scene was accepted";
  } catch (const SolverError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("another scene"), std::string::npos) << what;
    EXPECT_NE(what.find("contact.kn"), std::string::npos) << what;
  }
  EXPECT_EQ(other.step_index(), 0);

  Scene reseeded = coupled_box();
  reseeded.particles[0].seed = 4;  // same counts, other diameters
  Simulation third(reseeded);
  EXPECT_THROW(load_checkpoint_bytes(third, bytes), SolverError);

  Simulation dry(dry_bed());
  EXPECT_THROW(load_checkpoint_bytes(dry, bytes), SolverError);
}

TEST(Checkpoint, TruncatedOrCorruptCheckpointIsRefusedAndLeavesTheRunUntouched) {
  const Scene scene = coupled_box();
  Simulation sim(scene);
  for (int k = 0; k < 3; ++k) sim.step();
  const std::string bytes = checkpoint_bytes(sim);
  ASSERT_GT(bytes.size(), 1000u);

  Simulation target(scene);
  target.step();
  const GrainArray x_before = target.particles().x;
  // Cut in the magic, the header, the payload, and just before the end marker.
  for (const std::size_t keep : {std::size_t{0}, std::size_t{5}, std::size_t{40}, bytes.size() / 2,
                                 bytes.size() - 9, bytes.size() - 1}) {
    try {
      load_checkpoint_bytes(target, bytes.substr(0, keep));
      FAIL() << "a checkpoint cut to " << keep << " of " << bytes.size() << " bytes was accepted";
    } catch (const SolverError& e) {
      const std::string what = e.what();
      const bool clear = what.find("truncated") != std::string::npos || what.find("cut short") != std::string::npos ||
                         what.find("not an fdem checkpoint") != std::string::npos;
      EXPECT_TRUE(clear) << "cut to " << keep << ": " << what;
    }
  }
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  EXPECT_THROW(load_checkpoint_bytes(target, flipped), SolverError) << "one flipped bit in the state";
  EXPECT_THROW(load_checkpoint_bytes(target, "not a checkpoint at all"), SolverError);

  // Nothing of the refused files reached the run: it goes on as one never asked to load.
  EXPECT_EQ(target.step_index(), 1);
  EXPECT_TRUE(bitwise_equal(target.particles().x, x_before));
  Simulation reference(scene);
  reference.step();
  target.step();
  reference.step();
  expect_bitwise_same_state(reference, target);
}

// Header offsets of format version 2 (checkpoint_format.hpp): magic 0-7,
// version 8-11, byte-order mark 12-15, ranks 16-19, rank 20-23.
constexpr std::size_t kVersionAt = 8, kRanksAt = 16, kRankLayoutBytes = 8;

std::string with_u32_at(std::string bytes, std::size_t at, std::uint32_t value) {
  bytes.replace(at, sizeof value, reinterpret_cast<const char*>(&value), sizeof value);
  return bytes;
}

TEST(Checkpoint, RecordsTheRankCountAndRefusesAnotherOne) {
  Simulation sim(dry_bed());
  sim.step();
  const std::string bytes = checkpoint_bytes(sim);
  std::istringstream in(bytes, std::ios::in | std::ios::binary);
  const checkpoint::RankLayout layout = checkpoint::read_rank_layout(in);
  EXPECT_EQ(layout.ranks, 1u);  // one process
  EXPECT_EQ(layout.rank, 0u);

  Simulation other(dry_bed());
  try {
    load_checkpoint_bytes(other, with_u32_at(bytes, kRanksAt, 2));
    FAIL() << "a checkpoint of 2 ranks was loaded by one process";
  } catch (const SolverError& e) {
    EXPECT_NE(std::string(e.what()).find("written by rank 0 of 2 MPI ranks, read by rank 0 of 1"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(other.step_index(), 0);
  EXPECT_THROW(load_checkpoint_bytes(other, with_u32_at(bytes, kRanksAt, 0)), SolverError) << "no ranks at all";
}

TEST(Checkpoint, VersionOneFileWithoutARankLayoutResumesAsOneProcess) {
  Simulation sim(dry_bed());
  for (int k = 0; k < 3; ++k) sim.step();
  // Version 1 was version 2 without the rank layout.
  std::string v1 = with_u32_at(checkpoint_bytes(sim), kVersionAt, 1);
  v1.erase(kRanksAt, kRankLayoutBytes);
  Simulation resumed(dry_bed());
  load_checkpoint_bytes(resumed, v1);
  EXPECT_EQ(resumed.step_index(), 3);
  sim.step();
  resumed.step();
  expect_bitwise_same_state(sim, resumed);
  EXPECT_THROW(load_checkpoint_bytes(resumed, with_u32_at(checkpoint_bytes(sim), kVersionAt, 3)), SolverError)
      << "a newer version";
}

TEST(Checkpoint, EachRanksFileLiesBesideRankZerosNamedByItsRank) {
  EXPECT_EQ(checkpoint::rank_file_path("out/checkpoint.bin", 0), "out/checkpoint.bin");
  EXPECT_EQ(checkpoint::rank_file_path("out/checkpoint.bin", 1), "out/checkpoint.rank0001.bin");
  EXPECT_EQ(checkpoint::rank_file_path("state", 12), "state.rank0012");
}

TEST(Checkpoint, FluidSaveStateMakesTheNextStepRefactorThePreconditioner) {
  Scene s = coupled_box();
  s.particles.clear();
  BoxMesh mesh(s.domain.lower, s.domain.upper, s.cells);
  FluidSolver fluid(mesh, s);
  for (int k = 0; k < 3; ++k) fluid.step(1e-3);
  ASSERT_EQ(fluid.step(1e-3).preconditioner_factorizations, 0) << "the ILUT factors are reused between steps";
  std::ostringstream out(std::ios::out | std::ios::binary);
  fluid.save_state(out);
  EXPECT_GE(fluid.step(1e-3).preconditioner_factorizations, 1) << "a checkpoint is a refactor point";

  FluidSolver loaded(mesh, s);
  std::istringstream in(out.str(), std::ios::in | std::ios::binary);
  loaded.load_state(in);
  EXPECT_EQ(loaded.step_count(), 4);
  EXPECT_GE(loaded.step(1e-3).preconditioner_factorizations, 1);
  EXPECT_TRUE(bitwise_equal(loaded.velocity(), fluid.velocity()));
  EXPECT_TRUE(bitwise_equal(loaded.pressure(), fluid.pressure()));
}

}  // namespace
}  // namespace fdem
