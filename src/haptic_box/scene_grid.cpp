// Scene grid (see scene_grid.h).
//  1. Cells: cubes of SceneGridOptions::cell x the mesh diagonal over the mesh bounds plus
//     one cell on every side (the padding keeps the outside connected).
//  2. Surface cells: each triangle is tested against the cells its bounds cover with the
//     separating-axis triangle-box test (13 axes); a cell counts the triangles that meet it
//     and, per box, how many of them the box's list holds (chunks of triangles over all
//     cores, TBB). A cell is routed to one box: of the boxes holding all its triangles, the
//     one holding the largest share of the triangles around it (3 x 3 x 3 cells), i.e. the
//     box whose piece goes on furthest around the cell, away from the cut it was baked with
//     (pieces overlap at seams, so at a seam both boxes hold the cell). When no box holds
//     all of a cell's triangles, the cell lists every box holding one. Equal lists share
//     one code.
//  3. Cells without surface: 6-connected regions of them are labelled by flood fill; one
//     cell centre of each region (at least half a cell from any triangle) casts 6 axis rays
//     against the whole mesh (Embree). A point is inside a closed mesh exactly when a ray's
//     first hit is a back face, so all 6 agreeing gives the region's state; disagreeing rays
//     (open meshes, holes) leave it kUnknown, and the scene then asks its boxes instead.
#include "haptic_box/scene_grid.h"
#include "errors.h"
#include "exact/embree_scene.h"
#include "geometry/cell_dda.h"
#include "geometry/triangle_box.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <cstring>
#include <limits>
#include <map>
#include <mutex>

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

