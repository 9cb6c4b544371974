// Crash safety of `fdem run`: SIGINT or SIGTERM finish the current step, write
// every output for it and exit 130, leaving a valid checkpoint and output
// complete up to that step; SIGKILL (no chance to clean up) still leaves only
// complete files. The checkpoint the interrupted command wrote, loaded and run
// on, gives the uninterrupted run's result bit for bit (same thread count).
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <omp.h>
#include <signal.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "coupling/simulation.hpp"
#include "restart_scene.hpp"
#include "scene/scene_loader.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;

// A long run (100 s of 1 ms steps) writing VTU, CSV (and checkpoints) every step, so it is
// always mid-run when the signal comes.
fs::path write_scene(const fs::path& dir, bool checkpoints) {
  const std::string extra = std::string(", vtu_interval: 1.0e-3, csv_interval: 1.0e-3") +
                            (checkpoints ? ", checkpoint_interval: 1.0e-3" : "");
  const fs::path path = dir / "scene.yaml";
  hard::write_text(path, restart::coupled_scene_yaml(extra, 100.0));
  return path;
}

// Starts `fdem run` and waits until it has written the VTU of step 3.
struct Started {
  fs::path dir, out;
  std::unique_ptr<hard::FdemProcess> run;
};
Started start_run(const std::string& name, bool checkpoints) {
  Started s;
  s.dir = hard::scratch_dir(name);
  s.out = s.dir / "out";
  const fs::path scene = write_scene(s.dir, checkpoints);
  s.run = std::make_unique<hard::FdemProcess>(
      std::vector<std::string>{"run", scene.string(), "-o", s.out.string(), "-q", "-t", "1"}, s.dir);
  const bool progressed =
      hard::wait_for([&] { return fs::exists(s.out / "particles_000003.vtu") || !s.run->running(); }, 60.0);
  EXPECT_TRUE(progressed) << "the run did not reach step 3 within 60 s";
  return s;
}

// Every series on disk is complete and consistent; returns the last CSV time.
double expect_valid_output(const fs::path& out, bool forced_final_row) {
  const hard::Csv csv = hard::read_csv(out / "probes.csv");
  EXPECT_TRUE(csv.well_formed) << "probes.csv has a torn or malformed row";
  EXPECT_GE(csv.rows.size(), 1u);
  double previous = -1.0;
  for (const auto& row : csv.rows) {
    for (double v : row) EXPECT_TRUE(std::isfinite(v));
    EXPECT_GT(row[0], previous) << "times increase";
    previous = row[0];
  }
  for (const char* series : {"particles.pvd", "fluid.pvd"}) {
    const fs::path pvd = out / series;
    EXPECT_TRUE(fs::exists(pvd)) << series;
    if (!fs::exists(pvd)) continue;
    const std::vector<std::string> files = hard::pvd_datasets(pvd);
    EXPECT_GE(files.size(), 1u) << series;
    for (const auto& f : files) EXPECT_TRUE(hard::vtk_file_complete(out / f)) << series << " names " << f;
  }
  if (forced_final_row) {
    // The last VTU written is the state of the last CSV row: both stop at the same step.
    const std::string pvd = hard::read_text(out / "particles.pvd");
    const std::size_t at = pvd.rfind("timestep=\"");
    EXPECT_NE(at, std::string::npos);
    if (at != std::string::npos) {
      EXPECT_DOUBLE_EQ(std::stod(pvd.substr(at + 10)), previous);
    }
  }
  return previous;
}

void expect_clean_stop(int sig, const std::string& name) {
  Started s = start_run(name, false);
  ASSERT_TRUE(s.run->running()) << s.run->stderr_text();
  s.run->signal(sig);
  const bool ended = hard::wait_for([&] { return !s.run->running(); }, 30.0);
  ASSERT_TRUE(ended) << "fdem run must stop after the current step";
  EXPECT_EQ(s.run->wait(), 130) << s.run->stderr_text();
  EXPECT_NE(s.run->stderr_text().find(fmt::format("stopped by signal {}", sig)), std::string::npos)
      << s.run->stderr_text();
  const double last = expect_valid_output(s.out, true);
  EXPECT_GE(last, 3e-3 * (1 - 1e-12)) << "output reaches at least the step seen before the signal";
  for (const auto& entry : fs::directory_iterator(s.out))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
        << "a clean stop leaves no temporary: " << entry.path();
}

