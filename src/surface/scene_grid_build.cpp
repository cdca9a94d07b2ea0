// Building a scene grid (build_scene_grid, scene_grid.h).
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
#include "surface/scene_grid.h"
#include "errors.h"
#include "exact/embree_scene.h"
#include "geometry/triangle_box.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <map>
#include <mutex>

namespace hb {
namespace {

// The boxes holding each triangle: holders[start[t], start[t + 1]) (CSR).
struct TriangleHolders {
  std::vector<std::uint32_t> start, holders;
};

TriangleHolders triangle_holders(std::size_t tcount, const std::vector<std::vector<std::uint32_t>>& box_triangles) {
  TriangleHolders h;
  std::vector<std::uint32_t>& start = h.start;
  start.assign(tcount + 1, 0);
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
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  h.holders.resize(start.back());
  for (std::uint32_t b = 0; b < box_triangles.size(); ++b) {
    if (box_triangles[b].empty()) {
      for (std::size_t t = 0; t < tcount; ++t) h.holders[fill[t]++] = b;
      continue;
    }
    for (std::uint32_t t : box_triangles[b]) h.holders[fill[t]++] = b;
  }
  return h;
}

// Step 1: where the cells are.
struct GridFrame {
  Vec3 origin;
  float cell = 0.f;
  float diagonal = 0.f;  // of the mesh bounds (at least 1e-20)
  std::array<int, 3> dims{};
  std::size_t nx = 0, ny = 0, nz = 0, cells = 0;
  std::size_t index(int x, int y, int z) const { return (std::size_t(z) * ny + std::size_t(y)) * nx + std::size_t(x); }
  bool contains(int x, int y, int z) const { return x >= 0 && y >= 0 && z >= 0 && x < dims[0] && y < dims[1] && z < dims[2]; }
};

GridFrame grid_frame(const Bounds& bounds, const SceneGridOptions& options) {
  GridFrame f;
  f.diagonal = std::max(bounds.diagonal(), 1e-20f);
  float cell = options.cell * f.diagonal;
  std::array<int, 3>& dims = f.dims;
  for (;;) {
    std::size_t cells = 1;
    for (int k = 0; k < 3; ++k) {
      dims[k] = int(std::ceil((bounds.max[k] - bounds.min[k]) / cell)) + 2;
      cells *= std::size_t(dims[k]);
    }
    if (cells <= options.max_cells && dims[0] <= (1 << 16) && dims[1] <= (1 << 16) && dims[2] <= (1 << 16)) break;
    cell *= 1.25f;
  }
  f.cell = cell;
  f.origin = bounds.min - Vec3::Constant(cell);
  f.nx = std::size_t(dims[0]), f.ny = std::size_t(dims[1]), f.nz = std::size_t(dims[2]);
  f.cells = f.nx * f.ny * f.nz;
  return f;
}

// Step 2's counts: per cell the number of triangles meeting it (key cell << 32 | kTotalKey),
// and per box how many of them the box's list holds (key cell << 32 | box); sorted by key,
// one entry a key.
constexpr std::uint32_t kTotalKey = 0xffffffffu;
struct CellBoxCount {
  std::uint64_t key;
  std::uint32_t count;
};

// The (cell, box) keys of triangles [first, last), counted: runs of equal keys.
std::vector<CellBoxCount> count_block(const TriangleMesh& mesh, const GridFrame& f, const TriangleHolders& h,
                                      std::size_t first, std::size_t last) {
  const float half = 0.5f * f.cell * (1.f + 1e-4f);  // a hair larger: a triangle on a cell face counts for both
  std::vector<std::uint64_t> local;
  for (std::size_t t = first; t != last; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3& a = mesh.positions[tri[0]];
    const Vec3& b = mesh.positions[tri[1]];
    const Vec3& c = mesh.positions[tri[2]];
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      const float mn = std::min({a[k], b[k], c[k]}), mx = std::max({a[k], b[k], c[k]});
      lo[k] = std::max(0, int(std::floor((mn - f.origin[k]) / f.cell - 1e-3f)));
      hi[k] = std::min(f.dims[k] - 1, int(std::floor((mx - f.origin[k]) / f.cell + 1e-3f)));
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const Vec3 centre = f.origin + f.cell * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
          if (!triangle_meets_box(a, b, c, centre, half)) continue;
          const std::uint64_t ci = f.index(x, y, z);
          local.push_back(ci << 32 | kTotalKey);
          for (std::uint32_t k = h.start[t]; k < h.start[t + 1]; ++k) local.push_back(ci << 32 | h.holders[k]);
        }
  }
  std::sort(local.begin(), local.end());
  std::vector<CellBoxCount> runs;
  for (std::size_t i = 0; i < local.size();) {
    std::size_t j = i;
    while (j < local.size() && local[j] == local[i]) ++j;
    runs.push_back({local[i], std::uint32_t(j - i)});
    i = j;
  }
  return runs;
}

std::vector<CellBoxCount> count_cell_boxes(const TriangleMesh& mesh, const GridFrame& f, const TriangleHolders& h) {
  std::vector<CellBoxCount> counts;
  std::mutex counts_mutex;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangle_count(), 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    const std::vector<CellBoxCount> runs = count_block(mesh, f, h, r.begin(), r.end());
    std::lock_guard<std::mutex> lock(counts_mutex);
    counts.insert(counts.end(), runs.begin(), runs.end());
  });
  // Equal keys (one cell and box from several blocks) are summed below: any order of them gives the same counts.
  tbb::parallel_sort(counts.begin(), counts.end(), [](const CellBoxCount& x, const CellBoxCount& y) { return x.key < y.key; });
  std::size_t w = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (w > 0 && counts[w - 1].key == counts[i].key) counts[w - 1].count += counts[i].count;
    else counts[w++] = counts[i];
  }
  counts.resize(w);
  return counts;
}

