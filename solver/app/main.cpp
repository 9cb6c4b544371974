// fdem command line. Every error is caught here, once, and becomes an exit
// code: 0 ok, 2 bad input (InputError, command-line errors), 3 solver
// failure (SolverError), 130 interrupted (SIGINT/SIGTERM, after the current
// step and its output).
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <thread>

#include "app/check_command.hpp"
#include "app/run_command.hpp"
#include "core/error.hpp"
#include "core/petsc_runtime.hpp"
#include "scene/scene_schema.hpp"

namespace {
constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr int kExitSolverFailure = 3;
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fdem: hybrid FEM-DEM solver for fluid flow laden with many particles\n"
               "(Casagrande et al., Comp. Part. Mech. 2016). Scene file format: `fdem help scene`, examples/README.md.\n"
               "Exit codes: 0 ok, 2 bad input, 3 solver failure, 130 interrupted."};
  app.set_version_flag("--version", std::string("fdem ") + FDEM_VERSION);
  app.require_subcommand(1);

  std::string scene_path;
  auto* check = app.add_subcommand("check", "validate a scene and print the numbers to know before running it");
  check->add_option("SCENE", scene_path, "scene file (YAML)")->required();
  bool check_ignores_memory = false;
  check->add_flag("--ignore-memory-limit", check_ignores_memory,
                  "do not refuse a scene whose memory estimate exceeds the available memory");

  fdem::RunOptions options;
  auto* run = app.add_subcommand("run", "run a scene to its end time, writing VTU/PVD, CSV and checkpoints");
  run->add_option("SCENE", scene_path, "scene file (YAML)")->required();
  run->add_option("--output,-o", options.output_dir, "output folder (default: the scene's output.directory)");
  run->add_option("--threads,-t", options.threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores)")
      ->check(CLI::PositiveNumber);
  run->add_flag("--quiet,-q", options.quiet, "no progress line");
  run->add_option("--restart,-r", options.restart,
                  "resume from a checkpoint.bin of the same scene (write to another --output folder)")
      ->check([](const std::string& path) { return path.empty() ? std::string("an empty path names no checkpoint") : std::string(); });
  run->add_flag("--overwrite", options.overwrite,
                "clear an output folder that holds another scene's (or foreign) files instead of refusing it");
  run->add_flag("--stop-when-empty", options.stop_when_empty,
                "end the run (exit 0) once every particle has left the open domain");
  run->add_flag("--ignore-memory-limit", options.ignore_memory_limit,
                "run even when the memory estimate (fdem check) exceeds the available memory");

  std::string help_topic;
  auto* help = app.add_subcommand("help", "reference: `fdem help scene` prints every scene key, its type, default and meaning");
  help->add_option("TOPIC", help_topic, "scene")->required()->check(CLI::IsMember({"scene"}));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help, version, or the error with usage
    return code == 0 ? kExitOk : kExitBadInput;
  }

  if (help->parsed()) {
    std::fputs(fdem::format_scene_schema().c_str(), stdout);
    return kExitOk;
  }
  // Started by mpirun as one of several ranks: MPI (through PETSc) starts
  // now, so that every rank knows its part before the scene is read.
  if (run->parsed() && fdem::launched_on_several_ranks()) fdem::ensure_petsc_initialized();
  // On several ranks a failure every rank meets alike (bad input, a shared
  // solve that did not converge) is reported once, by rank 0; one that
  // another rank meets alone (its own checkpoint file, its piece of the
  // output) by that rank, after a grace period within which rank 0's abort,
  // when rank 0 failed too, ends it first. Any failure then ends all ranks
  // with its exit code (a rank left waiting in a collective would never return).
  const bool several_ranks = fdem::mpi_ranks() > 1;
  const bool reports = fdem::mpi_rank() == 0;
  const auto fail = [&](int code, const char* kind, const char* what) {
    std::fflush(stdout);
    if (reports) {
      std::fprintf(stderr, "fdem: %s: %s\n", kind, what);
    } else if (several_ranks) {
      std::this_thread::sleep_for(std::chrono::seconds(2));
      std::fprintf(stderr, "fdem (rank %d of %d): %s: %s\n", fdem::mpi_rank(), fdem::mpi_ranks(), kind, what);
    }
    if (several_ranks) fdem::abort_all_ranks(code);
    return code;
  };
  try {
    if (check->parsed()) return fdem::run_check_command(scene_path, stdout, check_ignores_memory);
    if (run->parsed()) return fdem::run_scene_command(scene_path, options);
  } catch (const fdem::InputError& e) {
    return fail(kExitBadInput, "error", e.what());
  } catch (const fdem::SolverError& e) {
    return fail(kExitSolverFailure, "solver failure", e.what());
  } catch (const std::exception& e) {
    return fail(kExitSolverFailure, "solver failure (unexpected)", e.what());
  }
  return kExitOk;
}
