// Scene grid (see scene_grid.h): the grid's parts validated, the query words and brick
// summaries derived from the codes (compute_clearance), and the file form. Building one from
// a mesh: scene_grid_build.cpp.
#include "surface/scene_grid.h"
#include "errors.h"
#include <algorithm>
#include <cstring>
#include <string>

namespace hb {

SceneGrid::SceneGrid(const Vec3& origin, float cell, const std::array<int, 3>& dims, std::vector<std::uint16_t> codes,
                     std::vector<std::uint32_t> list_offsets, std::vector<std::uint32_t> list_boxes)
    : origin_(origin), cell_(cell), inv_cell_(cell > 0.f ? 1.f / cell : 0.f), dims_(dims), codes_(std::move(codes)),
      list_offsets_(std::move(list_offsets)), list_boxes_(std::move(list_boxes)) {
  if (!origin_.allFinite() || !(cell_ > 0.f) || !std::isfinite(cell_) || !std::isfinite(inv_cell_))
    throw InvalidInput("scene grid: origin and cell must be finite, cell > 0");
  std::size_t cells = 1;
  for (int k = 0; k < 3; ++k) {
    if (dims_[k] < 1 || dims_[k] > (1 << 16)) throw InvalidInput("scene grid: dimension " + std::to_string(dims_[k]) + " out of range");
    cells *= std::size_t(dims_[k]);
  }
  if (cells > (std::size_t(1) << 30) || codes_.size() != cells)
    throw InvalidInput("scene grid: " + std::to_string(codes_.size()) + " codes for " + std::to_string(cells) + " cells");
  if (list_offsets_.empty() || list_offsets_.front() != 0 || list_offsets_.back() != list_boxes_.size() ||
      list_offsets_.size() - 1 > kMaxLists)
    throw InvalidInput("scene grid: inconsistent box lists");
  for (std::size_t i = 1; i < list_offsets_.size(); ++i)
    if (list_offsets_[i] < list_offsets_[i - 1]) throw InvalidInput("scene grid: inconsistent box lists");
  const std::size_t lists = list_offsets_.size() - 1;
  for (std::uint16_t code : codes_)
    if (code >= kFirstSurface + lists)
      throw InvalidInput("scene grid: cell code " + std::to_string(code) + " names no box list");
  compute_clearance();
}

namespace {

// Chessboard distance over an nx x ny x nz grid (x fastest) from the cells holding 0 in `d`,
// capped at `cap` (the other cells start at `cap`): a forward and a backward raster pass over
// the 13 neighbours of the 3 x 3 x 3 mask visited before a cell in that pass's order.
void chessboard_distance(std::vector<std::uint8_t>& d, int nx, int ny, int nz, int cap) {
  const auto index = [&](int x, int y, int z) {
    return (std::size_t(z) * std::size_t(ny) + std::size_t(y)) * std::size_t(nx) + std::size_t(x);
  };
  for (const int dir : {1, -1}) {
    const int x0 = dir > 0 ? 0 : nx - 1, y0 = dir > 0 ? 0 : ny - 1, z0 = dir > 0 ? 0 : nz - 1;
    for (int z = z0; z >= 0 && z < nz; z += dir)
      for (int y = y0; y >= 0 && y < ny; y += dir)
        for (int x = x0; x >= 0 && x < nx; x += dir) {
          std::uint8_t& here = d[index(x, y, z)];
          if (here == 0) continue;
          int best = here;
          for (int dz = -1; dz <= 0; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const int X = x + dir * dx, Y = y + dir * dy, Z = z + dir * dz;
                if (X < 0 || Y < 0 || Z < 0 || X >= nx || Y >= ny || Z >= nz) continue;
                best = std::min(best, int(d[index(X, Y, Z)]) + 1);
              }
          here = std::uint8_t(std::min(best, cap));
        }
  }
}

} // namespace

// Chessboard (L-infinity) distance in cells from each cell to the nearest surface cell,
// capped at 255: two raster passes over the 13 causal neighbours of the 3 x 3 x 3 mask are
// exact for this metric. Derived from the codes, so files need not store it.
void SceneGrid::compute_clearance() {
  const int nx = dims_[0], ny = dims_[1], nz = dims_[2];
  std::vector<std::uint8_t> clear(codes_.size(), 255);
  for (std::size_t c = 0; c < codes_.size(); ++c)
    if (codes_[c] >= kFirstSurface) clear[c] = 0;
  const auto index = [&](int x, int y, int z) {
    return (std::size_t(z) * std::size_t(ny) + std::size_t(y)) * std::size_t(nx) + std::size_t(x);
  };
  chessboard_distance(clear, nx, ny, nz, 255);
  // The query words in bricks (scene_grid.h, cells_); the bricks' cells beyond the grid are
  // never read.
  bricks_x_ = (nx + 3) / 4;
  bricks_y_ = (ny + 3) / 4;
  const int bricks_z = (nz + 3) / 4;
  cells_.assign(std::size_t(bricks_x_) * std::size_t(bricks_y_) * std::size_t(bricks_z) * 64, 0u);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const std::size_t c = index(x, y, z);
        cells_[cell_index(x, y, z)] = std::uint32_t(codes_[c]) | (std::uint32_t(clear[c]) << 16);
      }
  // Brick summaries (bricks()): the shared state of a brick without surface (its cells are
  // 6-connected and no triangle meets them, so the flood fill gave them one region; any
  // disagreement is kept as "surface", which only costs the cell word load), then the
  // chessboard distance in bricks to a brick with surface, by the same two raster passes.
  const std::size_t brick_count = std::size_t(bricks_x_) * std::size_t(bricks_y_) * std::size_t(bricks_z);
  std::vector<std::uint8_t> state(brick_count, 0xff);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const std::uint16_t code = codes_[index(x, y, z)];
        std::uint8_t& b = state[brick_index(x, y, z)];
        const std::uint8_t here = code >= kFirstSurface ? kBrickSurface : std::uint8_t(code);
        b = b == 0xff || b == here ? here : kBrickSurface;
      }
  const int bx = bricks_x_, by = bricks_y_, bz = bricks_z;
  std::vector<std::uint8_t> bclear(brick_count, 63);
  for (std::size_t b = 0; b < brick_count; ++b)
    if (state[b] == kBrickSurface) bclear[b] = 0;
  chessboard_distance(bclear, bx, by, bz, 63);
  bricks_.resize(brick_count);
  for (std::size_t b = 0; b < brick_count; ++b) bricks_[b] = std::uint8_t(state[b] | (bclear[b] << 2));
}

