// Checkpoints and failures on 2 MPI ranks, on verification/mpi/wet_slab_drop.yaml
// (384 beads thrown across the slab boundary in water on 320 tetrahedra: the
// fluid's solve shared by the ranks through PETSc). Each rank writes its own
// checkpoint file (checkpoint.bin for rank 0, checkpoint.rank0001.bin beside
// it) recording the rank count; a run on another count refuses them before
// any step, and an error met by one rank alone ends both with its code.
// The grains are decomposed over the ranks, with friction too (the slip
// history travels with them).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "mpi_runs.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;
using hard::read_csv;
using hard::read_text;
using mpi_test::fdem_on;
using mpi_test::occurrences;

// The scene with its end time `end` ("0.02" or "0.04"; the end time is not
// part of a checkpoint's scene fingerprint, so a run may resume past it).
fs::path scene_ending_at(const fs::path& dir, const std::string& end) {
  std::string scene = read_text(fs::path(FDEM_SOURCE_DIR) / "verification/mpi/wet_slab_drop.yaml");
  const auto at = scene.find("end: 0.04");
  if (at == std::string::npos) throw std::runtime_error("wet_slab_drop.yaml's time.end moved");
  scene.replace(at, 9, "end: " + end);
  const fs::path path = dir / ("wet_" + end + ".yaml");
  hard::write_text(path, scene);
  return path;
}

// A 2-rank run to t = 0.02 s: its folder holds both ranks' checkpoints of step 20.
fs::path two_rank_checkpoint(const fs::path& dir) {
  const fs::path out = dir / "first";
  const int code = fdem_on(2, fmt::format("run '{}' -o '{}' -q", scene_ending_at(dir, "0.02").string(), out.string()),
                           dir / "first.log");
  if (code != 0) throw std::runtime_error("the 2-rank run to 0.02 s failed: " + read_text(dir / "first.log"));
  return out;
}

// The rows of a run resumed from the 2-rank checkpoint of step 20 against
// the straight run's: bitwise before row 20 (carried from the first run),
// row 20 (the resumed run's probes of the loaded state, summed over its
// owners) within the rounding of two partial sums, the rest returned as the
// largest difference over each column's largest value.
double resumed_rows_against_straight(const hard::Csv& straight, const hard::Csv& resumed) {
  double worst = 0.0;
  for (std::size_t c = 0; c < straight.columns.size(); ++c) {
    double scale = 0.0;
    for (const auto& row : straight.rows) scale = std::max(scale, std::abs(row[c]));
    for (std::size_t r = 0; r < straight.rows.size(); ++r) {
      const double d = std::abs(resumed.rows[r][c] - straight.rows[r][c]);
      if (r < 20) {
        EXPECT_EQ(d, 0.0) << straight.columns[c] << " at row " << r;
      }
      if (scale > 0.0) worst = std::max(worst, d / scale);
    }
  }
  hard::Csv straight_at = straight, resumed_at = resumed;
  straight_at.rows = {straight.rows[20]};
  resumed_at.rows = {resumed.rows[20]};
  const double grains = straight.rows[20][static_cast<std::size_t>(straight.column("count"))];
  // The box's largest coordinate, 0.04 m (wet_slab_drop.yaml), bounds the positions' terms.
  fmt::print("the checkpoint's row on resuming: sums within {:.3f} of their rounding bound\n",
             mpi_test::expect_probes_within_sum_rounding(straight_at, resumed_at, grains, 0.04));
  return worst;
}

