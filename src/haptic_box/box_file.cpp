// The .hbox file format, version 7 (little-endian; versions 1 to 6 are still read):
//  1. Header: magic "HBOXFILE", u32 version, u32 box count, u64 mesh hash, u64 triangles,
//     f32 diagonal, u32 path length + path bytes; then per box: u32 codec (CodecId: 0 raw
//     8-byte samples, 1 Haar, 2 block), i32 m, i32 n, f32 centre[3], axes[9] (columns),
//     half[3], u64 table offset, u64 table bytes, u64 table hash (xxHash3 64); version 2 adds
//     the codec statistics: f32 error bound, mean and max t error (relative to the box
//     diagonal), mean and max normal angle (degrees), u64 hit/miss flips; version 3 adds
//     the box's triangle ids (u64 offset, u64 bytes: 0 without refinement, 2 or 4 a sample;
//     u64 hash; u32 base added to 2-byte ids, see TriangleIds) and,
//     after the boxes, the scene's surface triangles (u64 offset, u64 bytes, u64 hash);
//     version 4 adds the scene's piece ids (u64 offset, u64 bytes: 0 or 4 a triangle of the
//     source mesh, u64 hash; BoxScene::piece_of_triangle); version 5 adds the scene grid (u64
//     offset, u64 bytes: 0 without one, u64 hash; its bytes: SceneGrid::serialize); version 6
//     adds the budget report (u64 offset, u64 bytes: 0 for a scene not baked to a budget,
//     u64 hash; its bytes: BudgetReport::serialize, key=value text); version 7 adds the
//     surface's normal map (u32 side: 0 without one, u64 offset, u64 bytes, u64 hash; its
//     bytes: u32 octahedral codes, SurfaceTriangles::set_normal_map); then u64 hash of all
//     header bytes before it.
//  2. Tables at 64-byte aligned offsets: raw records in BoxLayout::sample_index order (box_layout.h), or a
//     compressed payload (codec/table_payload.h); then each refined box's triangle ids
//     (same order; u16 offsets or u32 slots), then the SurfaceTriangles records, then the
//     piece ids (u32 per triangle), then the scene grid, then the budget report, then the
//     normal map.
//  3. Loading maps the file read-only (mmap); boxes point into the mapping, which stays
//     alive while any box of the scene does. Always checked: the header hash, sizes and
//     offsets, every OBB (finite, positive half extents, orthonormal right-handed axes: see
//     obb_problem) and codec statistic, and each compressed payload's own header (one page).
//     Table hashes and "no bytes after the last section" only with LoadOptions::verify (they
//     read every page; lazy opening is the default). The scene grid (a few MB at most) is
//     always hashed, validated and copied.
#include "haptic_box/box_file.h"
#include "errors.h"
#include <xxhash.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hb {
namespace {

constexpr char kMagic[8] = {'H', 'B', 'O', 'X', 'F', 'I', 'L', 'E'};
constexpr std::uint32_t kVersion = 7;
constexpr std::size_t kAlign = 64;

class Writer {
public:
  template <typename T> void put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void put_bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const char*>(p);
    bytes_.insert(bytes_.end(), c, c + n);
  }
  std::vector<char>& bytes() { return bytes_; }

private:
  std::vector<char> bytes_;
};

class Reader {
public:
  Reader(const char* data, std::size_t size, const std::string& path) : data_(data), size_(size), path_(path) {}
  template <typename T> T get() {
    if (pos_ + sizeof(T) > size_) throw InvalidInput(path_ + ": truncated box file (header cut short)");
    T v;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string get_string(std::size_t n) {
    if (n > size_ - pos_) throw InvalidInput(path_ + ": truncated box file (header cut short)");
    std::string s(data_ + pos_, n);
    pos_ += n;
    return s;
  }
  std::size_t pos() const { return pos_; }

private:
  const char* data_;
  std::size_t size_;
  std::string path_;
  std::size_t pos_ = 0;
};

std::size_t align_up(std::size_t v) { return (v + kAlign - 1) / kAlign * kAlign; }

// Owns a read-only mapping of a whole file.
struct FileMap {
  void* data = MAP_FAILED;
  std::size_t size = 0;
  ~FileMap() {
    if (data != MAP_FAILED) munmap(data, size);
  }
};

// Owns an anonymous private copy of a file, 2 MB aligned and advised for huge pages.
struct HugeCopy {
  void* region = MAP_FAILED;
  std::size_t region_size = 0;
  char* data = nullptr;
  ~HugeCopy() {
    if (region != MAP_FAILED) munmap(region, region_size);
  }
};

constexpr std::size_t kHugePage = std::size_t(2) << 20;

} // namespace

