#pragma once
// Runs `fdem` on one process or under mpirun for the 2-rank tests; test code only.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <fmt/format.h>

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

}  // namespace fdem::mpi_test
