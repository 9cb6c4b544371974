#include "core/petsc_runtime.hpp"

#include <petscsys.h>

#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "core/error.hpp"

namespace fdem {

namespace {

// Open MPI keeps (and never frees) allocations of MPI_Init and of its
// dlopen'ed components, which it unloads before exit: LeakSanitizer would
// report them with stacks it cannot symbolise, so no suppression file can
// name them. Allocations made while LSan is disabled are not leak-checked;
// only the library's start and end are excluded, fdem's own code stays checked.
struct LeakCheckPause {
#if defined(__SANITIZE_ADDRESS__)
  LeakCheckPause() { __lsan_disable(); }
  ~LeakCheckPause() { __lsan_enable(); }
#else
  LeakCheckPause() = default;
#endif
  LeakCheckPause(const LeakCheckPause&) = delete;
  LeakCheckPause& operator=(const LeakCheckPause&) = delete;
};

bool finalized = false;

void finalize_petsc() {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized) return;
  [[maybe_unused]] const LeakCheckPause pause;
  PetscFinalize();
  finalized = true;
}

}  // namespace

void ensure_petsc_initialized() {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (initialized) return;
  if (finalized) throw SolverError("PETSc: used after it was finalised at exit");
  [[maybe_unused]] const LeakCheckPause pause;
  // A process no MPI launcher started is an Open MPI singleton, which would
  // fork a support daemon (orted) to serve MPI_Comm_spawn, never used here:
  // measured 0.25 s of wall time at every start (the settling scene's whole
  // run is ~2 s). An isolated singleton starts none; a value the user set stays.
  // Nor does one process need a network transport: Open MPI's default pml
  // "cm" opens its mtl components, and libpsm2's (Omni-Path) loader polls for
  // hardware in 125 us sleeps, 0.20-0.25 s of wall time at every start on this
  // host (strace: 934 usleep calls inside MPI_Init; a one-step run 0.40-0.44 s
  // wall against 0.16-0.19 s with pml ob1, benchmarks/README.md, "Start-up").
  // ob1 with its shared-memory and self transports is all a singleton uses.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr && std::getenv("PMI_SIZE") == nullptr) {
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
    setenv("OMPI_MCA_pml", "ob1", 0);
  }
  // Options set before PetscInitialize are honoured by it.
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  const PetscErrorCode code = PetscInitializeNoArguments();
  if (code != 0) throw SolverError(fmt::format("PETSc: PetscInitialize failed (error {})", static_cast<int>(code)));
  std::atexit(finalize_petsc);
}

bool petsc_finalized() { return finalized; }

bool launched_on_several_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* value = std::getenv(name);
    if (value != nullptr && std::atoi(value) > 1) return true;
  }
  return false;
}

int mpi_ranks() {
  PetscBool initialized = PETSC_FALSE;
  PetscInitialized(&initialized);
  if (!initialized || finalized) return 1;
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}

int mpi_rank() {
  if (mpi_ranks() == 1) return 0;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank;
}

bool on_any_rank(bool flag) {
  if (mpi_ranks() == 1) return flag;
  int mine = flag ? 1 : 0, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_LOR, PETSC_COMM_WORLD);
  return any != 0;
}

void max_over_ranks(std::span<double> values) {
  if (mpi_ranks() == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
}

void sum_over_ranks(std::span<double> values) {
  if (mpi_ranks() == 1 || values.empty()) return;
  MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
}

double sum_over_ranks(double value) {
  if (mpi_ranks() == 1) return value;
  double sum = 0.0;
  MPI_Allreduce(&value, &sum, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  return sum;
}

void abort_all_ranks(int exit_code) {
  std::fflush(stdout);
  std::fflush(stderr);
  if (mpi_ranks() > 1) MPI_Abort(PETSC_COMM_WORLD, exit_code);
  std::_Exit(exit_code);
}

int petsc_world_size() {
  ensure_petsc_initialized();
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}

}  // namespace fdem
