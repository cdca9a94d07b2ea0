// Open MPI behind hb::Communicator.
//  1. Variable-size buffers: the sizes travel first (MPI_Gather / MPI_Allgather of one 64-bit
//     count per rank), then the bytes (MPI_Gatherv / MPI_Allgatherv) in slices of at most
//     1 GiB, since MPI counts are ints.
//  2. Broadcast: the size, then the bytes in the same slices.
//  3. Abort: the message goes to stderr with the rank, then MPI_Abort ends every rank; mpirun
//     (or srun) reports the job as failed with a non-zero exit.
#include "mpi_communicator.h"
#include "errors.h"
#include <mpi.h>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace hb::mpi {
namespace {

constexpr std::uint64_t kSlice = std::uint64_t(1) << 30;

void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw LibraryError(std::string("MPI: ") + what + " failed: " + std::string(text, std::size_t(length)));
}

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

// One slice of a sliced gather: each rank's count of bytes at `offset` and where it lands in
// the receive buffer; returns the slice's total.
int slice_layout(const std::vector<std::uint64_t>& sizes, std::uint64_t offset, std::vector<int>& counts,
                 std::vector<int>& displs) {
  int total = 0;
  for (std::size_t r = 0; r < sizes.size(); ++r) {
    const std::uint64_t s = sizes[r];
    counts[r] = int(std::min(kSlice, s > offset ? s - offset : 0));
    displs[r] = total;
    total += counts[r];
  }
  return total;
}

// Copies a received slice into each rank's buffer at `offset`.
void unpack_slice(const Bytes& recv, const std::vector<int>& counts, const std::vector<int>& displs,
                  std::uint64_t offset, std::vector<Bytes>& out) {
  for (std::size_t r = 0; r < out.size(); ++r)
    if (counts[r] > 0) std::memcpy(out[r].data() + offset, recv.data() + displs[r], std::size_t(counts[r]));
}

int instances = 0;

} // namespace

bool launched_by_mpi() {
  if (const char* force = env("HB_MPI")) return std::strcmp(force, "0") != 0;
  return env("OMPI_COMM_WORLD_SIZE") || env("PMIX_RANK") || env("PMI_RANK") || env("PMI_SIZE");
}

MpiCommunicator::MpiCommunicator(int* argc, char*** argv) {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    // Errors come back as codes (turned into exceptions), not as an abort inside MPI.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  }
  ++instances;
  check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  if (const char* local = env("OMPI_COMM_WORLD_LOCAL_SIZE")) local_size_ = std::max(1, std::atoi(local));
}

MpiCommunicator::~MpiCommunicator() {
  if (--instances == 0) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
  }
}

std::vector<Bytes> MpiCommunicator::gather(const Bytes& mine, int root) {
  const std::uint64_t my_size = mine.size();
  std::vector<std::uint64_t> sizes(static_cast<std::size_t>(size_), 0);
  check(MPI_Gather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, root, MPI_COMM_WORLD), "MPI_Gather");
  // Every rank needs the number of rounds: the largest buffer decides.
  std::uint64_t largest = my_size;
  check(MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_UINT64_T, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  std::vector<Bytes> out;
  if (rank_ == root) {
    out.resize(std::size_t(size_));
    for (int r = 0; r < size_; ++r) out[std::size_t(r)].resize(sizes[std::size_t(r)]);
  }
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(static_cast<std::size_t>(size_));
  Bytes recv;
  for (std::uint64_t offset = 0; offset < std::max<std::uint64_t>(largest, 1); offset += kSlice) {
    const int my_count = int(std::min(kSlice, my_size > offset ? my_size - offset : 0));
    const int total = rank_ == root ? slice_layout(sizes, offset, counts, displs) : 0;
    recv.resize(std::size_t(total));
    check(MPI_Gatherv(mine.data() + std::min<std::uint64_t>(offset, my_size), my_count, MPI_BYTE, recv.data(),
                      counts.data(), displs.data(), MPI_BYTE, root, MPI_COMM_WORLD),
          "MPI_Gatherv");
    if (rank_ == root) unpack_slice(recv, counts, displs, offset, out);
    if (largest == 0) break;
  }
  if (rank_ != root) bytes_sent_ += my_size + sizeof(my_size);
  return out;
}

std::vector<Bytes> MpiCommunicator::all_gather(const Bytes& mine) {
  const std::uint64_t my_size = mine.size();
  std::vector<std::uint64_t> sizes(static_cast<std::size_t>(size_), 0);
  check(MPI_Allgather(&my_size, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD), "MPI_Allgather");
  const std::uint64_t largest = *std::max_element(sizes.begin(), sizes.end());
  std::vector<Bytes> out(static_cast<std::size_t>(size_));
  for (int r = 0; r < size_; ++r) out[std::size_t(r)].resize(sizes[std::size_t(r)]);
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(static_cast<std::size_t>(size_));
  Bytes recv;
  for (std::uint64_t offset = 0; offset < std::max<std::uint64_t>(largest, 1); offset += kSlice) {
    const int total = slice_layout(sizes, offset, counts, displs);
    recv.resize(std::size_t(total));
    check(MPI_Allgatherv(mine.data() + std::min<std::uint64_t>(offset, my_size), counts[std::size_t(rank_)], MPI_BYTE,
                         recv.data(), counts.data(), displs.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    unpack_slice(recv, counts, displs, offset, out);
    if (largest == 0) break;
  }
  bytes_sent_ += (my_size + sizeof(my_size)) * std::uint64_t(size_ - 1);
  return out;
}

void MpiCommunicator::broadcast(Bytes& buffer, int root) {
  std::uint64_t size = buffer.size();
  check(MPI_Bcast(&size, 1, MPI_UINT64_T, root, MPI_COMM_WORLD), "MPI_Bcast");
  if (rank_ != root) buffer.resize(size);
  for (std::uint64_t offset = 0; offset < size; offset += kSlice)
    check(MPI_Bcast(buffer.data() + offset, int(std::min(kSlice, size - offset)), MPI_BYTE, root, MPI_COMM_WORLD),
          "MPI_Bcast");
  if (rank_ == root) bytes_sent_ += (size + sizeof(size)) * std::uint64_t(size_ - 1);
}

void MpiCommunicator::barrier() { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

void MpiCommunicator::abort(const std::string& message, int code) {
  std::fprintf(stderr, "%s\n", message.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, code == 0 ? 1 : code);
  std::_Exit(code == 0 ? 1 : code);  // MPI_Abort does not return; this keeps the promise if it did
}

std::unique_ptr<Communicator> start(int* argc, char*** argv) {
  if (!launched_by_mpi()) return std::make_unique<SerialCommunicator>();
  return std::make_unique<MpiCommunicator>(argc, argv);
}

} // namespace hb::mpi
