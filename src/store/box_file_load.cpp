// Loading the .hbox file (the format: box_file_format.h).
//  1. The file is mapped read-only (mmap); with LoadOptions::huge_pages it is copied into
//     anonymous memory advised for huge pages. Boxes point into the mapping (or the copy),
//     which stays alive while any box of the scene does.
//  2. The header is read and its own hash checked.
//  3. Always checked: sizes and offsets, every OBB (finite, positive half extents,
//     orthonormal right-handed axes: see obb_problem) and codec statistic, and each compressed
//     payload's own header (one page). Table hashes and "no bytes after the last section"
//     only with LoadOptions::verify (they read every page; lazy opening is the default).
//  4. The sections: the surface triangles and normal map, the piece ids (copied, checked),
//     each box's table and triangle ids, the scene grid (always hashed, validated and
//     copied), the budget report, the stroke mesh (always hashed and checked; Embree is
//     built over it).
#include "store/box_file.h"
#include "store/box_file_format.h"
#include "errors.h"
#include "mesh/mapped_file.h"
#include <xxhash.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <sys/mman.h>

namespace hb {
namespace {


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



// One section of the file named by the header: where it starts, its bytes, its xxHash3.
struct Section {
  std::uint64_t offset = 0, bytes = 0, hash = 0;
};

// One box's record in the header.
struct BoxEntry {
  Obb obb;
  BoxParams params;
  std::uint64_t offset, bytes, hash;
  CodecId codec;
  CodecStats stats;
  Section ids;
  std::uint32_t ids_base = 0;
};

// What the header says (fields of later versions stay zero in older files).
struct FileHeader {
  std::uint32_t version = 0, count = 0;
  SourceInfo src;
  std::vector<BoxEntry> entries;
  Section surface, pieces, grid, budget, map, stroke;
  std::uint32_t map_side = 0;
  std::size_t end = 0;  // where the header's own hash starts
};

// The whole file mapped read-only; throws what load_box_file documents.
std::shared_ptr<const detail::MappedFile> map_box_file(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (!ec && bytes < sizeof(kBoxFileMagic) + 8)
    throw InvalidInput(path + ": not a HapticBox box file (too short: " + std::to_string(bytes) + " bytes)");
  return std::make_shared<const detail::MappedFile>(path, detail::MappedFile::Access::random);
}

Section read_section(Reader& r) {
  Section s;
  s.offset = r.get<std::uint64_t>();
  s.bytes = r.get<std::uint64_t>();
  s.hash = r.get<std::uint64_t>();
  return s;
}

BoxEntry read_box_entry(Reader& r, std::uint32_t version, const std::string& path) {
  BoxEntry e;
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
    e.ids = read_section(r);
    e.ids_base = r.get<std::uint32_t>();
  }
  return e;
}

// The header (format step 1), its own hash checked.
FileHeader read_header(const char* data, std::size_t size, const std::string& path) {
  if (std::memcmp(data, kBoxFileMagic, sizeof(kBoxFileMagic)) != 0)
    throw InvalidInput(path + ": not a HapticBox box file (bad magic)");
  Reader r(data, size, path);
  r.get_string(sizeof(kBoxFileMagic));
  FileHeader h;
  h.version = r.get<std::uint32_t>();
  if (h.version < 1 || h.version > kBoxFileVersion)
    throw InvalidInput(path + ": unsupported box file version " + std::to_string(h.version) +
                       " (this build reads version " + std::to_string(kBoxFileVersion) + ")");
  h.count = r.get<std::uint32_t>();
  if (h.count == 0 || h.count > 100000)
    throw InvalidInput(path + ": corrupt box file (box count " + std::to_string(h.count) + ")");
  h.src.mesh_hash = r.get<std::uint64_t>();
  h.src.triangles = r.get<std::uint64_t>();
  h.src.diagonal = r.get<float>();
  const auto path_len = r.get<std::uint32_t>();
  h.src.mesh_path = r.get_string(path_len);
  h.entries.reserve(h.count);
  for (std::uint32_t b = 0; b < h.count; ++b) h.entries.push_back(read_box_entry(r, h.version, path));
  if (h.version >= 3) h.surface = read_section(r);
  if (h.version >= 4) h.pieces = read_section(r);
  if (h.version >= 5) h.grid = read_section(r);
  if (h.version >= 6) h.budget = read_section(r);
  if (h.version >= 7) {
    h.map_side = r.get<std::uint32_t>();
    h.map = read_section(r);
  }
  if (h.version >= 9) h.stroke = read_section(r);
  h.end = r.pos();
  const auto stored_hash = r.get<std::uint64_t>();
  if (XXH3_64bits(data, h.end) != stored_hash) throw InvalidInput(path + ": corrupt box file (header checksum mismatch)");
  return h;
}

// LoadOptions::huge_pages: the file copied into anonymous memory advised for huge pages;
// `data` then points into the copy and the result owns it.
std::shared_ptr<const void> huge_page_copy(std::size_t size, const char*& data, const std::string& path) {
  auto copy = std::make_shared<HugeCopy>();
  const std::size_t rounded = (size + kHugePage - 1) / kHugePage * kHugePage;
  copy->region_size = rounded + kHugePage;
  copy->region = ::mmap(nullptr, copy->region_size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (copy->region == MAP_FAILED)
    throw IoError(path + ": cannot allocate " + std::to_string(size) + " bytes for the tables (" +
                  std::strerror(errno) + ")");
  const auto base = reinterpret_cast<std::uintptr_t>(copy->region);
  copy->data = reinterpret_cast<char*>((base + kHugePage - 1) / kHugePage * kHugePage);
#ifdef MADV_HUGEPAGE
  ::madvise(copy->data, rounded, MADV_HUGEPAGE);  // advice only: 4 KB pages when refused
#endif
  std::memcpy(copy->data, data, size);
  data = copy->data;
  return std::shared_ptr<const void>(copy, copy->data);
}

// The bytes of a loaded file and what keeps them alive, for the section readers.
struct Mapped {
  const char* data;
  std::size_t size;
  std::shared_ptr<const void> keep;
  const std::string& path;
};

// The surface triangles shared by the refined boxes, with the normal map (format version 7).
std::shared_ptr<const SurfaceTriangles> read_surface(const FileHeader& h, const Mapped& m, const LoadOptions& options) {
  const std::string& path = m.path;
  const Section& s = h.surface;
  if (s.bytes == 0) {
    if (h.map.bytes > 0 || h.map_side > 0)
      throw InvalidInput(path + ": corrupt box file (a normal map without surface triangles)");
    return nullptr;
  }
  if (s.bytes % sizeof(SurfaceTriangles::Record) != 0 || s.offset % kBoxFileAlign != 0)
    throw InvalidInput(path + ": corrupt box file (surface triangles have inconsistent sizes)");
  if (s.offset > m.size || s.bytes > m.size - s.offset)
    throw InvalidInput(path + ": truncated box file (the surface triangles are cut short)");
  if (options.verify && XXH3_64bits(m.data + s.offset, s.bytes) != s.hash)
    throw InvalidInput(path + ": corrupt box file (surface triangles checksum mismatch)");
  auto records = std::make_shared<SurfaceTriangles>(reinterpret_cast<const SurfaceTriangles::Record*>(m.data + s.offset),
                                                    std::size_t(s.bytes / sizeof(SurfaceTriangles::Record)), m.keep);
  if (h.map.bytes > 0 || h.map_side > 0) {
    // The normal map: small next to the records (4 bytes a lattice point), always hashed.
    const Section& map = h.map;
    const std::uint32_t side = h.map_side;
    const std::size_t count = records->size();
    if (side < 1 || side > std::uint32_t(SurfaceTriangles::kMaxMapSide) || map.offset % kBoxFileAlign != 0 ||
        map.bytes / 4 / SurfaceTriangles::lattice_points(int(side)) != count ||
        map.bytes != std::uint64_t(count) * SurfaceTriangles::lattice_points(int(side)) * 4)
      throw InvalidInput(path + ": corrupt box file (the normal map (side " + std::to_string(side) + ", " +
                         std::to_string(map.bytes) + " bytes) does not fit " + std::to_string(count) +
                         " surface triangles)");
    if (map.offset > m.size || map.bytes > m.size - map.offset)
      throw InvalidInput(path + ": truncated box file (the normal map is cut short)");
    if (XXH3_64bits(m.data + map.offset, map.bytes) != map.hash)
      throw InvalidInput(path + ": corrupt box file (normal map checksum mismatch)");
    records->set_normal_map(int(side), reinterpret_cast<const std::uint32_t*>(m.data + map.offset), m.keep);
  }
  return records;
}

// Every value the query trusts, before any box is built: the OBB (a NaN or an unbounded axis
// would turn the cell arithmetic into a far index), the diagonal, the codec stats; every
// section after the header; with LoadOptions::verify, no bytes after the last section.
void check_header_values(const FileHeader& h, std::size_t size, const LoadOptions& options, const std::string& path) {
  if (!(std::isfinite(h.src.diagonal) && h.src.diagonal >= 0.f))
    throw InvalidInput(path + ": corrupt box file (mesh diagonal " + std::to_string(h.src.diagonal) + ")");
  std::uint64_t end_of_data = h.end + sizeof(std::uint64_t);
  const auto section_end = [&](const Section& s) {
    if (s.bytes > 0 && s.offset < h.end + sizeof(std::uint64_t))
      throw InvalidInput(path + ": corrupt box file (a section starts inside the header)");
    if (s.bytes > 0 && s.offset <= size && s.bytes <= size - s.offset) end_of_data = std::max(end_of_data, s.offset + s.bytes);
  };
  for (std::size_t b = 0; b < h.entries.size(); ++b) {
    const BoxEntry& e = h.entries[b];
    if (const std::string why = obb_problem(e.obb); !why.empty())
      throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + ": " + why + ")");
    const CodecStats& cs = e.stats;
    for (float v : {cs.max_error_bound, cs.t_error_mean, cs.t_error_max, cs.normal_error_mean_deg, cs.normal_error_max_deg})
      if (!(std::isfinite(v) && v >= 0.f))
        throw InvalidInput(path + ": corrupt box file (box " + std::to_string(b) + " codec statistics hold " +
                           std::to_string(v) + ")");
    section_end(Section{e.offset, e.bytes, e.hash});
    section_end(e.ids);
  }
  for (const Section* s : {&h.surface, &h.pieces, &h.grid, &h.budget, &h.map, &h.stroke}) section_end(*s);
  // Bytes after the last section are no part of any box file this program writes.
  if (options.verify && size > end_of_data)
    throw InvalidInput(path + ": corrupt box file (" + std::to_string(size - end_of_data) + " bytes after the last section)");
}

// Piece ids: small (4 bytes a triangle), copied and always checked.
std::vector<std::uint32_t> read_piece_ids(const FileHeader& h, const Mapped& m) {
  const std::string& path = m.path;
  const Section& s = h.pieces;
  std::vector<std::uint32_t> pieces;
  if (s.bytes == 0) return pieces;
  // Divided, not multiplied: a recorded triangle count near 2^64 must not wrap into a match.
  if (s.bytes % sizeof(std::uint32_t) != 0 || s.bytes / sizeof(std::uint32_t) != h.src.triangles || s.offset % kBoxFileAlign != 0)
    throw InvalidInput(path + ": corrupt box file (piece ids have inconsistent sizes)");
  if (s.offset > m.size || s.bytes > m.size - s.offset)
    throw InvalidInput(path + ": truncated box file (the piece ids are cut short)");
  if (XXH3_64bits(m.data + s.offset, s.bytes) != s.hash)
    throw InvalidInput(path + ": corrupt box file (piece ids checksum mismatch)");
  pieces.resize(std::size_t(h.src.triangles));
  std::memcpy(pieces.data(), m.data + s.offset, s.bytes);
  for (std::uint32_t id : pieces)
    if (id >= h.count)
      throw InvalidInput(path + ": corrupt box file (piece id " + std::to_string(id) + " of " + std::to_string(h.count) +
                         " boxes)");
  return pieces;
}

// Box b's table (format step 2), and its triangle ids against the shared surface.
HapticBox read_box(std::size_t b, const BoxEntry& e, std::uint32_t version, const Mapped& m,
                   const std::shared_ptr<const SurfaceTriangles>& surface, const LoadOptions& options) {
  const std::string& path = m.path;
  const std::string box = "box " + std::to_string(b);
  if (e.bytes == 0 && version >= 8) {
    // A frame (format version 8): no table, no ids; its scene must be answered by Embree.
    if (e.codec != CodecId::none || e.offset != 0 || e.hash != 0 || e.ids.bytes != 0 || e.params.m > 1024 ||
        e.params.n > 256)
      throw InvalidInput(path + ": corrupt box file (" + box + " is a frame without a table but names table data)");
    try {
      return HapticBox(e.obb, e.params);
    } catch (const InvalidInput& err) {
      throw InvalidInput(path + ": corrupt box file (" + box + " " + err.what() + ")");
    }
  }
  if (e.params.m < 2 || e.params.n < 2 || e.params.m > 1024 || e.params.n > 256 ||
      (e.codec == CodecId::none && e.bytes != e.params.sample_count() * sizeof(Sample)) || e.offset % alignof(Sample) != 0)
    throw InvalidInput(path + ": corrupt box file (" + box + " has inconsistent sizes)");
  if (e.offset > m.size || e.bytes > m.size - e.offset)
    throw InvalidInput(path + ": truncated box file (" + box + " table is cut short)");
  if (options.verify && XXH3_64bits(m.data + e.offset, e.bytes) != e.hash)
    throw InvalidInput(path + ": corrupt box file (" + box + " table checksum mismatch)");
  const Section& ids = e.ids;
  if (ids.bytes > 0) {
    const std::uint64_t samples = e.params.sample_count();
    if (!surface || (ids.bytes != samples * 4u && ids.bytes != samples * 2u) || ids.offset % 4u != 0)
      throw InvalidInput(path + ": corrupt box file (" + box + " triangle ids have inconsistent sizes)");
    if (ids.offset > m.size || ids.bytes > m.size - ids.offset)
      throw InvalidInput(path + ": truncated box file (" + box + " triangle ids are cut short)");
    if (options.verify && XXH3_64bits(m.data + ids.offset, ids.bytes) != ids.hash)
      throw InvalidInput(path + ": corrupt box file (" + box + " triangle ids checksum mismatch)");
  }
  std::optional<HapticBox> out;
  if (e.codec == CodecId::none) {
    out.emplace(e.obb, e.params, reinterpret_cast<const Sample*>(m.data + e.offset), m.keep);
  } else {
    try {
      out.emplace(e.obb, e.params, e.codec, reinterpret_cast<const std::uint8_t*>(m.data + e.offset), std::size_t(e.bytes),
                  m.keep, e.stats);
    } catch (const InvalidInput& err) {
      throw InvalidInput(path + ": corrupt box file (" + box + " " + err.what() + ")");
    }
  }
  // Ids are bounds-checked at query time (lazy opening reads no id here).
  if (ids.bytes > 0) {
    const std::size_t samples = e.params.sample_count();
    const TriangleIds triangle_ids{m.data + ids.offset, int(ids.bytes / samples), e.ids_base};
    try {
      out->attach_surface(triangle_ids, samples, m.keep, surface, options.verify);
    } catch (const InvalidInput& err) {  // found by fuzzing: the message must name the file
      throw InvalidInput(path + ": corrupt box file (" + box + " " + err.what() + ")");
    }
  }
  return std::move(*out);
}

// The scene grid (a few MB at most): always hashed, validated and copied.
std::shared_ptr<const SceneGrid> read_grid(const FileHeader& h, const Mapped& m) {
  const std::string& path = m.path;
  const Section& s = h.grid;
  if (s.bytes == 0) return nullptr;
  if (s.offset > m.size || s.bytes > m.size - s.offset)
    throw InvalidInput(path + ": truncated box file (the scene grid is cut short)");
  const auto* g = reinterpret_cast<const std::uint8_t*>(m.data + s.offset);
  if (XXH3_64bits(g, s.bytes) != s.hash) throw InvalidInput(path + ": corrupt box file (scene grid checksum mismatch)");
  try {
    return std::make_shared<const SceneGrid>(SceneGrid::deserialize(g, std::size_t(s.bytes)));
  } catch (const InvalidInput& err) {
    throw InvalidInput(path + ": corrupt box file (" + err.what() + ")");
  }
}

// The budget report: a few hundred bytes of text, always hashed and parsed.
BudgetReport read_budget_report(const FileHeader& h, const Mapped& m) {
  const std::string& path = m.path;
  const Section& s = h.budget;
  if (s.bytes == 0) return BudgetReport{};
  if (s.bytes > (std::uint64_t(1) << 26) || s.offset > m.size || s.bytes > m.size - s.offset)
    throw InvalidInput(path + ": truncated box file (the budget report is cut short)");
  const char* b = m.data + s.offset;
  if (XXH3_64bits(b, s.bytes) != s.hash) throw InvalidInput(path + ": corrupt box file (budget report checksum mismatch)");
  try {
    return BudgetReport::parse(std::string(b, std::size_t(s.bytes)));
  } catch (const InvalidInput& err) {
    throw InvalidInput(path + ": corrupt box file (" + err.what() + ")");
  }
}

// The stroke route's full mesh (format version 9): always hashed and checked (sizes, finite
// values, indices), then copied into a mesh of its own (Embree is built over it).
std::optional<TriangleMesh> read_stroke_mesh(const FileHeader& h, const Mapped& m) {
  const std::string& path = m.path;
  const Section& s = h.stroke;
  if (s.bytes == 0) return std::nullopt;
  if (s.offset > m.size || s.bytes > m.size - s.offset || s.bytes < 8)
    throw InvalidInput(path + ": truncated box file (the stroke mesh is cut short)");
  const char* b = m.data + s.offset;
  if (XXH3_64bits(b, s.bytes) != s.hash) throw InvalidInput(path + ": corrupt box file (stroke mesh checksum mismatch)");
  std::uint32_t vertices = 0, triangles = 0;
  std::memcpy(&vertices, b, 4);
  std::memcpy(&triangles, b + 4, 4);
  if (s.bytes != 8 + std::uint64_t(vertices) * 24 + std::uint64_t(triangles) * 12 || triangles == 0)
    throw InvalidInput(path + ": corrupt box file (the stroke mesh's " + std::to_string(s.bytes) + " bytes do not hold " +
                       std::to_string(vertices) + " vertices and " + std::to_string(triangles) + " triangles)");
  TriangleMesh mesh;
  mesh.positions.resize(vertices);
  mesh.normals.resize(vertices);
  mesh.triangles.resize(triangles);
  static_assert(sizeof(Vec3) == 12 && sizeof(Triangle) == 12, "packed xyz and index triples");
  const char* p = b + 8;
  std::memcpy(mesh.positions.data(), p, std::size_t(vertices) * 12);
  std::memcpy(mesh.normals.data(), p + std::size_t(vertices) * 12, std::size_t(vertices) * 12);
  std::memcpy(mesh.triangles.data(), p + std::size_t(vertices) * 24, std::size_t(triangles) * 12);
  // Positions within 1e18 (an edge's cross product stays finite), unit normals (as written).
  for (const Vec3& v : mesh.positions)
    if (!v.allFinite() || v.cwiseAbs().maxCoeff() > 1e18f)
      throw InvalidInput(path + ": corrupt box file (a stroke mesh vertex is not finite or beyond 1e18)");
  for (const Vec3& v : mesh.normals) {
    const float length = v.norm();
    if (!(length > 0.9f && length < 1.1f))
      throw InvalidInput(path + ": corrupt box file (a stroke mesh vertex normal is not of unit length)");
  }
  for (std::uint32_t t = 0; t < triangles; ++t) {
    for (std::uint32_t v : mesh.triangles[t])
      if (v >= vertices)
        throw InvalidInput(path + ": corrupt box file (stroke mesh triangle " + std::to_string(t) + " names vertex " +
                           std::to_string(v) + " of " + std::to_string(vertices) + ")");
  }
  return mesh;
}

} // namespace