SceneGrid build_scene_grid(const TriangleMesh& mesh, const std::vector<std::vector<std::uint32_t>>& box_triangles,
                           const SceneGridOptions& options, const EmbreeScene* given_scene) {
  if (mesh.triangle_count() == 0) throw InvalidInput("scene grid: mesh has no triangles");
  if (box_triangles.empty()) throw InvalidInput("scene grid: no boxes");
  if (!(options.cell > 0.f && options.cell <= 1.f)) throw InvalidInput("scene grid: cell must be in (0, 1]");
  if (options.max_cells < 1) throw InvalidInput("scene grid: max_cells must be >= 1");
  const std::size_t tcount = mesh.triangle_count();
  // Boxes holding each triangle (CSR).
  std::vector<std::uint32_t> start(tcount + 1, 0);
  for (const auto& list : box_triangles) {
    if (list.empty()) {
      for (std::size_t t = 0; t < tcount; ++t) ++start[t + 1];
      continue;
    }
    for (std::uint32_t t : list) {
      if (t >= tcount) throw InvalidInput("scene grid: triangle " + std::to_string(t) + " beyond the mesh's " + std::to_string(tcount));
      ++start[t + 1];
    }
  }
  for (std::size_t t = 0; t < tcount; ++t) start[t + 1] += start[t];
  std::vector<std::uint32_t> holders(start.back()), fill(start.begin(), start.end() - 1);
  for (std::uint32_t b = 0; b < box_triangles.size(); ++b) {
    if (box_triangles[b].empty()) {
      for (std::size_t t = 0; t < tcount; ++t) holders[fill[t]++] = b;
      continue;
    }
    for (std::uint32_t t : box_triangles[b]) holders[fill[t]++] = b;
  }

  // 1. Cells.
  const Bounds bounds = mesh.bounds();
  const float diagonal = std::max(bounds.diagonal(), 1e-20f);
  float cell = options.cell * diagonal;
  std::array<int, 3> dims{};
  for (;;) {
    std::size_t cells = 1;
    for (int k = 0; k < 3; ++k) {
      dims[k] = int(std::ceil((bounds.max[k] - bounds.min[k]) / cell)) + 2;
      cells *= std::size_t(dims[k]);
    }
    if (cells <= options.max_cells && dims[0] <= (1 << 16) && dims[1] <= (1 << 16) && dims[2] <= (1 << 16)) break;
    cell *= 1.25f;
  }
  const Vec3 origin = bounds.min - Vec3::Constant(cell);
  const std::size_t nx = std::size_t(dims[0]), ny = std::size_t(dims[1]), nz = std::size_t(dims[2]);
  const std::size_t cells = nx * ny * nz;
  auto cell_index = [&](int x, int y, int z) { return (std::size_t(z) * ny + std::size_t(y)) * nx + std::size_t(x); };

  // 2. Surface cells: per cell the number of triangles meeting it, and per box how many of
  //    them it holds (keys cell << 32 | box, and cell << 32 | kTotal for the count).
  constexpr std::uint32_t kTotal = 0xffffffffu;
  struct Count {
    std::uint64_t key;
    std::uint32_t count;
  };
  std::vector<Count> counts;
  std::mutex counts_mutex;
  const float half = 0.5f * cell * (1.f + 1e-4f);  // a hair larger: a triangle on a cell face counts for both
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tcount, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    std::vector<std::uint64_t> local;
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      const Vec3& a = mesh.positions[tri[0]];
      const Vec3& b = mesh.positions[tri[1]];
      const Vec3& c = mesh.positions[tri[2]];
      int lo[3], hi[3];
      for (int k = 0; k < 3; ++k) {
        const float mn = std::min({a[k], b[k], c[k]}), mx = std::max({a[k], b[k], c[k]});
        lo[k] = std::max(0, int(std::floor((mn - origin[k]) / cell - 1e-3f)));
        hi[k] = std::min(dims[k] - 1, int(std::floor((mx - origin[k]) / cell + 1e-3f)));
      }
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            const Vec3 centre = origin + cell * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
            if (!triangle_meets_box(a, b, c, centre, half)) continue;
            const std::uint64_t ci = cell_index(x, y, z);
            local.push_back(ci << 32 | kTotal);
            for (std::uint32_t h = start[t]; h < start[t + 1]; ++h) local.push_back(ci << 32 | holders[h]);
          }
    }
    std::sort(local.begin(), local.end());
    std::vector<Count> runs;
    for (std::size_t i = 0; i < local.size();) {
      std::size_t j = i;
      while (j < local.size() && local[j] == local[i]) ++j;
      runs.push_back({local[i], std::uint32_t(j - i)});
      i = j;
    }
    std::lock_guard<std::mutex> lock(counts_mutex);
    counts.insert(counts.end(), runs.begin(), runs.end());
  });
  // Equal keys (one cell and box from several blocks) are summed below: any order of them gives the same counts.
  tbb::parallel_sort(counts.begin(), counts.end(), [](const Count& x, const Count& y) { return x.key < y.key; });
  {
    std::size_t w = 0;
    for (std::size_t i = 0; i < counts.size(); ++i) {
      if (w > 0 && counts[w - 1].key == counts[i].key) counts[w - 1].count += counts[i].count;
      else counts[w++] = counts[i];
    }
    counts.resize(w);
  }
  // Per surface cell its run in `counts` (boxes ascending, the total last).
  std::vector<std::uint32_t> run_of(cells, kTotal);
  std::vector<std::uint32_t> run_start;
  for (std::size_t i = 0; i < counts.size(); ++i)
    if (i == 0 || (counts[i].key >> 32) != (counts[i - 1].key >> 32)) {
      run_of[counts[i].key >> 32] = std::uint32_t(run_start.size());
      run_start.push_back(std::uint32_t(i));
    }
  run_start.push_back(std::uint32_t(counts.size()));
  auto run_begin = [&](std::size_t ci) { return counts.begin() + run_start[run_of[ci]]; };
  auto run_end = [&](std::size_t ci) { return counts.begin() + run_start[run_of[ci] + 1]; };
  // The box a surface cell is routed to: among the boxes holding every triangle that meets
  // the cell, the one holding the largest share of the triangle-cell overlaps in the 3 x 3 x
  // 3 cells around it (deepest inside its piece, farthest from its cut: a box sees its own
  // surface best away from the seams it was cut at). No such box: every box with a triangle
  // there.
  std::vector<std::uint16_t> codes(cells, SceneGrid::kUnknown);
  std::vector<std::uint32_t> list_offsets{0}, list_boxes;
  std::map<std::vector<std::uint32_t>, std::uint16_t> list_code;
  std::vector<std::uint32_t> list;
  for (std::size_t r = 0; r + 1 < run_start.size(); ++r) {
    const auto first = counts.begin() + run_start[r], last = counts.begin() + run_start[r + 1];
    const std::size_t ci = first->key >> 32;
    const std::uint32_t total = (last - 1)->count;
    list.clear();
    const int x = int(ci % nx), y = int((ci / nx) % ny), z = int(ci / (nx * ny));
    double best_score = -1.0;
    std::uint32_t best_box = 0;
    for (auto it = first; it + 1 < last; ++it) {
      if (it->count != total) continue;
      const std::uint32_t box = std::uint32_t(it->key);
      double held = 0.0, all = 0.0;
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int qx = x + dx, qy = y + dy, qz = z + dz;
            if (qx < 0 || qy < 0 || qz < 0 || qx >= dims[0] || qy >= dims[1] || qz >= dims[2]) continue;
            const std::size_t qi = cell_index(qx, qy, qz);
            if (run_of[qi] == kTotal) continue;
            const auto qlast = run_end(qi);
            all += double((qlast - 1)->count);
            for (auto q = run_begin(qi); q + 1 < qlast; ++q)
              if (std::uint32_t(q->key) == box) held += double(q->count);
          }
      const double score = all > 0.0 ? held / all : 0.0;
      if (score > best_score) best_score = score, best_box = box;
    }
    if (best_score >= 0.0) list.push_back(best_box);
    else
      for (auto it = first; it + 1 < last; ++it) list.push_back(std::uint32_t(it->key));
    auto found = list_code.find(list);
    if (found == list_code.end()) {
      if (list_code.size() >= SceneGrid::kMaxLists) return SceneGrid{};
      found = list_code.emplace(list, std::uint16_t(SceneGrid::kFirstSurface + list_code.size())).first;
      list_boxes.insert(list_boxes.end(), list.begin(), list.end());
      list_offsets.push_back(std::uint32_t(list_boxes.size()));
    }
    codes[ci] = found->second;
  }

  // 3. Regions without surface, one state each.
  std::unique_ptr<const EmbreeScene> own_scene;
  if (!given_scene) own_scene = std::make_unique<const EmbreeScene>(mesh);
  const EmbreeScene& scene = given_scene ? *given_scene : *own_scene;
  const Vec3 dirs[6] = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  std::vector<std::uint8_t> seen(cells, 0);
  std::vector<std::size_t> stack;
  const float far = 4.f * diagonal;
  for (std::size_t seed = 0; seed < cells; ++seed) {
    if (seen[seed] || codes[seed] >= SceneGrid::kFirstSurface) continue;
    const int sx = int(seed % nx), sy = int((seed / nx) % ny), sz = int(seed / (nx * ny));
    const Vec3 p = origin + cell * Vec3(float(sx) + 0.5f, float(sy) + 0.5f, float(sz) + 0.5f);
    int back = 0, other = 0;
    for (const Vec3& d : dirs) {
      const RayHit hit = scene.intersect(p, d, 0.f, far);
      (hit.hit && hit.back_face ? back : other) += 1;
    }
    const std::uint16_t state = back == 6 ? SceneGrid::kInside : other == 6 ? SceneGrid::kOutside : SceneGrid::kUnknown;
    stack.assign(1, seed);
    seen[seed] = 1;
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      codes[c] = state;
      const int x = int(c % nx), y = int((c / nx) % ny), z = int(c / (nx * ny));
      const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z}, {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& q : nb) {
        if (q[0] < 0 || q[1] < 0 || q[2] < 0 || q[0] >= dims[0] || q[1] >= dims[1] || q[2] >= dims[2]) continue;
        const std::size_t qi = cell_index(q[0], q[1], q[2]);
        if (seen[qi] || codes[qi] >= SceneGrid::kFirstSurface) continue;
        seen[qi] = 1;
        stack.push_back(qi);
      }
    }
  }
  return SceneGrid(origin, cell, dims, std::move(codes), std::move(list_offsets), std::move(list_boxes));
}

} // namespace hb