// Per surface cell its run in the counts (boxes ascending, the total last).
struct CellRuns {
  const std::vector<CellBoxCount>& counts;
  std::vector<std::uint32_t> run_of;  // per cell: its run, kTotalKey for none
  std::vector<std::uint32_t> run_start;

  CellRuns(const std::vector<CellBoxCount>& c, std::size_t cells) : counts(c), run_of(cells, kTotalKey) {
    for (std::size_t i = 0; i < counts.size(); ++i)
      if (i == 0 || (counts[i].key >> 32) != (counts[i - 1].key >> 32)) {
        run_of[counts[i].key >> 32] = std::uint32_t(run_start.size());
        run_start.push_back(std::uint32_t(i));
      }
    run_start.push_back(std::uint32_t(counts.size()));
  }
  std::vector<CellBoxCount>::const_iterator begin(std::size_t ci) const { return counts.begin() + run_start[run_of[ci]]; }
  std::vector<CellBoxCount>::const_iterator end(std::size_t ci) const { return counts.begin() + run_start[run_of[ci] + 1]; }
};

// The share of the triangle-cell overlaps in the 3 x 3 x 3 cells around (x, y, z) that `box` holds.
double held_share(const CellRuns& runs, const GridFrame& f, int x, int y, int z, std::uint32_t box) {
  double held = 0.0, all = 0.0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int qx = x + dx, qy = y + dy, qz = z + dz;
        if (!f.contains(qx, qy, qz)) continue;
        const std::size_t qi = f.index(qx, qy, qz);
        if (runs.run_of[qi] == kTotalKey) continue;
        const auto qlast = runs.end(qi);
        all += double((qlast - 1)->count);
        for (auto q = runs.begin(qi); q + 1 < qlast; ++q)
          if (std::uint32_t(q->key) == box) held += double(q->count);
      }
  return all > 0.0 ? held / all : 0.0;
}

// The boxes surface cell run r lists: among the boxes holding every triangle that meets the
// cell, the one holding the largest share of the triangle-cell overlaps around it (deepest
// inside its piece, farthest from its cut: a box sees its own surface best away from the
// seams it was cut at). No such box: every box with a triangle there.
void boxes_of_cell(const CellRuns& runs, std::size_t r, const GridFrame& f, std::vector<std::uint32_t>& list) {
  const auto first = runs.counts.begin() + runs.run_start[r], last = runs.counts.begin() + runs.run_start[r + 1];
  const std::size_t ci = first->key >> 32;
  const std::uint32_t total = (last - 1)->count;
  list.clear();
  const int x = int(ci % f.nx), y = int((ci / f.nx) % f.ny), z = int(ci / (f.nx * f.ny));
  double best_score = -1.0;
  std::uint32_t best_box = 0;
  for (auto it = first; it + 1 < last; ++it) {
    if (it->count != total) continue;
    const std::uint32_t box = std::uint32_t(it->key);
    const double score = held_share(runs, f, x, y, z, box);
    if (score > best_score) best_score = score, best_box = box;
  }
  if (best_score >= 0.0) list.push_back(best_box);
  else
    for (auto it = first; it + 1 < last; ++it) list.push_back(std::uint32_t(it->key));
}