void save_box_file(const BoxScene& scene, const std::string& path) {
  const auto& boxes = scene.boxes();
  const SourceInfo& src = scene.source();
  // Header size is known once written with placeholder offsets; compute offsets after.
  // The surface shared by the refined boxes, or the scene's own without triangle ids (a
  // scene has one, or none).
  const SurfaceTriangles* surface = scene.surface().get();
  for (const HapticBox& box : boxes)
    if (box.refines()) {
      if (surface && surface != box.surface().get())
        throw InvalidInput(path + ": cannot save boxes refining against different surfaces");
      surface = box.surface().get();
    }
  const std::uint64_t surface_hash = surface ? XXH3_64bits(surface->records(), surface->bytes()) : 0;
  // Piece ids are written when they match the recorded triangle count (always after hb::bake).
  static const std::vector<std::uint32_t> no_pieces;
  const std::vector<std::uint32_t>& pieces =
      scene.piece_of_triangle().size() == src.triangles ? scene.piece_of_triangle() : no_pieces;
  const std::size_t piece_bytes = pieces.size() * sizeof(std::uint32_t);
  const std::uint64_t piece_hash = pieces.empty() ? 0 : XXH3_64bits(pieces.data(), piece_bytes);
  std::vector<std::uint64_t> id_hashes;
  for (const HapticBox& box : boxes)
    id_hashes.push_back(box.refines() ? XXH3_64bits(box.triangle_ids().data, box.triangle_id_bytes()) : 0);
  const std::vector<std::uint8_t> grid_bytes = scene.grid() ? scene.grid()->serialize() : std::vector<std::uint8_t>{};
  const std::uint64_t grid_hash = grid_bytes.empty() ? 0 : XXH3_64bits(grid_bytes.data(), grid_bytes.size());
  const std::string budget_text = scene.budget_report().present ? scene.budget_report().serialize() : std::string();
  const std::uint64_t budget_hash = budget_text.empty() ? 0 : XXH3_64bits(budget_text.data(), budget_text.size());
  const std::size_t map_bytes = surface ? surface->normal_map_bytes() : 0;
  const std::uint64_t map_hash = map_bytes ? XXH3_64bits(surface->normal_map(), map_bytes) : 0;
  // offsets: the tables, then the ids of each box, then the surface, then the grid (zeros
  // while sizing).
  auto write_header = [&](const std::vector<std::uint64_t>& offsets) {
    Writer w;
    w.put_bytes(kMagic, sizeof(kMagic));
    w.put(kVersion);
    w.put(std::uint32_t(boxes.size()));
    w.put(src.mesh_hash);
    w.put(src.triangles);
    w.put(src.diagonal);
    w.put(std::uint32_t(src.mesh_path.size()));
    w.put_bytes(src.mesh_path.data(), src.mesh_path.size());
    for (std::size_t b = 0; b < boxes.size(); ++b) {
      const HapticBox& box = boxes[b];
      w.put(std::uint32_t(box.codec()));
      w.put(std::int32_t(box.params().m));
      w.put(std::int32_t(box.params().n));
      for (int c = 0; c < 3; ++c) w.put(box.obb().center[c]);
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) w.put(box.obb().axes(r, c));
      for (int c = 0; c < 3; ++c) w.put(box.obb().half[c]);
      w.put(std::uint64_t(offsets.empty() ? 0 : offsets[b]));
      w.put(std::uint64_t(box.table_bytes()));
      w.put(std::uint64_t(XXH3_64bits(box.samples().data(), box.table_bytes())));
      const CodecStats& cs = box.codec_stats();
      w.put(cs.max_error_bound);
      w.put(cs.t_error_mean);
      w.put(cs.t_error_max);
      w.put(cs.normal_error_mean_deg);
      w.put(cs.normal_error_max_deg);
      w.put(std::uint64_t(cs.hit_miss_flips));
      w.put(std::uint64_t(offsets.empty() || !box.refines() ? 0 : offsets[boxes.size() + b]));
      w.put(std::uint64_t(box.triangle_id_bytes()));
      w.put(id_hashes[b]);
      w.put(std::uint32_t(box.refines() ? box.triangle_ids().base : 0));
    }
    w.put(std::uint64_t(offsets.empty() || !surface ? 0 : offsets[2 * boxes.size()]));
    w.put(std::uint64_t(surface ? surface->bytes() : 0));
    w.put(surface_hash);
    w.put(std::uint64_t(offsets.empty() || pieces.empty() ? 0 : offsets[2 * boxes.size() + 1]));
    w.put(std::uint64_t(piece_bytes));
    w.put(piece_hash);
    w.put(std::uint64_t(offsets.empty() || grid_bytes.empty() ? 0 : offsets[2 * boxes.size() + 2]));
    w.put(std::uint64_t(grid_bytes.size()));
    w.put(grid_hash);
    w.put(std::uint64_t(offsets.empty() || budget_text.empty() ? 0 : offsets[2 * boxes.size() + 3]));
    w.put(std::uint64_t(budget_text.size()));
    w.put(budget_hash);
    w.put(std::uint32_t(map_bytes > 0 ? surface->normal_map_side() : 0));
    w.put(std::uint64_t(offsets.empty() || map_bytes == 0 ? 0 : offsets[2 * boxes.size() + 4]));
    w.put(std::uint64_t(map_bytes));
    w.put(map_hash);
    const std::uint64_t header_hash = XXH3_64bits(w.bytes().data(), w.bytes().size());
    w.put(header_hash);
    return std::move(w.bytes());
  };
  // Every block of the file in order: the tables, each box's ids, the surface, the piece ids,
  // the scene grid.
  std::vector<std::pair<const void*, std::size_t>> blocks;
  for (const HapticBox& box : boxes) blocks.emplace_back(box.samples().data(), box.table_bytes());
  for (const HapticBox& box : boxes) blocks.emplace_back(box.triangle_ids().data, box.triangle_id_bytes());
  blocks.emplace_back(surface ? static_cast<const void*>(surface->records()) : nullptr, surface ? surface->bytes() : 0);
  blocks.emplace_back(pieces.data(), piece_bytes);
  blocks.emplace_back(grid_bytes.empty() ? nullptr : grid_bytes.data(), grid_bytes.size());
  blocks.emplace_back(budget_text.empty() ? nullptr : budget_text.data(), budget_text.size());
  blocks.emplace_back(map_bytes ? static_cast<const void*>(surface->normal_map()) : nullptr, map_bytes);
  std::vector<std::uint64_t> offsets;
  std::size_t pos = align_up(write_header({}).size());
  for (const auto& block : blocks) {
    offsets.push_back(pos);
    pos = align_up(pos + block.second);
  }
  const std::vector<char> header = write_header(offsets);

  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(path + ": cannot open for writing (" + std::strerror(errno) + ")");
    out.write(header.data(), std::streamsize(header.size()));
    std::size_t written = header.size();
    const char zeros[kAlign] = {};
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      if (blocks[b].second == 0) continue;
      out.write(zeros, std::streamsize(offsets[b] - written));
      out.write(static_cast<const char*>(blocks[b].first), std::streamsize(blocks[b].second));
      written = offsets[b] + blocks[b].second;
    }
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw IoError(path + ": write failed (disk full?)");
    }
  }
  // Write to a temporary file and rename, so an interrupted save never leaves a half file.
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path + ": cannot rename the written file into place (" + std::strerror(errno) + ")");
  }
}

