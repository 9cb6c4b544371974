// `fdem run` names the real cause and leaves something to resume from: an
// empty --restart and garbage after a checkpoint's trailer are refused, a
// signal during set-up or with no checkpoint interval ends cleanly (exit 130,
// a checkpoint when there is a state), grains leaving an open domain are
// counted and reported (and --stop-when-empty ends the run when all are gone),
// a non-finite particle CSV value is refused naming file, line and column.
#include <gtest/gtest.h>

#include <signal.h>

#include <fstream>
#include <string>

#include "run_scenes.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

using hard::FdemProcess;
namespace fs = std::filesystem;

using hard::run_fdem;

TEST(RunDiagnostics, EmptyRestartPathIsRefusedInsteadOfStartingAtTimeZero) {
  const fs::path dir = hard::scratch_dir("diag_empty_restart");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(0.001));
  std::string err;
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "--restart", "", "-o", (dir / "out").string(), "-q"}, dir,
                     &err),
            2);
  EXPECT_NE(err.find("--restart"), std::string::npos) << err;
  EXPECT_NE(err.find("empty"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "out" / "probes.csv"));
}

TEST(RunDiagnostics, GarbageAfterTheCheckpointTrailerIsRefusedBeforeAnyStep) {
  const fs::path dir = hard::scratch_dir("diag_trailer_garbage");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(0.001, ", checkpoint_interval: 0.001"));
  std::string err;
  ASSERT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-o", (dir / "first").string(), "-q"}, dir, &err), 0)
      << err;
  std::ofstream(dir / "first" / "checkpoint.bin", std::ios::binary | std::ios::app) << "garbage";  // 7 bytes
  EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "--restart", (dir / "first" / "checkpoint.bin").string(),
                      "-o", (dir / "second").string(), "-q"},
                     dir, &err),
            3);
  EXPECT_NE(err.find("7 bytes after the end marker"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "second" / "probes.csv")) << "refused before the first step";
}

TEST(RunDiagnostics, SigtermWithNoCheckpointIntervalLeavesACheckpointThatResumes) {
  const fs::path dir = hard::scratch_dir("diag_final_checkpoint");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(100.0, ", vtu_interval: 1.0e-4"));  // no checkpoint_interval
  const fs::path out = dir / "out";
  FdemProcess run({"run", (dir / "scene.yaml").string(), "-o", out.string(), "-q", "-t", "1"}, dir);
  ASSERT_TRUE(hard::wait_for([&] { return fs::exists(out / "particles_000003.vtu") || !run.running(); }, 60.0));
  ASSERT_TRUE(run.running()) << run.stderr_text();
  run.signal(SIGTERM);
  EXPECT_EQ(run.wait(), 130) << run.stderr_text();
  EXPECT_NE(run.stderr_text().find("--restart"), std::string::npos) << "says how to resume: " << run.stderr_text();
  ASSERT_TRUE(fs::exists(out / "checkpoint.bin")) << "an interrupted run leaves a state to resume from";
  hard::write_text(dir / "resume.yaml", hard::dry_drop_yaml(0.01, ", vtu_interval: 1.0e-4"));
  std::string err;
  EXPECT_EQ(run_fdem({"run", (dir / "resume.yaml").string(), "--restart", (out / "checkpoint.bin").string(), "-o",
                      (dir / "resumed").string(), "-q"},
                     dir, &err),
            0)
      << err;
  EXPECT_NE(err.find("resumed from"), std::string::npos) << err;
}

TEST(RunDiagnostics, SignalDuringSetUpEndsWithExitCode130AndAMessage) {
  // A fluid mesh of 40^3 cells (320k tetrahedra) takes about a second to set
  // up; the signal comes once the output folder is claimed, i.e. during set-up.
  // (Still water without inlet: were the signal late, no step would solve.)
  const fs::path dir = hard::scratch_dir("diag_setup_signal");
  hard::write_text(dir / "scene.yaml", hard::still_water_yaml("[0.04, 0.04, 0.04]", "[40, 40, 40]", 100.0));
  const fs::path out = dir / "out";
  FdemProcess run({"run", (dir / "scene.yaml").string(), "-o", out.string(), "-q", "-t", "1"}, dir);
  ASSERT_TRUE(hard::wait_for([&] { return fs::exists(out / "run_manifest.json") || !run.running(); }, 60.0));
  run.signal(SIGTERM);
  const int code = run.wait();
  const std::string err = run.stderr_text();
  EXPECT_EQ(code, 130) << "not killed by the signal (143): " << err;
  EXPECT_NE(err.find("signal"), std::string::npos) << err;
}

TEST(RunDiagnostics, GrainsLeavingAnOpenDomainAreReportedAndStopWhenEmptyEndsTheRun) {
  // Walls off: the 27 beads fall through the floor under gravity within about 0.05 s.
  const fs::path dir = hard::scratch_dir("diag_open_domain");
  hard::write_text(dir / "scene.yaml", hard::dry_drop_yaml(1.0, ", csv_interval: 1.0e-3", "open drop", false));
  std::string err;
  ASSERT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q", "--stop-when-empty"},
                     dir, &err),
            0)
      << err;
  EXPECT_NE(err.find("27 of 27 particles left the open domain"), std::string::npos) << err;
  EXPECT_NE(err.find("--stop-when-empty"), std::string::npos) << err;
  const hard::Csv csv = hard::read_csv(dir / "out" / "probes.csv");
  ASSERT_TRUE(csv.well_formed);
  ASSERT_FALSE(csv.rows.empty());
  // Free fall from z >= 4 mm: all are out after sqrt(2 (0.010 + 0.0015) / g) = 0.048 s at the latest.
  EXPECT_LT(csv.rows.back().front(), 0.06) << "the run stopped when the last grain left, not at t = 1 s";
  EXPECT_EQ(csv.rows.back()[static_cast<std::size_t>(csv.column("count"))], 0.0);
  EXPECT_EQ(csv.rows.back()[static_cast<std::size_t>(csv.column("particles_removed"))], 27.0);
}

TEST(RunDiagnostics, NonFiniteParticleCsvValueIsRefusedNamingFileLineAndColumn) {
  const fs::path dir = hard::scratch_dir("diag_csv_nan");
  for (const std::string bad : {"nan", "NaN", "inf", "-inf", "1e999"}) {
    hard::write_text(dir / "grains.csv", "id,d,rho,x,y,z\n0,1e-3,2500,0.005,0.005,0.005\n1,1e-3,2500," + bad +
                                             ",0.005,0.007\n");
    hard::write_text(dir / "scene.yaml",
                     "effects: {fluid: false, gravity: true, normal_contact: true, walls: true}\n"
                     "domain: {lower: [0, 0, 0], upper: [0.01, 0.01, 0.01]}\n"
                     "particles:\n  - {name: read, placement: csv, file: grains.csv}\n"
                     "contact: {kn: 100, restitution: 0.5}\n"
                     "time: {dem_step: 1.0e-5, end: 0.001}\n"
                     "output: {directory: out}\n");
    std::string err;
    EXPECT_EQ(run_fdem({"run", (dir / "scene.yaml").string(), "-o", (dir / "out").string(), "-q"}, dir, &err), 2)
        << bad << ": " << err;
    EXPECT_NE(err.find("grains.csv:3"), std::string::npos) << bad << ": " << err;
    EXPECT_NE(err.find("column 4"), std::string::npos) << bad << ": " << err;
    EXPECT_NE(err.find("'x'"), std::string::npos) << bad << ": " << err;
    EXPECT_NE(err.find("finite"), std::string::npos) << bad << ": " << err;
  }
}

}  // namespace
}  // namespace fdem