namespace hb {

SurfaceCells::SurfaceCells(const SceneGrid& grid, std::shared_ptr<const SurfaceTriangles> surface)
    : origin_(grid.origin()), cell_(grid.cell()), inv_cell_(1.f / grid.cell()), dims_(grid.dims()),
      surface_(std::move(surface)) {
  if (grid.empty() || !surface_) throw InvalidInput("surface cells: no grid or no surface");
  const int nx = dims_[0], ny = dims_[1], nz = dims_[2];
  const std::vector<std::uint16_t>& codes = grid.codes();
  const auto flat = [&](int x, int y, int z) {
    return (std::size_t(z) * std::size_t(ny) + std::size_t(y)) * std::size_t(nx) + std::size_t(x);
  };
  // 1. Surface cells, ranked per brick.
  bricks_x_ = (nx + 3) / 4;
  bricks_y_ = (ny + 3) / 4;
  const int bricks_z = bricks_z_ = (nz + 3) / 4;
  const std::size_t brick_count = std::size_t(bricks_x_) * std::size_t(bricks_y_) * std::size_t(bricks_z);
  masks_.assign(brick_count, 0);
  base_.assign(brick_count, 0);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        if (codes[flat(x, y, z)] >= SceneGrid::kFirstSurface) {
          const std::size_t b = (std::size_t(z >> 2) * std::size_t(bricks_y_) + std::size_t(y >> 2)) * std::size_t(bricks_x_) +
                                std::size_t(x >> 2);
          masks_[b] |= std::uint64_t(1) << (((z & 3) << 4) | ((y & 3) << 2) | (x & 3));
        }
  {
    // The chessboard clearance of each cell, in the masks' order (a byte a cell, for
    // first_crossing_along's jumps over empty space).
    const std::vector<std::uint8_t> clear = grid.clearance();
    clear_.assign(brick_count * 64, 0);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
          const std::size_t b = (std::size_t(z >> 2) * std::size_t(bricks_y_) + std::size_t(y >> 2)) * std::size_t(bricks_x_) +
                                std::size_t(x >> 2);
          clear_[b * 64 + (((z & 3) << 4) | ((y & 3) << 2) | (x & 3))] = clear[flat(x, y, z)];
        }
  }
  std::uint32_t total = 0;
  for (std::size_t b = 0; b < brick_count; ++b) {
    base_[b] = total;
    total += std::uint32_t(__builtin_popcountll(masks_[b]));
  }
  // 2. The triangles meeting each surface cell: the grid's test (the same padded half), on
  //    the records' vertices. A triangle meeting a cell the grid has without surface (a
  //    surface other than the grid's mesh) is left out there.
  const SurfaceTriangles& surf = *surface_;
  const float half = 0.5f * cell_ * (1.f + 1e-4f);
  std::vector<std::uint64_t> pairs;  // cell index << 32 | slot: unique, so sorted they are in one order
  std::mutex pairs_mutex;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, surf.size(), 8192), [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<std::uint64_t> local;
    for (std::size_t t = range.begin(); t != range.end(); ++t) {
      const SurfaceTriangles::Record& r = surf.records()[t];
      const Vec3 a(r.a[0], r.a[1], r.a[2]);
      const Vec3 b = a + Vec3(r.e1[0], r.e1[1], r.e1[2]), c = a + Vec3(r.e2[0], r.e2[1], r.e2[2]);
      if (!a.allFinite() || !b.allFinite() || !c.allFinite()) continue;
      int lo[3], hi[3];
      bool outside = false;
      for (int k = 0; k < 3; ++k) {
        const float mn = std::min({a[k], b[k], c[k]}), mx = std::max({a[k], b[k], c[k]});
        lo[k] = std::max(0, int(std::floor((mn - origin_[k]) * inv_cell_ - 1e-3f)));
        hi[k] = std::min(dims_[k] - 1, int(std::floor((mx - origin_[k]) * inv_cell_ + 1e-3f)));
        outside |= lo[k] > hi[k];
      }
      if (outside) continue;
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            const std::uint32_t ci = index(x, y, z);
            if (ci == kNone) continue;
            const Vec3 centre = origin_ + cell_ * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
            if (triangle_meets_box(a, b, c, centre, half)) local.push_back(std::uint64_t(ci) << 32 | std::uint64_t(t));
          }
    }
    std::lock_guard<std::mutex> lock(pairs_mutex);
    pairs.insert(pairs.end(), local.begin(), local.end());
  });
  tbb::parallel_sort(pairs.begin(), pairs.end());
  offsets_.assign(std::size_t(total) + 1, 0);
  slots_.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ++offsets_[(pairs[k] >> 32) + 1];
    slots_[k] = std::uint32_t(pairs[k]);
  }
  for (std::size_t k = 0; k < total; ++k) offsets_[k + 1] += offsets_[k];
  // 3. Centre states in waves from the cells without surface. kPending: not decided yet.
  constexpr std::uint8_t kPending = 0xff;
  states_.assign(total, kPending);
  std::vector<std::array<int, 3>> cell_of(total);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const std::uint32_t ci = index(x, y, z);
        if (ci != kNone) cell_of[ci] = {x, y, z};
      }
  // 3a. Sub-cells for the cells listing many triangles (first_crossing_along).
  subcells_ = SurfaceSubcells(origin_, cell_, cell_of, offsets_, slots_, surf);
  // 3b. Each cell's slab: the area-weighted mean normal of its triangles (none when they
  //     cancel, as on two sheets facing away), their vertices' extent along it, cut to the
  //     cell's extent along it (the triangles' parts in the cell lie in both), widened by a
  //     thousandth of a cell for rounding.
  slabs_.assign(total, Slab{{0.f, 0.f, 1.f}, -std::numeric_limits<float>::infinity(),
                            std::numeric_limits<float>::infinity()});
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, total, 1024), [&](const tbb::blocked_range<std::uint32_t>& range) {
    for (std::uint32_t ci = range.begin(); ci != range.end(); ++ci) {
      Vec3 sum = Vec3::Zero();
      float area = 0.f;
      for (std::uint32_t k = offsets_[ci]; k < offsets_[ci + 1]; ++k) {
        const SurfaceTriangles::Record& r = surf.records()[slots_[k]];
        const Vec3 g = Vec3(r.e1[0], r.e1[1], r.e1[2]).cross(Vec3(r.e2[0], r.e2[1], r.e2[2]));
        sum += g;
        area += g.norm();
      }
      const float len = sum.norm();
      if (!(len > 0.5f * area) || !std::isfinite(len) || !(area > 0.f)) continue;  // no one side
      const Vec3 n = sum / len;
      float lo = std::numeric_limits<float>::infinity(), hi = -lo;
      for (std::uint32_t k = offsets_[ci]; k < offsets_[ci + 1]; ++k) {
        const SurfaceTriangles::Record& r = surf.records()[slots_[k]];
        const Vec3 a(r.a[0], r.a[1], r.a[2]);
        for (const Vec3& v : {a, Vec3(a + Vec3(r.e1[0], r.e1[1], r.e1[2])), Vec3(a + Vec3(r.e2[0], r.e2[1], r.e2[2]))}) {
          const float dv = n.dot(v);
          lo = std::min(lo, dv);
          hi = std::max(hi, dv);
        }
      }
      const std::array<int, 3>& q = cell_of[ci];
      const Vec3 centre = origin_ + cell_ * Vec3(float(q[0]) + 0.5f, float(q[1]) + 0.5f, float(q[2]) + 0.5f);
      const float reach = 0.5f * cell_ * (std::fabs(n.x()) + std::fabs(n.y()) + std::fabs(n.z()));
      const float margin = 1e-3f * cell_;
      lo = std::max(lo, n.dot(centre) - reach) - margin;
      hi = std::min(hi, n.dot(centre) + reach) + margin;
      if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
      slabs_[ci] = Slab{{n.x(), n.y(), n.z()}, lo, hi};
    }
  });
  const auto centre_of = [&](int x, int y, int z) -> Vec3 {  // a Vec3, not an expression of a temporary
    return origin_ + cell_ * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
  };
  // The state a decided neighbour (x, y, z) gives cell ci's centre, or kUnknown.
  const auto vote = [&](std::uint32_t ci, int x, int y, int z, std::uint8_t neighbour_state) -> std::uint8_t {
    const std::array<int, 3>& q = cell_of[ci];
    const Vec3 from = centre_of(q[0], q[1], q[2]), to = centre_of(x, y, z);
    std::uint32_t cells[2] = {ci, index(x, y, z)};
    float s = 0.f;
    bool front = false;
    std::uint32_t tri = kNoTriangle;
    if (!first_crossing(cells, cells[1] == kNone ? 1 : 2, from, to, 1.f, s, front, tri)) return neighbour_state;
    return front ? SceneGrid::kOutside : SceneGrid::kInside;
  };
  std::vector<std::uint32_t> frontier;
  std::vector<std::pair<std::uint32_t, std::uint8_t>> decided;
  for (std::uint32_t ci = 0; ci < total; ++ci) frontier.push_back(ci);
  const int nb[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
  for (;;) {
    decided.clear();
    std::vector<std::uint32_t> rest;
    for (std::uint32_t ci : frontier) {
      const std::array<int, 3>& q = cell_of[ci];
      int votes = 0;
      std::uint8_t state = kPending;
      bool disagree = false;
      for (const auto& o : nb) {
        const int x = q[0] + o[0], y = q[1] + o[1], z = q[2] + o[2];
        if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) continue;
        const std::uint32_t qi = index(x, y, z);
        std::uint8_t known;
        if (qi == kNone) {
          const std::uint16_t code = codes[flat(x, y, z)];
          if (code != SceneGrid::kInside && code != SceneGrid::kOutside) continue;
          known = std::uint8_t(code);
        } else {
          known = states_[qi];
          if (known != SceneGrid::kInside && known != SceneGrid::kOutside) continue;
        }
        const std::uint8_t v = vote(ci, x, y, z, known);
        ++votes;
        if (state == kPending) state = v;
        else if (state != v) disagree = true;
      }
      if (votes == 0) rest.push_back(ci);
      else decided.emplace_back(ci, disagree ? std::uint8_t(SceneGrid::kUnknown) : state);
    }
    for (const auto& d : decided) states_[d.first] = d.second;
    if (decided.empty() || rest.empty()) {
      for (std::uint32_t ci : rest) states_[ci] = SceneGrid::kUnknown;
      break;
    }
    frontier.swap(rest);
  }
}