float SceneGrid::surface_distance_bound(const Vec3& p) const noexcept {
  if (codes_.empty() || !p.allFinite()) return 0.f;
  const Vec3 lo = origin_, hi = origin_ + cell_ * Vec3(float(dims_[0]), float(dims_[1]), float(dims_[2]));
  const Vec3 outside = (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero());
  const Vec3 q = p.cwiseMax(lo).cwiseMin(hi);  // p's nearest point of the grid
  int c[3];
  for (int k = 0; k < 3; ++k) c[k] = std::min(dims_[k] - 1, std::max(0, int((q[k] - origin_[k]) * inv_cell_)));
  const std::uint8_t brick = bricks_[brick_index(c[0], c[1], c[2])];
  // A surface cell `cells` away (chessboard) leaves at least cells - 1 whole cells between.
  int cells;
  if ((brick & kBrickSurface) != kBrickSurface) cells = 4 * int(brick >> 2) - 3;
  else cells = int((cells_[cell_index(c[0], c[1], c[2])] >> 16) & 0xffu);
  return outside.norm() + float(std::max(0, cells - 1)) * cell_;
}

std::vector<std::uint8_t> SceneGrid::clearance() const {
  std::vector<std::uint8_t> out(codes_.size());
  std::size_t c = 0;
  for (int z = 0; z < dims_[2]; ++z)
    for (int y = 0; y < dims_[1]; ++y)
      for (int x = 0; x < dims_[0]; ++x) out[c++] = std::uint8_t(cells_[cell_index(x, y, z)] >> 16);
  return out;
}