BoxScene load_box_file(const std::string& path, const LoadOptions& options) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open box file (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw IoError(path + ": not a regular file");
  }
  auto map = std::make_shared<FileMap>();
  map->size = std::size_t(st.st_size);
  if (map->size < sizeof(kMagic) + 8) {
    ::close(fd);
    throw InvalidInput(path + ": not a HapticBox box file (too short: " + std::to_string(map->size) + " bytes)");
  }
  map->data = ::mmap(nullptr, map->size, PROT_READ, MAP_PRIVATE, fd, 0);
  ::close(fd);
  if (map->data == MAP_FAILED) throw IoError(path + ": cannot map box file (" + std::strerror(errno) + ")");
  const char* data = static_cast<const char*>(map->data);

  if (std::memcmp(data, kMagic, sizeof(kMagic)) != 0)
    throw InvalidInput(path + ": not a HapticBox box file (bad magic)");
  Reader r(data, map->size, path);
  r.get_string(sizeof(kMagic));
  const auto version = r.get<std::uint32_t>();
  if (version < 1 || version > kVersion)
    throw InvalidInput(path + ": unsupported box file version " + std::to_string(version) +
                       " (this build reads version " + std::to_string(kVersion) + ")");
  const auto count = r.get<std::uint32_t>();
  if (count == 0 || count > 100000) throw InvalidInput(path + ": corrupt box file (box count " + std::to_string(count) + ")");
  SourceInfo src;
  src.mesh_hash = r.get<std::uint64_t>();
  src.triangles = r.get<std::uint64_t>();
  src.diagonal = r.get<float>();
  const auto path_len = r.get<std::uint32_t>();
  src.mesh_path = r.get_string(path_len);
  struct Entry {
    Obb obb;
    BoxParams params;
    std::uint64_t offset, bytes, hash;
    CodecId codec;
    CodecStats stats;
    std::uint64_t ids_offset = 0, ids_bytes = 0, ids_hash = 0;
    std::uint32_t ids_base = 0;
  };
  std::vector<Entry> entries(count);
  for (auto& e : entries) {
    const auto codec = r.get<std::uint32_t>();
    if (codec > std::uint32_t(CodecId::block) || (version == 1 && codec != 0))
      throw InvalidInput(path + ": unknown table codec " + std::to_string(codec));
    e.codec = CodecId(codec);
    e.params.m = r.get<std::int32_t>();
    e.params.n = r.get<std::int32_t>();
    for (int c = 0; c < 3; ++c) e.obb.center[c] = r.get<float>();
    for (int c = 0; c < 3; ++c)
      for (int rr = 0; rr < 3; ++rr) e.obb.axes(rr, c) = r.get<float>();
    for (int c = 0; c < 3; ++c) e.obb.half[c] = r.get<float>();
    e.offset = r.get<std::uint64_t>();
    e.bytes = r.get<std::uint64_t>();
    e.hash = r.get<std::uint64_t>();
    if (version >= 2) {
      e.stats.max_error_bound = r.get<float>();
      e.stats.t_error_mean = r.get<float>();
      e.stats.t_error_max = r.get<float>();
      e.stats.normal_error_mean_deg = r.get<float>();
      e.stats.normal_error_max_deg = r.get<float>();
      e.stats.hit_miss_flips = r.get<std::uint64_t>();
    }
    if (version >= 3) {
      e.ids_offset = r.get<std::uint64_t>();
      e.ids_bytes = r.get<std::uint64_t>();
      e.ids_hash = r.get<std::uint64_t>();
      e.ids_base = r.get<std::uint32_t>();
    }
  }
  std::uint64_t surface_offset = 0, surface_bytes = 0, surface_hash = 0;
  if (version >= 3) {
    surface_offset = r.get<std::uint64_t>();
    surface_bytes = r.get<std::uint64_t>();
    surface_hash = r.get<std::uint64_t>();
  }
  std::uint64_t pieces_offset = 0, pieces_bytes = 0, pieces_hash = 0;
  if (version >= 4) {
    pieces_offset = r.get<std::uint64_t>();
    pieces_bytes = r.get<std::uint64_t>();
    pieces_hash = r.get<std::uint64_t>();
  }
  std::uint64_t grid_offset = 0, grid_bytes = 0, grid_hash = 0;
  if (version >= 5) {
    grid_offset = r.get<std::uint64_t>();
    grid_bytes = r.get<std::uint64_t>();
    grid_hash = r.get<std::uint64_t>();
  }
  std::uint64_t budget_offset = 0, budget_bytes = 0, budget_hash = 0;
  if (version >= 6) {
    budget_offset = r.get<std::uint64_t>();
    budget_bytes = r.get<std::uint64_t>();
    budget_hash = r.get<std::uint64_t>();
  }
  std::uint32_t map_side = 0;
  std::uint64_t map_offset = 0, map_bytes = 0, map_hash = 0;
  if (version >= 7) {
    map_side = r.get<std::uint32_t>();
    map_offset = r.get<std::uint64_t>();
    map_bytes = r.get<std::uint64_t>();
    map_hash = r.get<std::uint64_t>();
  }
  const std::size_t header_end = r.pos();
  const auto stored_hash = r.get<std::uint64_t>();
  if (XXH3_64bits(data, header_end) != stored_hash)
    throw InvalidInput(path + ": corrupt box file (header checksum mismatch)");

  std::shared_ptr<const void> keep = map;
  if (options.huge_pages) {
    auto copy = std::make_shared<HugeCopy>();
    const std::size_t rounded = (map->size + kHugePage - 1) / kHugePage * kHugePage;
    copy->region_size = rounded + kHugePage;
    copy->region = ::mmap(nullptr, copy->region_size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (copy->region == MAP_FAILED)
      throw IoError(path + ": cannot allocate " + std::to_string(map->size) + " bytes for the tables (" +
                    std::strerror(errno) + ")");
    const auto base = reinterpret_cast<std::uintptr_t>(copy->region);
    copy->data = reinterpret_cast<char*>((base + kHugePage - 1) / kHugePage * kHugePage);
#ifdef MADV_HUGEPAGE
    ::madvise(copy->data, rounded, MADV_HUGEPAGE);  // advice only: 4 KB pages when refused
#endif
    std::memcpy(copy->data, data, map->size);
    data = copy->data;
    keep = std::shared_ptr<const void>(copy, copy->data);
  }

  std::shared_ptr<const SurfaceTriangles> surface;
  if (surface_bytes > 0) {
    if (surface_bytes % sizeof(SurfaceTriangles::Record) != 0 || surface_offset % kAlign != 0)
      throw InvalidInput(path + ": corrupt box file (surface triangles have inconsistent sizes)");
    if (surface_offset > map->size || surface_bytes > map->size - surface_offset)
      throw InvalidInput(path + ": truncated box file (the surface triangles are cut short)");
    if (options.verify && XXH3_64bits(data + surface_offset, surface_bytes) != surface_hash)
      throw InvalidInput(path + ": corrupt box file (surface triangles checksum mismatch)");
    auto records = std::make_shared<SurfaceTriangles>(
        reinterpret_cast<const SurfaceTriangles::Record*>(data + surface_offset),
        std::size_t(surface_bytes / sizeof(SurfaceTriangles::Record)), keep);
    if (map_bytes > 0 || map_side > 0) {
      // The normal map: small next to the records (4 bytes a lattice point), always hashed.
      const std::size_t count = records->size();
      if (map_side < 1 || map_side > std::uint32_t(SurfaceTriangles::kMaxMapSide) || map_offset % kAlign != 0 ||
          map_bytes / 4 / SurfaceTriangles::lattice_points(int(map_side)) != count ||
          map_bytes != std::uint64_t(count) * SurfaceTriangles::lattice_points(int(map_side)) * 4)
        throw InvalidInput(path + ": corrupt box file (the normal map (side " + std::to_string(map_side) + ", " +
                           std::to_string(map_bytes) + " bytes) does not fit " + std::to_string(count) +
                           " surface triangles)");
      if (map_offset > map->size || map_bytes > map->size - map_offset)
        throw InvalidInput(path + ": truncated box file (the normal map is cut short)");
      if (XXH3_64bits(data + map_offset, map_bytes) != map_hash)
        throw InvalidInput(path + ": corrupt box file (normal map checksum mismatch)");
      records->set_normal_map(int(map_side), reinterpret_cast<const std::uint32_t*>(data + map_offset), keep);
    }
    surface = std::move(records);
  } else if (map_bytes > 0 || map_side > 0) {
    throw InvalidInput(path + ": corrupt box file (a normal map without surface triangles)");
  }

  // Every value the query trusts, before any box is built: the OBB (a NaN or an unbounded
  // axis would turn the cell arithmetic into a far index), the diagonal, the codec stats.
  if (!(std::isfinite(src.diagonal) && src.diagonal >= 0.f))
    throw InvalidInput(path + ": corrupt box file (mesh diagonal " + std::to_string(src.diagonal) + ")");
  std::uint64_t end_of_data = header_end + sizeof(std::uint64_t);
  const auto section_end = [&](std::uint64_t offset, std::uint64_t bytes) {
    if (bytes > 0 && offset < header_end + sizeof(std::uint64_t))
      throw InvalidInput(path + ": corrupt box file (a section starts inside the header)");
    if (bytes > 0 && offset <= map->size && bytes <= map->size - offset) end_of_data = std::max(end_of_data, offset + bytes);
  };
  for (std::size_t b = 0; b < entries.size(); ++b) {
    const Entry& e = entries[b];
    if (const std::string why = obb_problem(e.obb); !why.empty())
      throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + ": " + why + ")");
    const CodecStats& cs = e.stats;
    for (float v : {cs.max_error_bound, cs.t_error_mean, cs.t_error_max, cs.normal_error_mean_deg, cs.normal_error_max_deg})
      if (!(std::isfinite(v) && v >= 0.f))
        throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " codec statistics hold " +
                           std::to_string(v) + ")");
    section_end(e.offset, e.bytes);
    section_end(e.ids_offset, e.ids_bytes);
  }
  section_end(surface_offset, surface_bytes);
  section_end(pieces_offset, pieces_bytes);
  section_end(grid_offset, grid_bytes);
  section_end(budget_offset, budget_bytes);
  section_end(map_offset, map_bytes);
  // Bytes after the last section are no part of any box file this program writes.
  if (options.verify && map->size > end_of_data)
    throw InvalidInput(path + ": corrupt box file (" + std::to_string(map->size - end_of_data) +
                       " bytes after the last section)");

  // Piece ids: small (4 bytes a triangle), copied and always checked.
  std::vector<std::uint32_t> pieces;
  if (pieces_bytes > 0) {
    // Divided, not multiplied: a recorded triangle count near 2^64 must not wrap into a match.
    if (pieces_bytes % sizeof(std::uint32_t) != 0 || pieces_bytes / sizeof(std::uint32_t) != src.triangles ||
        pieces_offset % kAlign != 0)
      throw InvalidInput(path + ": corrupt box file (piece ids have inconsistent sizes)");
    if (pieces_offset > map->size || pieces_bytes > map->size - pieces_offset)
      throw InvalidInput(path + ": truncated box file (the piece ids are cut short)");
    if (XXH3_64bits(data + pieces_offset, pieces_bytes) != pieces_hash)
      throw InvalidInput(path + ": corrupt box file (piece ids checksum mismatch)");
    pieces.resize(std::size_t(src.triangles));
    std::memcpy(pieces.data(), data + pieces_offset, pieces_bytes);
    for (std::uint32_t id : pieces)
      if (id >= count) throw InvalidInput(path + ": corrupt box file (piece id " + std::to_string(id) + " of " +
                                          std::to_string(count) + " boxes)");
  }

  std::vector<HapticBox> boxes;
  boxes.reserve(count);
  for (std::size_t b = 0; b < entries.size(); ++b) {
    const Entry& e = entries[b];
    if (e.params.m < 2 || e.params.n < 2 || e.params.m > 1024 || e.params.n > 256 ||
        (e.codec == CodecId::none && e.bytes != e.params.sample_count() * sizeof(Sample)) ||
        e.offset % alignof(Sample) != 0)
      throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " has inconsistent sizes)");
    if (e.offset > map->size || e.bytes > map->size - e.offset)
      throw InvalidInput(path + ": truncated box file (box " + std::to_string(b) + " table is cut short)");
    if (options.verify && XXH3_64bits(data + e.offset, e.bytes) != e.hash)
      throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " table checksum mismatch)");
    if (e.ids_bytes > 0) {
      const std::uint64_t samples = e.params.sample_count();
      if (!surface || (e.ids_bytes != samples * 4u && e.ids_bytes != samples * 2u) || e.ids_offset % 4u != 0)
        throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " triangle ids have inconsistent sizes)");
      if (e.ids_offset > map->size || e.ids_bytes > map->size - e.ids_offset)
        throw InvalidInput(path + ": truncated box file (box " + std::to_string(b) + " triangle ids are cut short)");
      if (options.verify && XXH3_64bits(data + e.ids_offset, e.ids_bytes) != e.ids_hash)
        throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " triangle ids checksum mismatch)");
    }
    if (e.codec == CodecId::none) {
      boxes.emplace_back(e.obb, e.params, reinterpret_cast<const Sample*>(data + e.offset),
                         keep);
    } else {
      try {
        boxes.emplace_back(e.obb, e.params, e.codec, reinterpret_cast<const std::uint8_t*>(data + e.offset),
                           std::size_t(e.bytes), keep, e.stats);
      } catch (const InvalidInput& err) {
        throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " " + err.what() + ")");
      }
    }
    // Ids are bounds-checked at query time (lazy opening reads no id here).
    if (e.ids_bytes > 0) {
      const std::size_t samples = e.params.sample_count();
      const TriangleIds ids{data + e.ids_offset, int(e.ids_bytes / samples), e.ids_base};
      try {
        boxes.back().attach_surface(ids, samples, keep, surface, options.verify);
      } catch (const InvalidInput& err) {  // found by fuzzing: the message must name the file
        throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " " + err.what() + ")");
      }
    }
  }
  std::shared_ptr<const SceneGrid> grid;
  if (grid_bytes > 0) {
    if (grid_offset > map->size || grid_bytes > map->size - grid_offset)
      throw InvalidInput(path + ": truncated box file (the scene grid is cut short)");
    const auto* g = reinterpret_cast<const std::uint8_t*>(data + grid_offset);
    if (XXH3_64bits(g, grid_bytes) != grid_hash) throw InvalidInput(path + ": corrupt box file (scene grid checksum mismatch)");
    try {
      grid = std::make_shared<const SceneGrid>(SceneGrid::deserialize(g, std::size_t(grid_bytes)));
    } catch (const InvalidInput& err) {
      throw InvalidInput(path + ": corrupt box file (" + err.what() + ")");
    }
  }
  // The budget report: a few hundred bytes of text, always hashed and parsed.
  BudgetReport budget;
  if (budget_bytes > 0) {
    if (budget_bytes > (std::uint64_t(1) << 26) || budget_offset > map->size || budget_bytes > map->size - budget_offset)
      throw InvalidInput(path + ": truncated box file (the budget report is cut short)");
    const char* b = data + budget_offset;
    if (XXH3_64bits(b, budget_bytes) != budget_hash)
      throw InvalidInput(path + ": corrupt box file (budget report checksum mismatch)");
    try {
      budget = BudgetReport::parse(std::string(b, std::size_t(budget_bytes)));
    } catch (const InvalidInput& err) {
      throw InvalidInput(path + ": corrupt box file (" + err.what() + ")");
    }
  }
  try {
    BoxScene scene(std::move(boxes), src, std::move(pieces), std::move(grid), surface);
    scene.set_budget_report(std::move(budget));
    return scene;
  } catch (const InvalidInput& err) {
    throw InvalidInput(path + ": corrupt box file (" + err.what() + ")");
  }
}

} // namespace hb
