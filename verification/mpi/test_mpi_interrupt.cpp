// Ctrl-C through mpirun: SIGINT to `mpirun -n 2 fdem run` stops both ranks
// cleanly. Open MPI's mpirun (4.1) does not forward SIGINT; it ends the job,
// sending each rank SIGTERM (then SIGKILL after odls_base_sigkill_timeout,
// 1 s by default). fdem's stop path takes SIGTERM like SIGINT
// (app/run_command.cpp, StopOnSignal): the ranks agree on the step to stop
// after (a collective), write its outputs (every file atomically) and the
// checkpoints of that step, and rank 0 reports once. The run here is long
// (5 s of 1 ms steps), so the signal always comes mid-run.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "mpi_runs.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;
using hard::read_text;
using mpi_test::fdem_on;
using mpi_test::occurrences;
using mpi_test::shell;

TEST(MpiInterrupt, SigintToMpirunStopsBothRanksWithCompleteOutputAndAResumableCheckpoint) {
  const fs::path dir = hard::scratch_dir("mpi_interrupt");
  std::string scene = read_text(fs::path(FDEM_SOURCE_DIR) / "verification/mpi/wet_slab_drop.yaml");
  const auto end = scene.find("end: 0.04");
  ASSERT_NE(end, std::string::npos) << "wet_slab_drop.yaml's time.end moved";
  scene.replace(end, 9, "end: 5.0");
  hard::write_text(dir / "long.yaml", scene);
  const fs::path out = dir / "out";
  // mpirun in the background; once the first snapshot (t = 0.01 s) is on
  // disk, SIGINT to mpirun alone (as a terminal's Ctrl-C would reach it), then its exit code.
  const std::string script = fmt::format(
      "OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n 2 '{}' run '{}' -o '{}' -q > '{}' 2>&1 & "
      "job=$!; for i in $(seq 1 1200); do [ -e '{}' ] && break; sleep 0.1; done; kill -INT $job; wait $job; "
      "echo \"mpirun exit $?\"",
      FDEM_MPIEXEC, FDEM_EXE, (dir / "long.yaml").string(), out.string(), (dir / "run.log").string(),
      (out / "particles_000001.pvtu").string());
  shell(script, dir / "script.log");
  const std::string log = read_text(dir / "run.log");
  // Both ranks stopped by the signal mpirun sent them, after the same step, reported once by rank 0.
  EXPECT_EQ(occurrences(log, "fdem run: stopped by signal 15 at t = "), 1) << log;
  EXPECT_EQ(occurrences(log, "fdem run: wall"), 1) << log;
  const hard::Csv probes = hard::read_csv(out / "probes.csv");
  ASSERT_TRUE(probes.well_formed) << "a torn row";
  ASSERT_GE(probes.rows.size(), 11u) << "the signal came after t = 0.01 s";
  const long last_step = std::lround(probes.rows.back()[static_cast<std::size_t>(probes.column("step"))]);
  EXPECT_NE(log.find(fmt::format("(step {})", last_step)), std::string::npos) << "the rows reach the stop step\n" << log;
  // Both ranks' checkpoints, of that step: a 2-rank run resumes from them
  // (it refuses files of different steps) and runs 3 more steps.
  ASSERT_TRUE(fs::is_regular_file(out / "checkpoint.bin"));
  ASSERT_TRUE(fs::is_regular_file(out / "checkpoint.rank0001.bin"));
  std::string resumed_scene = scene;
  resumed_scene.replace(end, 8, fmt::format("end: {:.3f}", 1e-3 * static_cast<double>(last_step + 3)));
  hard::write_text(dir / "more.yaml", resumed_scene);
  ASSERT_EQ(fdem_on(2,
                    fmt::format("run '{}' -o '{}' -q --restart '{}'", (dir / "more.yaml").string(),
                                (dir / "resumed").string(), (out / "checkpoint.bin").string()),
                    dir / "resumed.log"),
            0)
      << read_text(dir / "resumed.log");
  const hard::Csv resumed = hard::read_csv(dir / "resumed/probes.csv");
  ASSERT_TRUE(resumed.well_formed);
  EXPECT_EQ(resumed.rows.size(), probes.rows.size() + 3) << read_text(dir / "resumed.log");
}

}  // namespace
}  // namespace fdem
