#pragma once
// The header every compressed table payload starts with (little-endian), followed by an
// index of u32 byte offsets (one per tile or block) and the data section, then
// kPayloadPadding zero bytes so that decoders may read a whole record past any valid offset
// without a bounds check per bit.
#include "codec/codec.h"
#include "codec/sample.h"
#include <cstdint>
#include <vector>

namespace hb {

constexpr std::size_t kPayloadPadding = 512;

struct PayloadHeader {
  char magic[4];              ///< "HBTC"
  std::uint32_t codec;        ///< CodecId
  std::int32_t m, n;
  float t_step;               ///< t lattice step, model units
  float n_step;               ///< octahedral coordinate lattice step
  std::uint64_t index_offset; ///< bytes from payload start
  std::uint64_t index_entries;
  std::uint64_t data_offset;
  std::uint64_t data_bytes;
};
static_assert(sizeof(PayloadHeader) == 56, "packed payload header");

/// Checks the header against the box (O(1), touches only the first page) and returns it.
/// Throws hb::InvalidInput("compressed payload: <cause>") on any inconsistency.
PayloadHeader validate_payload(const std::uint8_t* payload, std::size_t bytes, CodecId codec,
                               const BoxParams& params, std::uint64_t expected_entries,
                               std::size_t padding = kPayloadPadding);

/// While encoding in parallel chunks: the index entry of a record that holds only misses.
constexpr std::uint32_t kMissEntry = 0xffffffffu;

/// Joins records encoded in parallel chunks: the data starts with one shared all-miss byte,
/// then chunk 0's records, chunk 1's, ...; index entries [c * entries_per_chunk, (c + 1) *
/// entries_per_chunk) hold offsets local to chunk c (or kMissEntry) and are rebased to offsets
/// into the joined data (kMissEntry to 0). Frees the chunks. Throws hb::InvalidInput when the
/// data exceeds 4 GiB (`codec` names the codec in the message).
std::vector<std::uint8_t> join_chunk_records(std::vector<std::vector<std::uint8_t>>& chunk_data,
                                             std::vector<std::uint32_t>& index, std::size_t entries_per_chunk,
                                             const char* codec);

/// Assembles header + index + data + padding.
std::vector<std::uint8_t> assemble_payload(CodecId codec, const BoxParams& params, float t_step, float n_step,
                                           const std::vector<std::uint32_t>& index,
                                           const std::vector<std::uint8_t>& data,
                                           std::size_t padding = kPayloadPadding);

} // namespace hb
