#pragma once
// PETSc (and with it MPI) initialised once per process, on first use, and
// finalised at exit. Every PETSc object in fdem is created after
// ensure_petsc_initialized() and must be destroyed before exit's finaliser
// runs; an object outlived by it skips its destroy (petsc_finalized()).

namespace fdem {

/// Initialises PETSc (MPI_Init included) if this process has not yet, with
/// PETSc's signal handlers off (fdem handles SIGINT/SIGTERM itself) and
/// registers PetscFinalize with std::atexit. Throws SolverError on failure.
void ensure_petsc_initialized();

/// True once PetscFinalize has run (then PETSc objects must not be touched).
bool petsc_finalized();

/// Number of MPI ranks of PETSC_COMM_WORLD (initialises PETSc).
int petsc_world_size();

}  // namespace fdem