TEST(MpiCheckpoint, WrittenOnTwoRanksResumesOnTwoWithinRounding) {
  const fs::path dir = hard::scratch_dir("mpi_checkpoint_resume");
  const fs::path first = two_rank_checkpoint(dir);
  ASSERT_TRUE(fs::is_regular_file(first / "checkpoint.bin"));
  ASSERT_TRUE(fs::is_regular_file(first / "checkpoint.rank0001.bin"));
  const std::string whole = scene_ending_at(dir, "0.04").string();
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q", whole, (dir / "straight").string()), dir / "straight.log"), 0)
      << read_text(dir / "straight.log");
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q --restart '{}'", whole, (dir / "resumed").string(),
                                   (first / "checkpoint.bin").string()),
                    dir / "resumed.log"),
            0)
      << read_text(dir / "resumed.log");
  const hard::Csv straight = read_csv(dir / "straight/probes.csv"), resumed = read_csv(dir / "resumed/probes.csv");
  ASSERT_TRUE(straight.well_formed && resumed.well_formed);
  ASSERT_EQ(straight.columns, resumed.columns);
  ASSERT_EQ(straight.rows.size(), 41u);  // t = 0 and 40 steps
  // The resumed run carries the first run's rows before its checkpoint and
  // continues. The grains (with their slip history) are decomposed: after
  // the checkpoint the resumed run's owners are those of the loaded
  // positions, which regroups the porosity and source sums in elements
  // touched by both ranks (a few ulp; the frictionless test below says
  // more), so the rows after it agree to the linear tolerance, not bitwise.
  // Row 20, the checkpoint's own time, sums the probes per rank over owners
  // that may differ from the straight run's (the grains migrate at the
  // decomposed run's absolute skin test, several times before 0.02 s): within
  // the rounding of two partial sums, as in the frictionless test below.
  ASSERT_EQ(resumed.rows.size(), straight.rows.size());
  const double worst = resumed_rows_against_straight(straight, resumed);
  fmt::print("frictional coupled run resumed on 2 ranks against straight through: {:.2e} of each column's largest\n",
             worst);
  EXPECT_LE(worst, 1e-8);
  // The snapshot of the end, as pieces, in both.
  EXPECT_EQ(hard::pvd_datasets(dir / "resumed/particles.pvd").back(), "particles_000002.pvtu");
  EXPECT_TRUE(fs::is_regular_file(dir / "resumed/particles_000002_rank0001.vtu"));
}

// The scene without friction and rotation: the checkpoint holds the whole
// set gathered in id order with its mean drag, and a resumed run
// redistributes it by the loaded positions.
TEST(MpiCheckpoint, CoupledDecomposedWrittenOnTwoRanksResumesOnTwoWithinRounding) {
  const fs::path dir = hard::scratch_dir("mpi_checkpoint_decomposed");
  const auto frictionless = [&](const std::string& end) {
    const fs::path path = scene_ending_at(dir, end);
    std::string scene = read_text(path);
    const std::string effects = "tangential_contact: true, rotation: true";
    const auto at = scene.find(effects);
    if (at == std::string::npos) throw std::runtime_error("wet_slab_drop.yaml's effects moved");
    scene.replace(at, effects.size(), "tangential_contact: false, rotation: false");
    const std::string contact = "kt: 50, friction: 0.3";
    const auto law = scene.find(contact);
    if (law == std::string::npos) throw std::runtime_error("wet_slab_drop.yaml's contact moved");
    scene.replace(law, contact.size(), "");
    hard::write_text(path, scene);
    return path.string();
  };
  const std::string first = frictionless("0.02"), whole = frictionless("0.04");
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q", first, (dir / "first").string()), dir / "first.log"), 0)
      << read_text(dir / "first.log");
  // Straight through, writing its checkpoint at 0.02 s as well: a
  // checkpoint is a refactor point of the fluid's preconditioner.
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q", whole, (dir / "straight").string()), dir / "straight.log"), 0)
      << read_text(dir / "straight.log");
  const std::string straight_log = read_text(dir / "straight.log");
  EXPECT_NE(straight_log.find("the grains decomposed in 2 slabs"), std::string::npos) << straight_log;
  ASSERT_EQ(fdem_on(2, fmt::format("run '{}' -o '{}' -q --restart '{}'", whole, (dir / "resumed").string(),
                                   (dir / "first/checkpoint.bin").string()),
                    dir / "resumed.log"),
            0)
      << read_text(dir / "resumed.log");
  const hard::Csv straight = read_csv(dir / "straight/probes.csv"), resumed = read_csv(dir / "resumed/probes.csv");
  ASSERT_TRUE(straight.well_formed && resumed.well_formed);
  ASSERT_EQ(straight.columns, resumed.columns);
  ASSERT_EQ(straight.rows.size(), 41u);  // t = 0 and 40 steps
  ASSERT_EQ(resumed.rows.size(), straight.rows.size());
  // Bitwise up to the checkpoint (the rows are carried); after it, the
  // resumed run's owners are those of the loaded positions, the straight
  // run's those of its last redistribution: a grain that crossed the face
  // in between is summed into the porosity and source term by the other
  // rank, which regroups those sums (a few ulp, simulation_state.cpp). The
  // fluid's solve takes them on, so the runs agree to its linear tolerance
  // 1e-8 (an upper bound: ulp in its data move the converged solution by
  // about that times the condition number, not by the stopping tolerance;
  // measured 3.0e-12 of a column's largest value; 4.9e-15 since the
  // checkpoint holds the writer's slab cut, 3.7e-14 before). Row 20, the
  // checkpoint's own time, is the resumed run's probes of the loaded state:
  // its sums are per rank (its owners), so it matches the straight run's
  // within the rounding of two partial sums (mpi_runs.hpp), not bitwise.
  const double worst = resumed_rows_against_straight(straight, resumed);
  fmt::print("decomposed coupled run resumed on 2 ranks against straight through: {:.2e} of each column's largest\n",
             worst);
  EXPECT_LE(worst, 1e-8);
}

