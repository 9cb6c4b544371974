// `mpirun -n 2 fdem run SCENE` against `fdem run SCENE`: the study's settling
// scene (verification/settling/settling.yaml, 12100 tetrahedra) for its first
// 0.5 s (50 fluid steps: the grain's acceleration to its terminal velocity,
// where drag and the fluid's answer to it change fastest, and its fall from
// rank 1's slab through the face at z = 0.04 m into rank 0's at ~0.33 s: a
// lone grain has no relative displacement, so only the decomposed run's
// absolute skin test migrates it, dem_engine.cpp).
//
// On 2 ranks the fluid's linear solve is shared (PETSc, each rank a block of
// rows) and the grain is owned by the rank of its slab (the other holds
// none: its partial sums of porosity and source term are zeros, so the
// fields summed over the ranks are one process's bit for bit); on one
// process the scene's own solver (its fluid.solver: PETSc FGMRES, Schur
// fieldsplit, SOR velocity, LU pressure) runs with one block, on 2 ranks the
// same options make SOR local to each rank's rows (the pressure LU is each
// rank's whole copy, PCREDUNDANT). The two are
// different preconditioners stopped at the same relative residual
// (fluid.linear_tolerance) of the same equilibrated system, so they agree to
// that tolerance and not bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <string>

#include "mpi_runs.hpp"
#include "test_support.hpp"

namespace fdem {
namespace {

namespace fs = std::filesystem;
using hard::Csv;
using hard::read_csv;
using hard::read_text;

using mpi_test::shell;

TEST(MpiSettling, TwoRanksGiveOneProcessAnswerWithinTheLinearTolerance) {
  const fs::path dir = hard::scratch_dir("mpi_settling");
  std::string scene = read_text(fs::path(FDEM_SOURCE_DIR) / "verification/settling/settling.yaml");
  const auto end = scene.find("  end: 1.0");
  ASSERT_NE(end, std::string::npos) << "settling.yaml's time.end moved";
  scene.replace(end, 10, "  end: 0.5");
  hard::write_text(dir / "settling.yaml", scene);

  const std::string fdem = FDEM_EXE, yaml = (dir / "settling.yaml").string();
  ASSERT_EQ(shell(fmt::format("'{}' run '{}' -o '{}' -q -t 1", fdem, yaml, (dir / "one").string()), dir / "one.log"), 0)
      << read_text(dir / "one.log");
  // OMP_NUM_THREADS=1: one core per rank.
  ASSERT_EQ(shell(fmt::format("OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n 2 '{}' run '{}' -o '{}' -q",
                              FDEM_MPIEXEC, fdem, yaml, (dir / "two").string()),
                  dir / "two.log"),
            0)
      << read_text(dir / "two.log");
  const std::string two_log = read_text(dir / "two.log");
  EXPECT_NE(two_log.find("2 MPI ranks"), std::string::npos) << two_log;
  EXPECT_NE(two_log.find("the grains decomposed in 2 slabs"), std::string::npos) << two_log;
  // Rank 0 alone reports: the start line once.
  const std::string start_line = "fdem run: " + yaml + ": 1 particles";
  const auto first = two_log.find(start_line);
  ASSERT_NE(first, std::string::npos) << two_log;
  EXPECT_EQ(two_log.find(start_line, first + 1), std::string::npos) << two_log;
  // The grain crossed the face and changed owner (before the absolute skin
  // test it stayed rank 1's, and the coupling's sums refused it far below
  // its slab).
  EXPECT_NE(two_log.find("1 grains migrated"), std::string::npos) << two_log;
  EXPECT_NE(two_log.find("grains per rank at the end 1, 0"), std::string::npos) << two_log;

  const Csv one = read_csv(dir / "one/probes.csv"), two = read_csv(dir / "two/probes.csv");
  ASSERT_TRUE(one.well_formed && two.well_formed);
  ASSERT_EQ(one.columns, two.columns);
  ASSERT_EQ(one.rows.size(), 51u);  // t = 0 and 50 steps
  ASSERT_EQ(two.rows.size(), one.rows.size());
  const int vx = one.column("mean_vx"), vy = one.column("mean_vy"), vz = one.column("mean_vz"),
            z = one.column("mean_z");
  ASSERT_GE(std::min({vx, vy, vz, z}), 0);
  double speed_max = 0.0, worst_velocity = 0.0, worst_z = 0.0;
  for (const auto& row : one.rows) speed_max = std::max(speed_max, std::hypot(row[vx], row[vy], row[vz]));
  ASSERT_GT(speed_max, 0.01) << "the grain settles (terminal ~0.1 m/s)";
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    const auto &a = one.rows[i], &b = two.rows[i];
    worst_velocity = std::max(worst_velocity, std::hypot(b[vx] - a[vx], b[vy] - a[vy], b[vz] - a[vz]) / speed_max);
    worst_z = std::max(worst_z, std::abs(b[z] - a[z]) / std::abs(a[z]));
  }
  fmt::print("2 ranks against 1: grain velocity {:.2e} of its largest speed, height {:.2e} relative\n",
             worst_velocity, worst_z);
  // The linear tolerance 1e-8: each step's fluid solution differs by about
  // that much relative between the two solvers, and the grain's velocity
  // follows the fluid's through the drag (measured 4.0e-12, height 8.3e-13 to
  // 0.2 s; the whole 1 s run 3.6e-10 and 1.9e-13 m: both solvers reach well
  // below the tolerance).
  EXPECT_LE(worst_velocity, 1e-8);
  EXPECT_LE(worst_z, 1e-8);
  EXPECT_LT(one.rows.back()[z], 0.04) << "the grain reached rank 0's slab";
}


// fluid.scheme: projection solves on one rank only (fluid/projection_scheme.hpp):
// under mpirun the run stops before its first step, naming the key.
TEST(MpiSettling, ProjectionSchemeOnTwoRanksIsRefusedBeforeTheFirstStep) {
  const fs::path dir = hard::scratch_dir("mpi_settling_projection");
  std::string scene = read_text(fs::path(FDEM_SOURCE_DIR) / "verification/settling/settling.yaml");
  const auto solver = scene.find("  solver: {linear_solver: petsc,");
  const auto solver_end = scene.find("}\n", solver);
  ASSERT_TRUE(solver != std::string::npos && solver_end != std::string::npos) << "settling.yaml's solver block moved";
  scene.replace(solver, solver_end + 2 - solver, "  scheme: projection\n");
  hard::write_text(dir / "settling.yaml", scene);
  const std::string fdem = FDEM_EXE, yaml = (dir / "settling.yaml").string();
  const int code = shell(fmt::format("OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n 2 '{}' run '{}' -o '{}' -q",
                                     FDEM_MPIEXEC, fdem, yaml, (dir / "two").string()),
                         dir / "two.log");
  const std::string log = read_text(dir / "two.log");
  EXPECT_NE(code, 0) << log;
  EXPECT_NE(log.find("fluid.scheme: projection runs on one MPI rank only"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "two/probes.csv")) << "a refused run wrote probes";
}

}  // namespace
}  // namespace fdem
