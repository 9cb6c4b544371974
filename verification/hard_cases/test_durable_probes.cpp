// probes.csv is appended row by row: a run killed with -9 keeps every row up
// to its last snapshot, a full disk (a file-size limit here) keeps every row
// that fitted, whole, and a run resumed from a checkpoint carries the rows
// before it into its new folder.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>

#include <cmath>
#include <string>

#include "run_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

using hard::FdemProcess;
namespace fs = std::filesystem;

// Time of the last snapshot a .pvd names.
double last_snapshot_time(const fs::path& pvd) {
  const std::string text = hard::read_text(pvd);
  const std::size_t at = text.rfind("timestep=\"");
  return at == std::string::npos ? -1.0 : std::stod(text.substr(at + 10));
}

TEST(DurableProbes, KillNineKeepsEveryRowUpToTheLastSnapshot) {
  // Before: the CSV was rewritten every 10 s of wall time, so kill -9 left only the t = 0 row.
  const fs::path dir = hard::scratch_dir("probes_kill9");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(100.0, ", vtu_interval: 2.0e-4, csv_interval: 1.0e-4"));
  const fs::path out = dir / "out";
  FdemProcess run({"run", (dir / "scene.yaml").string(), "-o", out.string(), "-q", "-t", "1"}, dir);
  ASSERT_TRUE(hard::wait_for([&] { return fs::exists(out / "particles_000008.vtu") || !run.running(); }, 60.0));
  ASSERT_TRUE(run.running()) << run.stderr_text();
  run.signal(SIGKILL);
  EXPECT_EQ(run.wait(), 128 + SIGKILL);
  const double snapshot = last_snapshot_time(out / "particles.pvd");
  ASSERT_GE(snapshot, 1.4e-3);
  const hard::Csv csv = hard::read_csv(out / "probes.csv");
  EXPECT_TRUE(csv.well_formed);
  ASSERT_FALSE(csv.rows.empty());
  // The rows of every 1e-4 s up to the last snapshot (CSV cadence is twice the VTU's).
  EXPECT_GE(csv.rows.back().front(), snapshot - 1e-12);
  EXPECT_GE(csv.rows.size(), static_cast<std::size_t>(snapshot / 1e-4 + 0.5) + 1);
}

TEST(DurableProbes, FullDiskKeepsEveryRowThatFittedAndEndsOnAWholeRow) {
  // Before: the rows were held in memory and written whole at the end, which failed: only the t = 0 row remained.
  const fs::path dir = hard::scratch_dir("probes_full_disk");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(0.05, ", vtu_interval: 0.01, csv_interval: 1.0e-5"));
  constexpr rlim_t limit = 48 * 1024;  // above a 27-grain snapshot (about 10 KiB), below 5000 probe rows
  const int code = hard::run_fdem_limited(
      {"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q", "-t", "1"}, dir, RLIMIT_FSIZE, limit);
  const std::string err = hard::read_text(dir / "stderr.txt");
  EXPECT_EQ(code, 3) << err;
  EXPECT_NE(err.find("probes.csv"), std::string::npos) << err;
  const fs::path csv_path = dir / "out" / "probes.csv";
  const std::string text = hard::read_text(csv_path);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "the file ends with a whole row";
  const hard::Csv csv = hard::read_csv(csv_path);
  EXPECT_TRUE(csv.well_formed);
  // Filled to within one row of the limit: every row that fitted is there.
  const std::size_t row_bytes = text.size() / (csv.rows.size() + 1);
  EXPECT_GT(text.size() + 2 * row_bytes, limit) << csv.rows.size() << " rows, " << text.size() << " bytes";
  for (const auto& f : hard::pvd_datasets(dir / "out" / "particles.pvd"))
    EXPECT_TRUE(hard::vtk_file_complete(dir / "out" / f)) << f;
}

TEST(DurableProbes, RunResumedAfterKillNineCarriesTheRowsBeforeItsCheckpoint) {
  const fs::path dir = hard::scratch_dir("probes_resume");
  hard::write_text(dir / "scene.yaml",
                   hard::dry_drop_yaml(100.0, ", vtu_interval: 1.0e-3, csv_interval: 1.0e-4, checkpoint_interval: 5.0e-4"));
  const fs::path out = dir / "out";
  {
    FdemProcess run({"run", (dir / "scene.yaml").string(), "-o", out.string(), "-q", "-t", "1"}, dir);
    ASSERT_TRUE(hard::wait_for([&] { return fs::exists(out / "particles_000002.vtu") || !run.running(); }, 60.0));
    ASSERT_TRUE(run.running()) << run.stderr_text();
    run.signal(SIGKILL);
    run.wait();
  }
  const hard::Csv killed = hard::read_csv(out / "probes.csv");
  ASSERT_FALSE(killed.rows.empty());
  // Resume to 1 ms after the killed run's last row, so past its last checkpoint however late the kill landed
  // (a fixed 3 ms end failed on a fast host: the kill came after the 3.5 ms checkpoint). Same scene but for its end.
  const double resume_end = std::round((killed.rows.back().front() + 1.0e-3) / 1.0e-4) * 1.0e-4;
  hard::write_text(dir / "resume.yaml",
                   hard::dry_drop_yaml(resume_end, ", vtu_interval: 1.0e-3, csv_interval: 1.0e-4, checkpoint_interval: 5.0e-4"));
  FdemProcess resumed({"run", (dir / "resume.yaml").string(), "--restart", (out / "checkpoint.bin").string(), "-o",
                       (dir / "resumed").string(), "-q", "-t", "1"},
                      dir);
  ASSERT_EQ(resumed.wait(), 0) << resumed.stderr_text();
  const hard::Csv carried = hard::read_csv(dir / "resumed" / "probes.csv");
  ASSERT_TRUE(carried.well_formed);
  ASSERT_FALSE(carried.rows.empty());
  EXPECT_EQ(carried.rows.front().front(), 0.0) << "the rows start at t = 0, not at the checkpoint";
  // Every row before the checkpoint's step is the killed run's, value for value.
  const int step = carried.column("step");
  std::size_t compared = 0;
  for (std::size_t r = 0; r < carried.rows.size() && r < killed.rows.size(); ++r) {
    if (carried.rows[r][static_cast<std::size_t>(step)] >= killed.rows.back()[static_cast<std::size_t>(step)]) break;
    EXPECT_EQ(carried.rows[r], killed.rows[r]) << "row " << r;
    ++compared;
  }
  EXPECT_GE(compared, 10u) << "the checkpoint at 1e-3 s or later holds 10 rows of 1e-4 s before it";
  EXPECT_NEAR(carried.rows.back().front(), resume_end, 1e-9) << "the resumed run reaches its own end";
}

}  // namespace
}  // namespace fdem