bool SurfaceCells::first_crossing(const std::uint32_t* cells, std::size_t count, const Vec3& a, const Vec3& b,
                                  float s_max, float& s, bool& front, std::uint32_t& triangle) const noexcept {
  const float o[3] = {a.x(), a.y(), a.z()};
  const float d[3] = {b.x() - a.x(), b.y() - a.y(), b.z() - a.z()};
  bool found = false;
  for (std::size_t k = 0; k < count; ++k) {
    if (cells[k] >= states_.size()) continue;
    float cs = 0.f;
    bool cf = false;
    std::uint32_t ct = kNoTriangle;
    const std::uint32_t* first = begin(cells[k]);
    if (!surface_->first_crossing(first, std::size_t(end(cells[k]) - first), o, d, 0.f, s_max, cs, cf, ct)) continue;
    if (!found || cs < s) s = cs, front = cf, triangle = ct, found = true;
  }
  return found;
}


bool SurfaceCells::walk_start(const Vec3& a, const Vec3& b, float s_max, WalkStart& w) const noexcept {
  // In cell units from the grid's origin.
  const Vec3 fa = (a - origin_) * inv_cell_, fd = (b - a) * inv_cell_;
  float s0 = 0.f, s1 = std::min(s_max, 1.f);
  for (int k = 0; k < 3; ++k) {
    const float hi = float(dims_[k]);
    if (std::fabs(fd[k]) < 1e-30f) {
      if (!(fa[k] >= 0.f && fa[k] <= hi)) return false;
      continue;
    }
    float u = (0.f - fa[k]) / fd[k], v = (hi - fa[k]) / fd[k];
    if (u > v) std::swap(u, v);
    s0 = std::max(s0, u);
    s1 = std::min(s1, v);
  }
  if (!(s0 <= s1)) return false;
  const float max_d = std::max({std::fabs(fd.x()), std::fabs(fd.y()), std::fabs(fd.z())});
  w.s_per_cell = max_d > 0.f ? 1.f / max_d : 2.f;
  w.s0 = s0;
  w.s1 = s1;
  for (int k = 0; k < 3; ++k) {
    w.o[k] = a[k];
    w.d[k] = b[k] - a[k];
    w.fa[k] = fa[k];
    w.fd[k] = fd[k];
    // The DDA's divisions done once: a jump restarts it at a new s.
    w.inv[k] = fd[k] > 1e-30f || fd[k] < -1e-30f ? 1.f / fd[k] : 0.f;
  }
  return true;
}

