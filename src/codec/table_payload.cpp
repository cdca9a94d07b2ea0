#include "codec/table_payload.h"
#include "codec/bit_io.h"
#include "errors.h"
#include <cmath>
#include <cstring>
#include <string>

namespace hb {

PayloadHeader validate_payload(const std::uint8_t* payload, std::size_t bytes, CodecId codec,
                               const BoxParams& params, std::uint64_t expected_entries,
                               std::size_t padding) {
  auto fail = [](const std::string& why) { throw InvalidInput("compressed payload: " + why); };
  if (!payload || bytes < sizeof(PayloadHeader)) fail("too short for its header");
  PayloadHeader h;
  std::memcpy(&h, payload, sizeof(h));
  if (std::memcmp(h.magic, "HBTC", 4) != 0) fail("bad magic");
  if (h.codec != std::uint32_t(codec)) fail("codec id " + std::to_string(h.codec) + " does not match the box's");
  if (h.m != params.m || h.n != params.n) fail("densities do not match the box's");
  if (!(h.t_step > 0.f) || !std::isfinite(h.t_step) || !(h.n_step > 0.f) || !std::isfinite(h.n_step))
    fail("bad quantisation steps");
  if (h.index_entries != expected_entries) fail("index has " + std::to_string(h.index_entries) + " entries, expected " + std::to_string(expected_entries));
  if (h.index_offset < sizeof(PayloadHeader) || h.index_offset > bytes || h.index_entries * 4u > bytes - h.index_offset)
    fail("index runs past the end");
  if (h.data_offset < h.index_offset + h.index_entries * 4u || h.data_offset > bytes ||
      h.data_bytes > bytes - h.data_offset || bytes - h.data_offset - h.data_bytes < padding)
    fail("data section runs past the end");
  if (h.data_bytes > 0xffffffffull) fail("data section larger than 4 GiB");
  return h;
}

std::vector<std::uint8_t> assemble_payload(CodecId codec, const BoxParams& params, float t_step, float n_step,
                                           const std::vector<std::uint32_t>& index,
                                           const std::vector<std::uint8_t>& data,
                                           std::size_t padding) {
  PayloadHeader h{};
  std::memcpy(h.magic, "HBTC", 4);
  h.codec = std::uint32_t(codec);
  h.m = params.m;
  h.n = params.n;
  h.t_step = t_step;
  h.n_step = n_step;
  h.index_offset = 64;
  h.index_entries = index.size();
  h.data_offset = (h.index_offset + index.size() * 4u + 63u) / 64u * 64u;
  h.data_bytes = data.size();
  std::vector<std::uint8_t> out(h.data_offset + data.size() + padding, 0);
  std::memcpy(out.data(), &h, sizeof(h));
  std::memcpy(out.data() + h.index_offset, index.data(), index.size() * 4u);
  std::memcpy(out.data() + h.data_offset, data.data(), data.size());
  return out;
}

std::vector<std::uint8_t> join_chunk_records(std::vector<std::vector<std::uint8_t>>& chunk_data,
                                             std::vector<std::uint32_t>& index, std::size_t entries_per_chunk,
                                             const char* codec) {
  std::vector<std::uint8_t> data(1, 0);  // the shared all-miss record
  std::vector<std::uint64_t> base(chunk_data.size());
  for (std::size_t c = 0; c < chunk_data.size(); ++c) {
    base[c] = data.size();
    data.insert(data.end(), chunk_data[c].begin(), chunk_data[c].end());
    std::vector<std::uint8_t>().swap(chunk_data[c]);
  }
  if (data.size() > 0xffffffffull) throw InvalidInput(std::string(codec) + " codec: compressed table larger than 4 GiB");
  for (std::size_t i = 0; i < index.size(); ++i) {
    std::uint32_t& e = index[i];
    e = e == kMissEntry ? 0u : std::uint32_t(base[i / entries_per_chunk] + e);
  }
  return data;
}

} // namespace hb
