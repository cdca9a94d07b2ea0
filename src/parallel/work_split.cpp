#include "parallel/work_split.h"
#include <algorithm>

namespace hb {

std::size_t deal_chunk_size(std::size_t count, int ranks, std::size_t per_rank, std::size_t min_chunk) {
  const std::size_t chunks = std::max<std::size_t>(1, std::size_t(std::max(ranks, 1)) * std::max<std::size_t>(per_rank, 1));
  return std::max<std::size_t>(std::max<std::size_t>(min_chunk, 1), (count + chunks - 1) / chunks);
}

} // namespace hb