bool SurfaceCells::first_crossing_along(const Vec3& a, const Vec3& b, float s_max, float& s_out, bool& front_out,
                                        std::uint32_t& tri_out, float s_start, float* s_free) const noexcept {
  // A walk that meets no cell within a cell of the surface leaves the whole segment free.
  if (s_free) *s_free = 1.f;
  WalkStart w;
  if (masks_.empty() || !walk_start(a, b, s_max, w)) return false;
  const float s0 = std::max(w.s0, s_start), s1 = w.s1, s_per_cell = w.s_per_cell;
  if (s0 > s1) return false;
  const float *o = w.o, *d = w.d, *inv = w.inv, *fa3 = w.fa, *fd3 = w.fd;
  const Vec3 fa(fa3[0], fa3[1], fa3[2]), fd(fd3[0], fd3[1], fd3[2]);
  const int* n = dims_.data();
  CellDda dda(inv);
  float best = std::numeric_limits<float>::infinity();
  bool best_front = false;
  std::uint32_t best_id = kNoTriangle;
  float s = s0;
  dda.start(fa3, fd3, inv, s, n);
  const int limit = dims_[0] + dims_[1] + dims_[2];
  int it = 0;
  for (; it < limit; ++it) {
    if (s > best) break;  // a cell entered beyond the nearest crossing holds no nearer one
    const std::size_t brick = (std::size_t(dda.z >> 2) * std::size_t(bricks_y_) + std::size_t(dda.y >> 2)) *
                                  std::size_t(bricks_x_) + std::size_t(dda.x >> 2);
    const unsigned bit = unsigned(((dda.z & 3) << 4) | ((dda.y & 3) << 2) | (dda.x & 3));
    const int clear = clear_[brick * 64 + bit];
    if (s_free && clear < 2) {
      *s_free = s;
      s_free = nullptr;
    }
    if (clear >= 2) {
      // Every cell within clear - 1 of this one (chessboard) has no surface; the point is in
      // this cell, so moving it by less than clear - 1 cells in every axis keeps it, and the
      // part of the segment crossed, among them.
      const float jump = s + (float(clear - 1) - 0.01f) * s_per_cell;
      if (jump > s1) break;
      s = jump;
      dda.start(fa3, fd3, inv, s, n);
      continue;
    }
    // A surface cell (clearance 0 exactly there: both come from the grid's codes), unless
    // the segment passes its triangles by (its slab): then none is crossed here.
    const std::uint32_t index = clear == 0 ? base_[brick] + cells_below(masks_[brick], bit) : kNone;
    if (clear == 0 && slab_may_cross(index, o, d, s, std::min(dda.exit(), s1))) {
      const std::uint32_t begin = offsets_[index], count = offsets_[index + 1] - begin;
      const std::uint32_t crowded = subcells_.may_be_crowded(count) ? subcells_.crowded(index) : SurfaceSubcells::kNone;
      if (crowded != SurfaceSubcells::kNone) {
        // Only the sub-cells the segment passes in this cell.
        const int cell[3] = {dda.x, dda.y, dda.z};
        subcells_.first_crossing(crowded, cell, fa, fd, inv, s, std::min(dda.exit(), s1), s1, o, d, *surface_, best,
                                 best_front, best_id);
      } else {
        float cs = 0.f;
        bool cf = false;
        std::uint32_t ct = kNoTriangle;
        if (surface_->first_crossing(slots_.data() + begin, count, o, d, 0.f, std::min(best, s1), cs, cf, ct) &&
            cs < best)
          best = cs, best_front = cf, best_id = ct;
      }
    }
    bool inside = true;
    s = dda.step(n, inside);
    if (s > s1 || !inside) break;
  }
  if (s_free && it == limit) *s_free = std::min(*s_free, s);  // the walk stopped short: free only to there
  if (best_id == kNoTriangle) return false;
  s_out = best;
  front_out = best_front;
  tri_out = best_id;
  return true;
}

std::uint16_t SurfaceCells::state_at(const Vec3& p) const noexcept {
  const Vec3 f = (p - origin_) * inv_cell_;
  if (!(f.x() >= 0.f && f.y() >= 0.f && f.z() >= 0.f)) return SceneGrid::kUnknown;
  const int x = int(f.x()), y = int(f.y()), z = int(f.z());
  const std::uint32_t ci = index(x, y, z);
  if (ci == kNone) return SceneGrid::kUnknown;
  const std::uint16_t centre = states_[ci];
  if (centre != SceneGrid::kInside && centre != SceneGrid::kOutside) return SceneGrid::kUnknown;
  const Vec3 c = origin_ + cell_ * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
  float s = 0.f;
  bool front = false;
  std::uint32_t tri = kNoTriangle;
  if (!first_crossing(&ci, 1, p, c, 1.f, s, front, tri)) return centre;
  return front ? SceneGrid::kOutside : SceneGrid::kInside;
}

} // namespace hb
