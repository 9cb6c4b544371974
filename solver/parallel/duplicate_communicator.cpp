#include "parallel/duplicate_communicator.hpp"

#include <mpi.h>

#include <stdexcept>
#include <string>

namespace fdem {

DuplicateCommunicator::DuplicateCommunicator(const char* owner) {
  int running = 0, finished = 0;
  MPI_Initialized(&running);
  MPI_Finalized(&finished);
  if (!running || finished) throw std::invalid_argument(std::string(owner) + ": MPI is not running");
  MPI_Comm comm = MPI_COMM_NULL;
  MPI_Comm_dup(MPI_COMM_WORLD, &comm);
  handle_ = MPI_Comm_c2f(comm);
}

DuplicateCommunicator::~DuplicateCommunicator() {
  int finished = 0;
  MPI_Finalized(&finished);
  if (finished) return;
  MPI_Comm comm = MPI_Comm_f2c(handle_);
  MPI_Comm_free(&comm);
}

}  // namespace fdem
