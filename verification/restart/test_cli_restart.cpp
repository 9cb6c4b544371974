// `fdem run --restart CHECKPOINT`: a run stopped halfway and resumed from its
// checkpoint ends in the same state, bit for bit, as the straight run.
#include <gtest/gtest.h>

#include <string>

#include "run_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

// The dry drop of examples/dry_drop.yaml (27 beads, walls, contacts) in steps
// of 100 DEM steps, with checkpoints; `end` is the only difference between the
// half and the whole run (the checkpoint's scene check leaves end time and
// output settings out).
std::string dry_drop(double end) {
  return hard::dry_drop_yaml(end, ", vtu_interval: 0.01, csv_interval: 0.001, checkpoint_interval: 0.01",
                             "dry drop for restart", true, 100);
}

std::string last_particles_vtu(const hard::fs::path& dir) {
  const auto files = hard::pvd_datasets(dir / "particles.pvd");
  if (files.empty()) return {};
  return hard::read_text(dir / files.back());
}

TEST(CliRestart, ResumedRunEndsBitwiseEqualToTheStraightRun) {
  // Shows: stop at 0.02 s, resume with --restart to 0.05 s: the last particle
  // snapshot (shortest round-trip decimal of every double) and the probes
  // (rows before the checkpoint carried over) equal the straight run's.
  const auto dir = hard::scratch_dir("cli_restart");
  hard::write_text(dir / "whole.yaml", dry_drop(0.05));
  hard::write_text(dir / "half.yaml", dry_drop(0.02));
  const std::vector<std::string> common{"-q", "-t", "1"};
  auto run = [&](std::vector<std::string> args) {
    args.insert(args.end(), common.begin(), common.end());
    hard::FdemProcess p(args, dir);
    const int code = p.wait();
    EXPECT_EQ(code, 0) << p.stderr_text();
    return code;
  };
  ASSERT_EQ(run({"run", (dir / "whole.yaml").string(), "-o", (dir / "straight").string()}), 0);
  ASSERT_EQ(run({"run", (dir / "half.yaml").string(), "-o", (dir / "half").string()}), 0);
  ASSERT_TRUE(hard::fs::exists(dir / "half" / "checkpoint.bin"));
  ASSERT_EQ(run({"run", (dir / "whole.yaml").string(), "--restart", (dir / "half" / "checkpoint.bin").string(), "-o",
                 (dir / "resumed").string()}),
            0);
  const std::string straight = last_particles_vtu(dir / "straight");
  const std::string resumed = last_particles_vtu(dir / "resumed");
  ASSERT_FALSE(straight.empty());
  EXPECT_EQ(resumed, straight) << "the resumed run's final state differs from the straight run's";
  // The resumed probes carry the half run's rows before the checkpoint and
  // continue from it: the whole file equals the straight run's, byte for byte.
  const hard::Csv csv = hard::read_csv(dir / "resumed" / "probes.csv");
  ASSERT_TRUE(csv.well_formed);
  ASSERT_GE(csv.rows.size(), 1u);
  EXPECT_EQ(csv.rows.front().front(), 0.0);
  EXPECT_EQ(hard::read_text(dir / "resumed" / "probes.csv"), hard::read_text(dir / "straight" / "probes.csv"));
}

TEST(CliRestart, ResumingIntoTheCheckpointsOwnFolderIsRefused) {
  // Shows: resuming would renumber and overwrite the earlier snapshots, so it is bad input (exit 2).
  const auto dir = hard::scratch_dir("cli_restart_refused");
  hard::write_text(dir / "half.yaml", dry_drop(0.02));
  {
    hard::FdemProcess p({"run", (dir / "half.yaml").string(), "-o", (dir / "half").string(), "-q", "-t", "1"}, dir);
    ASSERT_EQ(p.wait(), 0) << p.stderr_text();
  }
  hard::FdemProcess p({"run", (dir / "half.yaml").string(), "--restart", (dir / "half" / "checkpoint.bin").string(),
                       "-o", (dir / "half").string(), "-q"},
                      dir);
  EXPECT_EQ(p.wait(), 2);
  EXPECT_NE(p.stderr_text().find("--output"), std::string::npos) << p.stderr_text();
}

}  // namespace
}  // namespace fdem
