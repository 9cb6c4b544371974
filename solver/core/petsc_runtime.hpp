#pragma once
// PETSc (and with it MPI) initialised once per process, on first use, and
// finalised at exit. Every PETSc object in fdem is created after
// ensure_petsc_initialized() and must be destroyed before exit's finaliser
// runs; an object outlived by it skips its destroy (petsc_finalized()).

#include <span>

namespace fdem {

/// Initialises PETSc (MPI_Init included) if this process has not yet, with
/// PETSc's signal handlers off (fdem handles SIGINT/SIGTERM itself) and
/// registers PetscFinalize with std::atexit. Throws SolverError on failure.
void ensure_petsc_initialized();

/// True once PetscFinalize has run (then PETSc objects must not be touched).
bool petsc_finalized();

/// Number of MPI ranks of PETSC_COMM_WORLD (initialises PETSc).
int petsc_world_size();

// A run on several MPI ranks (`mpirun -n N fdem run`): every rank holds the
// whole scene and steps it identically; the fluid's linear solve is shared
// (each rank owns a block of rows), output and messages come from rank 0.
// One process, or one rank, never initialises MPI for this.

/// True when an MPI launcher started this process as one of more than one
/// rank (Open MPI's OMPI_COMM_WORLD_SIZE, MPICH's PMI_SIZE; read before
/// MPI_Init, so a single process never starts MPI to find out).
bool launched_on_several_ranks();

/// Ranks and this rank of a running MPI world; 1 and 0 while PETSc is not
/// initialised (then nothing here initialises it).
int mpi_ranks();
int mpi_rank();

/// True on every rank when `flag` is true on any rank (a collective: every
/// rank must call it at the same point); `flag` itself on one rank.
bool on_any_rank(bool flag);

/// Element-wise maximum over the ranks, in place on every rank; sum over the
/// ranks. Collectives like on_any_rank; on one process they return the input.
void max_over_ranks(std::span<double> values);
double sum_over_ranks(double value);
void sum_over_ranks(std::span<double> values);  // in place, every rank the sums (one MPI_Allreduce)

/// Ends every rank with `exit_code` (MPI_Abort): an error on one rank must
/// not leave the others waiting in a collective.
[[noreturn]] void abort_all_ranks(int exit_code);

}  // namespace fdem