TEST(MpiCheckpoint, WrittenOnTwoRanksIsRefusedOnOneBeforeAnyStep) {
  const fs::path dir = hard::scratch_dir("mpi_checkpoint_refused");
  const fs::path first = two_rank_checkpoint(dir);
  const std::string checkpoint = (first / "checkpoint.bin").string();
  const fs::path out = dir / "one";
  EXPECT_EQ(fdem_on(1, fmt::format("run '{}' -o '{}' -q --restart '{}'", scene_ending_at(dir, "0.04").string(),
                                   out.string(), checkpoint),
                    dir / "one.log"),
            2);  // bad input
  const std::string log = read_text(dir / "one.log");
  EXPECT_NE(log.find(checkpoint), std::string::npos) << log;
  EXPECT_NE(log.find("written by a run on 2 MPI ranks, this run has 1"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out)) << "refused before the output folder is claimed, so before any step";
}

TEST(MpiFailure, AnErrorOnOneRankStopsBothWithItsMessageAndCode) {
  const fs::path dir = hard::scratch_dir("mpi_failure_one_rank");
  const fs::path first = two_rank_checkpoint(dir);
  // Rank 1's file damaged in its state (one byte in the middle): rank 1
  // alone refuses it (checksum), rank 0 reads its own and goes on to wait
  // for rank 1 in the first collective.
  {
    std::fstream f(first / "checkpoint.rank0001.bin", std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(0, std::ios::end);
    const auto middle = static_cast<std::streamoff>(f.tellg()) / 2;
    f.seekg(middle);
    const char c = static_cast<char>(f.get());
    f.seekp(middle);
    f.put(static_cast<char>(c ^ 0x5a));
  }
  const auto started = std::chrono::steady_clock::now();
  const int code = fdem_on(2,
                           fmt::format("run '{}' -o '{}' -q --restart '{}'", scene_ending_at(dir, "0.04").string(),
                                       (dir / "resumed").string(), (first / "checkpoint.bin").string()),
                           dir / "resumed.log");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const std::string log = read_text(dir / "resumed.log");
  EXPECT_EQ(code, 3) << log;  // a solver failure's code, through MPI_Abort and mpirun
  EXPECT_EQ(occurrences(log, fmt::format("fdem (rank 1 of 2): solver failure: {}: checkpoint: the state does not "
                                         "match its checksum",
                                         (first / "checkpoint.rank0001.bin").string())),
            1)
      << log;
  EXPECT_EQ(log.find("fdem run: wall"), std::string::npos) << "no rank finished: " << log;
  fmt::print("one rank's error ended both ranks in {:.1f} s with exit {}\n", seconds, code);
}

TEST(MpiFailure, AnErrorOfEveryRankIsReportedOnceWithItsCode) {
  // A fluid solve that cannot converge (1 iteration to 1e-14): every rank
  // meets it in the shared solve; rank 0 reports it, alone.
  const fs::path dir = hard::scratch_dir("mpi_failure_every_rank");
  std::string scene = read_text(scene_ending_at(dir, "0.04"));
  const std::string fluid = "fluid: {density: 1000, viscosity: 1.0e-3}";
  const auto at = scene.find(fluid);
  ASSERT_NE(at, std::string::npos) << "wet_slab_drop.yaml's fluid moved";
  scene.replace(at, fluid.size(),
                "fluid: {density: 1000, viscosity: 1.0e-3, solver: {max_linear_iterations: 1, linear_tolerance: "
                "1.0e-14}}");
  hard::write_text(dir / "stuck.yaml", scene);
  const int code =
      fdem_on(2, fmt::format("run '{}' -o '{}' -q", (dir / "stuck.yaml").string(), (dir / "out").string()),
              dir / "stuck.log");
  const std::string log = read_text(dir / "stuck.log");
  EXPECT_EQ(code, 3) << log;
  EXPECT_EQ(occurrences(log, "fdem: solver failure: fluid step"), 1) << log;
  EXPECT_NE(log.find("did not converge in 1 iterations"), std::string::npos) << log;
  EXPECT_EQ(log.find("(rank 1 of 2)"), std::string::npos) << "reported once, by rank 0: " << log;
}

}  // namespace
}  // namespace fdem