// The codes and box lists of the grid (step 2's routing; every cell without surface kUnknown
// until step 3).
struct GridCodes {
  std::vector<std::uint16_t> codes;
  std::vector<std::uint32_t> list_offsets{0}, list_boxes;
};

// False when the scene needs more than SceneGrid::kMaxLists distinct lists.
bool route_surface_cells(const std::vector<CellBoxCount>& counts, const GridFrame& f, GridCodes& out) {
  const CellRuns runs(counts, f.cells);
  out.codes.assign(f.cells, SceneGrid::kUnknown);
  std::map<std::vector<std::uint32_t>, std::uint16_t> list_code;
  std::vector<std::uint32_t> list;
  for (std::size_t r = 0; r + 1 < runs.run_start.size(); ++r) {
    boxes_of_cell(runs, r, f, list);
    auto found = list_code.find(list);
    if (found == list_code.end()) {
      if (list_code.size() >= SceneGrid::kMaxLists) return false;
      found = list_code.emplace(list, std::uint16_t(SceneGrid::kFirstSurface + list_code.size())).first;
      out.list_boxes.insert(out.list_boxes.end(), list.begin(), list.end());
      out.list_offsets.push_back(std::uint32_t(out.list_boxes.size()));
    }
    out.codes[counts[runs.run_start[r]].key >> 32] = found->second;
  }
  return true;
}

// Step 3: each 6-connected region of cells without surface takes the state the 6 axis rays
// from its first cell's centre give.
void classify_empty_regions(const EmbreeScene& scene, const GridFrame& f, std::vector<std::uint16_t>& codes) {
  const Vec3 dirs[6] = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(0, 0, -1)};
  std::vector<std::uint8_t> seen(f.cells, 0);
  std::vector<std::size_t> stack;
  const float far = 4.f * f.diagonal;
  const std::size_t nx = f.nx, ny = f.ny;
  for (std::size_t seed = 0; seed < f.cells; ++seed) {
    if (seen[seed] || codes[seed] >= SceneGrid::kFirstSurface) continue;
    const int sx = int(seed % nx), sy = int((seed / nx) % ny), sz = int(seed / (nx * ny));
    const Vec3 p = f.origin + f.cell * Vec3(float(sx) + 0.5f, float(sy) + 0.5f, float(sz) + 0.5f);
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
        if (!f.contains(q[0], q[1], q[2])) continue;
        const std::size_t qi = f.index(q[0], q[1], q[2]);
        if (seen[qi] || codes[qi] >= SceneGrid::kFirstSurface) continue;
        seen[qi] = 1;
        stack.push_back(qi);
      }
    }
  }
}

} // namespace

SceneGrid build_scene_grid(const TriangleMesh& mesh, const std::vector<std::vector<std::uint32_t>>& box_triangles,
                           const SceneGridOptions& options, const EmbreeScene* given_scene) {
  if (mesh.triangle_count() == 0) throw InvalidInput("scene grid: mesh has no triangles");
  if (box_triangles.empty()) throw InvalidInput("scene grid: no boxes");
  if (!(options.cell > 0.f && options.cell <= 1.f)) throw InvalidInput("scene grid: cell must be in (0, 1]");
  if (options.max_cells < 1) throw InvalidInput("scene grid: max_cells must be >= 1");
  const TriangleHolders holders = triangle_holders(mesh.triangle_count(), box_triangles);
  const GridFrame frame = grid_frame(mesh.bounds(), options);
  GridCodes grid;
  if (!route_surface_cells(count_cell_boxes(mesh, frame, holders), frame, grid)) return SceneGrid{};
  std::unique_ptr<const EmbreeScene> own_scene;
  if (!given_scene) own_scene = std::make_unique<const EmbreeScene>(mesh);
  classify_empty_regions(given_scene ? *given_scene : *own_scene, frame, grid.codes);
  return SceneGrid(frame.origin, frame.cell, frame.dims, std::move(grid.codes), std::move(grid.list_offsets),
                   std::move(grid.list_boxes));
}

} // namespace hb
