// Surface cells (see surface_cells.h).
//  1. The grid's surface cells are ranked per 4 x 4 x 4 brick (a 64-bit mask and a base
//     index a brick); every cell's chessboard clearance is kept in the same order.
//  2. Each surface triangle is tested against the cells its bounds cover (the grid's
//     triangle-box test, in parallel); the pairs sorted give each cell's list of slots.
//  3. Crowded cells get sub-cells (SurfaceSubcells) and every cell a slab where its
//     triangles lie; the centres' states are decided in waves out from the cells without
//     surface.
//  4. Queries: the first crossing in given cells, along a segment (a DDA through the cells,
//     jumping by clearance, skipping cells whose slab the segment passes), and a point's state.
#include "surface/surface_cells.h"
#include "errors.h"
#include "geometry/cell_dda.h"
#include "geometry/triangle_box.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>
#include <cmath>
#include <limits>
#include <mutex>

namespace hb {

SurfaceCells::SurfaceCells(const SceneGrid& grid, std::shared_ptr<const SurfaceTriangles> surface)
    : origin_(grid.origin()), cell_(grid.cell()), inv_cell_(1.f / grid.cell()), dims_(grid.dims()),
      surface_(std::move(surface)) {
  if (grid.empty() || !surface_) throw InvalidInput("surface cells: no grid or no surface");
  const std::uint32_t total = rank_cells(grid);
  list_triangles(total);
  // 3. Centre states (below), after the sub-cells and slabs, which need each cell's place.
  const std::vector<std::array<int, 3>> cell_of = cell_coordinates(total);
  // 3a. Sub-cells for the cells listing many triangles (first_crossing_along).
  subcells_ = SurfaceSubcells(origin_, cell_, cell_of, offsets_, slots_, *surface_);
  fit_slabs(cell_of);
  decide_centre_states(grid.codes(), cell_of);
}

namespace {
// The index of cell (x, y, z) in an nx x ny grid, x fastest (the grid's codes()).
inline std::size_t flat_cell(int x, int y, int z, int nx, int ny) {
  return (std::size_t(z) * std::size_t(ny) + std::size_t(y)) * std::size_t(nx) + std::size_t(x);
}
} // namespace

// 1. Surface cells, ranked per brick, and every cell's chessboard clearance in the masks'
//    order (a byte a cell, for first_crossing_along's jumps over empty space). Returns the
//    number of surface cells.
std::uint32_t SurfaceCells::rank_cells(const SceneGrid& grid) {
  const int nx = dims_[0], ny = dims_[1], nz = dims_[2];
  const std::vector<std::uint16_t>& codes = grid.codes();
  bricks_x_ = (nx + 3) / 4;
  bricks_y_ = (ny + 3) / 4;
  const int bricks_z = bricks_z_ = (nz + 3) / 4;
  const std::size_t brick_count = std::size_t(bricks_x_) * std::size_t(bricks_y_) * std::size_t(bricks_z);
  const auto brick_of = [&](int x, int y, int z) {
    return (std::size_t(z >> 2) * std::size_t(bricks_y_) + std::size_t(y >> 2)) * std::size_t(bricks_x_) + std::size_t(x >> 2);
  };
  masks_.assign(brick_count, 0);
  base_.assign(brick_count, 0);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        if (codes[flat_cell(x, y, z, nx, ny)] >= SceneGrid::kFirstSurface)
          masks_[brick_of(x, y, z)] |= std::uint64_t(1) << (((z & 3) << 4) | ((y & 3) << 2) | (x & 3));
  const std::vector<std::uint8_t> clear = grid.clearance();
  clear_.assign(brick_count * 64, 0);
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        clear_[brick_of(x, y, z) * 64 + (((z & 3) << 4) | ((y & 3) << 2) | (x & 3))] = clear[flat_cell(x, y, z, nx, ny)];
  std::uint32_t total = 0;
  for (std::size_t b = 0; b < brick_count; ++b) {
    base_[b] = total;
    total += std::uint32_t(__builtin_popcountll(masks_[b]));
  }
  return total;
}

// 2. The triangles meeting each surface cell: the grid's test (the same padded half), on the
//    records' vertices. A triangle meeting a cell the grid has without surface (a surface
//    other than the grid's mesh) is left out there.
void SurfaceCells::list_triangles(std::uint32_t total) {
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
        // Cut to the grid before the conversion (a damaged file's 1e31 is no int).
        const auto cell_at = [&](float f) { return int(std::floor(std::clamp(f, -2.f, float(dims_[k]) + 1.f))); };
        lo[k] = std::max(0, cell_at((mn - origin_[k]) * inv_cell_ - 1e-3f));
        hi[k] = std::min(dims_[k] - 1, cell_at((mx - origin_[k]) * inv_cell_ + 1e-3f));
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
}

// Each surface cell's grid coordinates.
std::vector<std::array<int, 3>> SurfaceCells::cell_coordinates(std::uint32_t total) const {
  std::vector<std::array<int, 3>> cell_of(total);
  for (int z = 0; z < dims_[2]; ++z)
    for (int y = 0; y < dims_[1]; ++y)
      for (int x = 0; x < dims_[0]; ++x) {
        const std::uint32_t ci = index(x, y, z);
        if (ci != kNone) cell_of[ci] = {x, y, z};
      }
  return cell_of;
}

// 3b. Each cell's slab: the area-weighted mean normal of its triangles (none when they
//     cancel, as on two sheets facing away), their vertices' extent along it, cut to the
//     cell's extent along it (the triangles' parts in the cell lie in both), widened by a
//     thousandth of a cell for rounding.
void SurfaceCells::fit_slabs(const std::vector<std::array<int, 3>>& cell_of) {
  const SurfaceTriangles& surf = *surface_;
  const std::uint32_t total = std::uint32_t(cell_of.size());
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
}

// 3. Centre states in waves from the cells without surface: each undecided cell next to a
//    decided one (or to a grid cell without surface) takes the state its decided neighbours'
//    votes give (vote()); disagreeing votes leave it kUnknown, as do cells no wave reaches.
void SurfaceCells::decide_centre_states(const std::vector<std::uint16_t>& codes,
                                        const std::vector<std::array<int, 3>>& cell_of) {
  const int nx = dims_[0], ny = dims_[1], nz = dims_[2];
  const std::uint32_t total = std::uint32_t(cell_of.size());
  constexpr std::uint8_t kPending = 0xff;  // not decided yet
  states_.assign(total, kPending);
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
          const std::uint16_t code = codes[flat_cell(x, y, z, nx, ny)];
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
  if (!(f.x() < float(dims_[0]) && f.y() < float(dims_[1]) && f.z() < float(dims_[2]))) return SceneGrid::kUnknown;
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