std::uint32_t SceneGrid::max_box() const {
  std::uint32_t m = 0;
  for (std::uint32_t b : list_boxes_) m = std::max(m, b);
  return m;
}

namespace {
constexpr std::uint32_t kGridMagic = 0x52474248;  // "HBGR"
constexpr std::uint32_t kGridVersion = 1;
template <class T> void put(std::vector<std::uint8_t>& out, const T& v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof(T));
}
} // namespace

std::vector<std::uint8_t> SceneGrid::serialize() const {
  std::vector<std::uint8_t> out;
  put(out, kGridMagic);
  put(out, kGridVersion);
  for (int k = 0; k < 3; ++k) put(out, origin_[k]);
  put(out, cell_);
  for (int k = 0; k < 3; ++k) put(out, std::int32_t(dims_[k]));
  put(out, std::uint32_t(list_offsets_.size()));
  put(out, std::uint32_t(list_boxes_.size()));
  const auto* c = reinterpret_cast<const std::uint8_t*>(codes_.data());
  out.insert(out.end(), c, c + codes_.size() * 2);
  const auto* o = reinterpret_cast<const std::uint8_t*>(list_offsets_.data());
  out.insert(out.end(), o, o + list_offsets_.size() * 4);
  const auto* b = reinterpret_cast<const std::uint8_t*>(list_boxes_.data());
  out.insert(out.end(), b, b + list_boxes_.size() * 4);
  return out;
}

SceneGrid SceneGrid::deserialize(const std::uint8_t* data, std::size_t bytes) {
  std::size_t pos = 0;
  auto get = [&](auto& v) {
    if (bytes - pos < sizeof(v)) throw InvalidInput("scene grid: truncated");
    std::memcpy(&v, data + pos, sizeof(v));
    pos += sizeof(v);
  };
  std::uint32_t magic = 0, version = 0, offsets = 0, boxes = 0;
  get(magic);
  get(version);
  if (magic != kGridMagic) throw InvalidInput("scene grid: bad magic");
  if (version != kGridVersion) throw InvalidInput("scene grid: unsupported version " + std::to_string(version));
  Vec3 origin;
  float cell = 0.f;
  std::array<int, 3> dims{};
  for (int k = 0; k < 3; ++k) get(origin[k]);
  get(cell);
  for (int k = 0; k < 3; ++k) {
    std::int32_t d = 0;
    get(d);
    if (d < 1 || d > (1 << 16)) throw InvalidInput("scene grid: dimension " + std::to_string(d) + " out of range");
    dims[k] = d;
  }
  get(offsets);
  get(boxes);
  const std::size_t cells = std::size_t(dims[0]) * std::size_t(dims[1]) * std::size_t(dims[2]);
  if (cells > (std::size_t(1) << 30) || (bytes - pos) / 2 < cells) throw InvalidInput("scene grid: truncated");
  const std::size_t need = cells * 2 + (std::size_t(offsets) + std::size_t(boxes)) * 4;
  if (bytes - pos != need) throw InvalidInput("scene grid: " + std::to_string(bytes) + " bytes, expected " + std::to_string(pos + need));
  std::vector<std::uint16_t> codes(cells);
  std::memcpy(codes.data(), data + pos, cells * 2);
  pos += cells * 2;
  std::vector<std::uint32_t> list_offsets(offsets), list_boxes(boxes);
  if (offsets) std::memcpy(list_offsets.data(), data + pos, std::size_t(offsets) * 4);
  pos += std::size_t(offsets) * 4;
  if (boxes) std::memcpy(list_boxes.data(), data + pos, std::size_t(boxes) * 4);
  return SceneGrid(origin, cell, dims, std::move(codes), std::move(list_offsets), std::move(list_boxes));
}

} // namespace hb
