#pragma once
// How the core's distributed loops share work between ranks: fixed, deterministic schedules
// that depend on the work's size and the number of ranks only, so every rank computes the same
// schedule without talking, and rank 0 knows where each rank's results go.
#include <cstddef>
#include <vector>

namespace hb {

/// Items [0, count) cut into chunks of `chunk` items (the last may be shorter), dealt to the
/// ranks in turn: chunk k goes to rank k % ranks. Dealing (rather than one block per rank)
/// spreads regions of the work that cost more (probes in pockets, box faces that meet the
/// surface) over every rank. chunk >= 1, ranks >= 1.
struct DealtChunks {
  std::size_t count = 0;
  std::size_t chunk = 1;
  int ranks = 1;

  std::size_t chunk_count() const { return count == 0 ? 0 : (count + chunk - 1) / chunk; }
  int owner(std::size_t k) const { return int(k % std::size_t(ranks)); }
  std::size_t begin(std::size_t k) const { return k * chunk; }
  std::size_t end(std::size_t k) const { return k * chunk + chunk < count ? k * chunk + chunk : count; }
  /// Items the given rank owns.
  std::size_t items_of(int rank) const {
    std::size_t total = 0;
    for (std::size_t k = std::size_t(rank); k < chunk_count(); k += std::size_t(ranks)) total += end(k) - begin(k);
    return total;
  }
  /// Calls f(first, last) for every chunk of `rank`, in item order.
  template <class F> void for_each_of(int rank, F&& f) const {
    for (std::size_t k = std::size_t(rank); k < chunk_count(); k += std::size_t(ranks)) f(begin(k), end(k));
  }
};

/// A chunk size for dealing `count` items to `ranks` ranks: about `per_rank` chunks per rank
/// (so dealing evens out), at least `min_chunk` items (so each chunk is worth its bookkeeping).
std::size_t deal_chunk_size(std::size_t count, int ranks, std::size_t per_rank = 64, std::size_t min_chunk = 16);

} // namespace hb
