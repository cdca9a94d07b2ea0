#pragma once
// hb::mpi: the Open MPI implementation of hb::Communicator, and the start of a job.
// MPI is started only when the process was launched by an MPI launcher (mpirun, mpiexec, or
// srun with PMIx/PMI): the same binary run on its own stays a plain process (no MPI_Init, so
// no launcher daemons, no network probing, no root check).
#include "parallel/communicator.h"
#include <memory>

namespace hb::mpi {

/// True when the environment says an MPI launcher started this process (Open MPI's
/// OMPI_COMM_WORLD_SIZE, PMIx's PMIX_RANK, PMI's PMI_RANK). HB_MPI=1 forces MPI (a singleton
/// start), HB_MPI=0 forbids it.
bool launched_by_mpi();

/// The ranks of MPI_COMM_WORLD. Constructing the first one calls MPI_Init_thread (funneled:
/// only the thread that made it calls MPI; TBB's workers never do); the last one destroyed
/// calls MPI_Finalize. Throws hb::LibraryError when MPI cannot start.
class MpiCommunicator final : public Communicator {
public:
  MpiCommunicator(int* argc, char*** argv);
  ~MpiCommunicator() override;
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<Bytes> gather(const Bytes& mine, int root) override;
  std::vector<Bytes> all_gather(const Bytes& mine) override;
  void broadcast(Bytes& buffer, int root) override;
  void barrier() override;
  [[noreturn]] void abort(const std::string& message, int code) override;

  /// Ranks sharing this node (Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE; 1 when unknown).
  int local_size() const { return local_size_; }

private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
};

/// The communicator of this process: an MpiCommunicator when launched_by_mpi(), otherwise a
/// SerialCommunicator.
std::unique_ptr<Communicator> start(int* argc, char*** argv);

} // namespace hb::mpi
