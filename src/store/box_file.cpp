// Writing the .hbox file (the format: box_file_format.h). The header is written twice: once
// with zero offsets to learn its size, then with every section's offset, each aligned to 64
// bytes; the file is written to PATH.tmp and renamed into place.
#include "store/box_file.h"
#include "store/box_file_format.h"
#include "errors.h"
#include <xxhash.h>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace hb {
namespace {


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

std::size_t align_up(std::size_t v) { return (v + kBoxFileAlign - 1) / kBoxFileAlign * kBoxFileAlign; }

// The stroke mesh section (format version 9); empty without a mesh.
std::vector<char> stroke_mesh_bytes(const TriangleMesh* mesh) {
  Writer w;
  if (!mesh) return {};
  static_assert(sizeof(Vec3) == 12 && sizeof(Triangle) == 12, "packed xyz and index triples");
  w.put(std::uint32_t(mesh->positions.size()));
  w.put(std::uint32_t(mesh->triangles.size()));
  w.put_bytes(mesh->positions.data(), mesh->positions.size() * 12);
  w.put_bytes(mesh->normals.data(), mesh->normals.size() * 12);
  w.put_bytes(mesh->triangles.data(), mesh->triangles.size() * 12);
  return std::move(w.bytes());
}

} // namespace

void save_box_file(const BoxScene& scene, const std::string& path) {
  const auto& boxes = scene.parts().boxes;
  const SourceInfo& src = scene.parts().source;
  // Header size is known once written with placeholder offsets; compute offsets after.
  // The surface shared by the refined boxes, or the scene's own without triangle ids (a
  // scene has one, or none).
  const SurfaceTriangles* surface = scene.parts().surface.get();
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
      scene.parts().piece_of_triangle.size() == src.triangles ? scene.parts().piece_of_triangle : no_pieces;
  const std::size_t piece_bytes = pieces.size() * sizeof(std::uint32_t);
  const std::uint64_t piece_hash = pieces.empty() ? 0 : XXH3_64bits(pieces.data(), piece_bytes);
  std::vector<std::uint64_t> id_hashes;
  for (const HapticBox& box : boxes)
    id_hashes.push_back(box.refines() ? XXH3_64bits(box.triangle_ids().data, box.triangle_id_bytes()) : 0);
  const std::vector<std::uint8_t> grid_bytes = scene.parts().grid ? scene.parts().grid->serialize() : std::vector<std::uint8_t>{};
  const std::uint64_t grid_hash = grid_bytes.empty() ? 0 : XXH3_64bits(grid_bytes.data(), grid_bytes.size());
  const std::string budget_text = scene.parts().budget.present ? scene.parts().budget.serialize() : std::string();
  const std::uint64_t budget_hash = budget_text.empty() ? 0 : XXH3_64bits(budget_text.data(), budget_text.size());
  const std::size_t map_bytes = surface ? surface->normal_map_bytes() : 0;
  const std::uint64_t map_hash = map_bytes ? XXH3_64bits(surface->normal_map(), map_bytes) : 0;
  const std::vector<char> stroke_bytes = stroke_mesh_bytes(stroke_mesh(scene));
  const std::uint64_t stroke_hash = stroke_bytes.empty() ? 0 : XXH3_64bits(stroke_bytes.data(), stroke_bytes.size());
  const std::uint32_t version = !stroke_bytes.empty() ? kBoxFileVersion
                                : has_tables(scene.parts())  ? kBoxFileVersionWithTables
                                                      : kBoxFileVersionWithFrames;
  // offsets: the tables, then the ids of each box, then the surface, then the grid (zeros
  // while sizing).
  auto write_header = [&](const std::vector<std::uint64_t>& offsets) {
    Writer w;
    w.put_bytes(kBoxFileMagic, sizeof(kBoxFileMagic));
    w.put(version);
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
      w.put(std::uint64_t(offsets.empty() || !box.has_table() ? 0 : offsets[b]));
      w.put(std::uint64_t(box.table_bytes()));
      w.put(std::uint64_t(box.has_table() ? XXH3_64bits(box.samples().data(), box.table_bytes()) : 0));
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
    if (version >= 9) {
      w.put(std::uint64_t(offsets.empty() ? 0 : offsets[2 * boxes.size() + 5]));
      w.put(std::uint64_t(stroke_bytes.size()));
      w.put(stroke_hash);
    }
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
  blocks.emplace_back(stroke_bytes.empty() ? nullptr : stroke_bytes.data(), stroke_bytes.size());
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
    const char zeros[kBoxFileAlign] = {};
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

} // namespace hb