TEST(Interrupt, SigintFinishesTheStepWritesOutputAndExits130) {
  // Shows: SIGINT mid-run -> exit 130, CSV rows whole and finite, every VTU named by the PVDs complete, no temporaries.
  expect_clean_stop(SIGINT, "interrupt_sigint");
}

TEST(Interrupt, SigtermFinishesTheStepWritesOutputAndExits130) {
  // Shows: the same for SIGTERM (a batch system's stop).
  expect_clean_stop(SIGTERM, "interrupt_sigterm");
}

TEST(Interrupt, SigkillLeavesOnlyCompleteFiles) {
  // Shows: SIGKILL (no handler runs) still leaves a well-formed CSV and only complete VTU files in the PVDs.
  Started s = start_run("interrupt_sigkill", false);
  ASSERT_TRUE(s.run->running()) << s.run->stderr_text();
  s.run->signal(SIGKILL);
  EXPECT_EQ(s.run->wait(), 128 + SIGKILL);
  expect_valid_output(s.out, false);
}

TEST(Interrupt, CheckpointLeftBySigintRestartsToTheUninterruptedResultBitwise) {
  // Shows: SIGINT leaves checkpoint.bin at the last CSV time; loaded and run to step 20 it equals the uninterrupted run bitwise.
  Started s = start_run("interrupt_checkpoint", true);
  ASSERT_TRUE(s.run->running()) << s.run->stderr_text();
  s.run->signal(SIGINT);
  ASSERT_EQ(s.run->wait(), 130) << s.run->stderr_text();
  const double last = expect_valid_output(s.out, true);
  ASSERT_TRUE(fs::exists(s.out / "checkpoint.bin"));

  const Scene scene = load_scene((s.dir / "scene.yaml").string());
  omp_set_num_threads(1);  // the thread count of the `fdem run -t 1` that wrote the checkpoint
  // Both runs write a checkpoint after every step, as the command does with
  // checkpoint_interval = one step (a checkpoint is the fluid's ILUT refactor point).
  std::ostringstream discard(std::ios::binary);
  Simulation resumed(scene);
  std::ifstream in(s.out / "checkpoint.bin", std::ios::binary);
  resumed.load_checkpoint(in);
  EXPECT_DOUBLE_EQ(resumed.time(), last) << "the checkpoint is the state of the last output";
  const long target_step = std::max(20L, resumed.step_index() + 3);
  while (resumed.step_index() < target_step) {
    resumed.step();
    resumed.save_checkpoint(discard);
  }

  Simulation uninterrupted(scene);
  uninterrupted.save_checkpoint(discard);  // the command writes one at t = 0 too
  while (uninterrupted.step_index() < target_step) {
    uninterrupted.step();
    uninterrupted.save_checkpoint(discard);
  }
  ASSERT_EQ(resumed.particles().size(), uninterrupted.particles().size());
  for (std::size_t i = 0; i < uninterrupted.particles().size(); ++i) {
    EXPECT_EQ(resumed.particles().x[i], uninterrupted.particles().x[i]) << "particle " << i;
    EXPECT_EQ(resumed.particles().vz[i], uninterrupted.particles().vz[i]) << "particle " << i;
  }
  const auto u = uninterrupted.fluid_velocity(), v = resumed.fluid_velocity();
  ASSERT_EQ(u.size(), v.size());
  EXPECT_EQ(std::memcmp(u.data(), v.data(), u.size_bytes()), 0) << "fluid velocity bitwise";
}

}  // namespace
}  // namespace fdem
