#pragma once
// A duplicate of MPI_COMM_WORLD held for an object's lifetime, so its
// messages never meet PETSc's or another object's (the grains' exchange,
// the mesh's sums), and freed with it unless MPI has been finalized first.
// Held as the handle MPI_Comm_c2f gives, so mpi.h stays out of the headers.
namespace fdem {

class DuplicateCommunicator {
 public:
  /// Throws std::invalid_argument when MPI is not running (`owner` names
  /// the object in the message).
  explicit DuplicateCommunicator(const char* owner);
  ~DuplicateCommunicator();
  DuplicateCommunicator(const DuplicateCommunicator&) = delete;
  DuplicateCommunicator& operator=(const DuplicateCommunicator&) = delete;

  /// The MPI_Comm as MPI_Comm_c2f gives it (MPI_Comm_f2c turns it back).
  int handle() const { return handle_; }

 private:
  int handle_ = 0;
};

}  // namespace fdem