BoxScene load_box_file(const std::string& path, const LoadOptions& options) {
  const std::shared_ptr<const detail::MappedFile> map = map_box_file(path);
  const char* data = map->data();
  const FileHeader h = read_header(data, map->size(), path);
  std::shared_ptr<const void> keep = map;
  if (options.huge_pages) keep = huge_page_copy(map->size(), data, path);
  const Mapped m{data, map->size(), keep, path};
  const std::shared_ptr<const SurfaceTriangles> surface = read_surface(h, m, options);
  check_header_values(h, map->size(), options, path);
  std::vector<std::uint32_t> pieces = read_piece_ids(h, m);
  std::vector<HapticBox> boxes;
  boxes.reserve(h.count);
  for (std::size_t b = 0; b < h.entries.size(); ++b) boxes.push_back(read_box(b, h.entries[b], h.version, m, surface, options));
  std::shared_ptr<const SceneGrid> grid = read_grid(h, m);
  BudgetReport budget = read_budget_report(h, m);
  std::optional<TriangleMesh> stroke = read_stroke_mesh(h, m);
  try {
    SceneParts parts{std::move(boxes), h.src, std::move(pieces), std::move(grid), surface};
    // The bake measured Embree faster on this scene: it answers (a surface without a normal map).
    if (budget.answer == Answerer::embree && surface && surface->normal_map_side() == 0) parts.route = SceneRoute::embree;
    parts.budget = std::move(budget);
    if (stroke) parts.stroke = make_stroke_route(std::move(*stroke));
    if (!has_tables(parts) && parts.route != SceneRoute::embree && !(parts.grid && parts.surface))
      throw InvalidInput("box frames without tables, and the scene names no Embree route (nor surface cells) to answer it");
    return BoxScene(std::move(parts));
  } catch (const InvalidInput& err) {
    throw InvalidInput(path + ": corrupt box file (" + err.what() + ")");
  }
}

} // namespace hb
