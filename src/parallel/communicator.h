#pragma once
// The processes that share one job (MPI ranks, or this process alone) and the few collective
// operations the core's distributed loops need. The core knows only this interface; the MPI
// implementation lives in mpi/ (hb::mpi), which the command line links.
//
// Every operation is collective: every rank of the communicator calls it, in the same order,
// with the same arguments where the comment says so. Results are placed in rank order, so a
// reduction done with them is the same whatever the ranks' timing (decomposition and results
// stay deterministic). A rank that fails calls abort(), which ends the whole job.
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

/// A buffer of bytes exchanged between ranks.
using Bytes = std::vector<std::uint8_t>;

/// What one rank did in a distributed loop (filled by the core's loops, gathered on rank 0).
struct RankWork {
  int rank = 0;
  std::uint64_t work = 0;        ///< units of work done (rays cast, probes answered, ...).
  double seconds = 0.0;          ///< wall time of this rank's share of the loop.
  std::uint64_t bytes_sent = 0;  ///< payload bytes this rank sent for the loop.
};

/// The ranks of a job. Not thread-safe: call from the thread that runs the job.
class Communicator {
public:
  virtual ~Communicator() = default;
  /// This process's rank in [0, size()).
  virtual int rank() const = 0;
  /// Number of ranks (1: this process alone).
  virtual int size() const = 0;
  bool is_root() const { return rank() == 0; }

  /// Rank `root` receives every rank's buffer (its own included) in rank order; the other
  /// ranks receive an empty list. Buffers may differ in size (also empty).
  virtual std::vector<Bytes> gather(const Bytes& mine, int root = 0) = 0;
  /// Every rank receives every rank's buffer in rank order.
  virtual std::vector<Bytes> all_gather(const Bytes& mine) = 0;
  /// Rank `root`'s buffer replaces `buffer` on every other rank (sizes need not be known).
  virtual void broadcast(Bytes& buffer, int root = 0) = 0;
  /// Waits for every rank.
  virtual void barrier() = 0;
  /// Ends the whole job: prints `message` on stderr and exits every rank with `code` (!= 0).
  /// A rank never returns from it.
  [[noreturn]] virtual void abort(const std::string& message, int code) = 0;

  /// Sums and maxima over the ranks, every rank receives the result. The sum of doubles adds
  /// the ranks' values in rank order, so it is the same on every run.
  double sum(double value);
  std::uint64_t sum(std::uint64_t value);
  double max(double value);
  /// Every rank's value, in rank order, on every rank.
  std::vector<double> all_values(double value);

  /// Payload bytes this rank has sent since it was created (rank 0 keeps its own share of a
  /// gather, so that costs it nothing; a broadcast costs the root size() - 1 copies).
  std::uint64_t bytes_sent() const { return bytes_sent_; }

protected:
  std::uint64_t bytes_sent_ = 0;
};

/// This process alone: rank 0 of 1. Collectives return the process's own data.
class SerialCommunicator final : public Communicator {
public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::vector<Bytes> gather(const Bytes& mine, int) override { return {mine}; }
  std::vector<Bytes> all_gather(const Bytes& mine) override { return {mine}; }
  void broadcast(Bytes&, int) override {}
  void barrier() override {}
  [[noreturn]] void abort(const std::string& message, int code) override;
};

/// The communicator to use when an Options struct gives none (nullptr): a process-wide
/// SerialCommunicator. Distributed loops called with it run as they always did.
Communicator& serial_communicator();

/// `communicator` or, when null, serial_communicator().
inline Communicator& communicator_or_serial(Communicator* communicator) {
  return communicator ? *communicator : serial_communicator();
}

} // namespace hb
