// The main of the tests that are themselves the MPI program: every rank runs
// every case, and the run fails when any rank fails.
#include <gtest/gtest.h>
#include <mpi.h>

#include "core/petsc_runtime.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  fdem::ensure_petsc_initialized();  // MPI_Init (PETSc's, as fdem run does)
  const int mine = RUN_ALL_TESTS();
  int any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return any;
}
