#pragma once
// Runs `fdem` on one process or under mpirun for the 2-rank tests, and
// compares their probes; test code only.
#include <sys/wait.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "test_support.hpp"

namespace fdem::mpi_test {

namespace fs = std::filesystem;

/// The shell's exit code of one command, its stdout and stderr to `log`.
inline int shell(const std::string& command, const fs::path& log) {
  const int status = std::system(fmt::format("{} > '{}' 2>&1", command, log.string()).c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// `fdem ARGS` on `ranks` MPI ranks (1: one process, no mpirun), one
/// OpenMP thread each; returns the exit code, the output in `log`.
inline int fdem_on(int ranks, const std::string& args, const fs::path& log) {
  if (ranks == 1) return shell(fmt::format("OMP_NUM_THREADS=1 '{}' {}", FDEM_EXE, args), log);
  // As root in CI, on fewer cores than ranks: --allow-run-as-root --oversubscribe.
  return shell(fmt::format("OMP_NUM_THREADS=1 '{}' --allow-run-as-root --oversubscribe -n {} '{}' {}", FDEM_MPIEXEC,
                           ranks, FDEM_EXE, args),
               log);
}

/// The number of times `needle` occurs in `text`.
inline int occurrences(const std::string& text, const std::string& needle) {
  int n = 0;
  for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

/// Probe rows of a run on several ranks (`two`) against one process's
/// (`one`). Decomposed, each rank sums its own grains' probes and the ranks
/// add the sums (app/run_command.cpp, own_probe_sums), so a mean of n terms
/// summed in parts differs from the one sum by at most 2 (n - 1) eps
/// max|x_i| (Higham 2002, eq. 4.4): max|x_i| is `coordinate_bound` [m] (the
/// box's largest coordinate) for positions and the row's max_speed for
/// velocities; the kinetic energy (positive terms) by 2 (n - 1) eps of
/// itself. Every other column (time, counts, extrema, the diagnostics'
/// counts and maxima) bit for bit. Returns the largest difference over its
/// bound among the sums (0: the same bits).
inline double expect_probes_within_sum_rounding(const hard::Csv& one, const hard::Csv& two, double grains,
                                                double coordinate_bound) {
  EXPECT_EQ(one.columns, two.columns);
  EXPECT_EQ(one.rows.size(), two.rows.size());
  if (one.columns != two.columns || one.rows.size() != two.rows.size()) return 1e300;
  const double bound = 2.0 * (grains - 1.0) * DBL_EPSILON;
  const int speed = one.column("max_speed");
  double worst = 0.0;
  for (std::size_t r = 0; r < one.rows.size(); ++r)
    for (std::size_t c = 0; c < one.columns.size(); ++c) {
      const std::string& name = one.columns[c];
      const double a = one.rows[r][c], b = two.rows[r][c], d = std::abs(b - a);
      double allowed = -1.0;
      if (name.starts_with("mean_v") && speed >= 0) allowed = bound * one.rows[r][static_cast<std::size_t>(speed)];
      else if (name == "mean_x" || name == "mean_y" || name == "mean_z") allowed = bound * coordinate_bound;
      else if (name == "kinetic_energy") allowed = bound * a;
      if (allowed < 0.0) {
        EXPECT_EQ(b, a) << name << " at row " << r;
        continue;
      }
      EXPECT_LE(d, allowed) << name << " at row " << r;
      if (d > 0.0) worst = std::max(worst, d / allowed);
    }
  return worst;
}

}  // namespace fdem::mpi_test
