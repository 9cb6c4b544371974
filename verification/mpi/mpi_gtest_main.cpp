// The main of the tests that are themselves the MPI program: every rank runs
// every case, and the run fails when any rank fails.
#include <gtest/gtest.h>

#include "core/petsc_runtime.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  fdem::ensure_petsc_initialized();  // MPI_Init (PETSc's, as fdem run does)
  const int mine = RUN_ALL_TESTS();
  return fdem::on_any_rank(mine != 0) ? 1 : 0;
}
