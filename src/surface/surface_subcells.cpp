// The sub-cells of crowded surface cells (surface_subcells.h).
#include "surface/surface_subcells.h"
#include "geometry/cell_dda.h"
#include "geometry/triangle_box.h"
#include "surface/surface_cells.h"
#include "prefetch.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cmath>
#include <limits>

namespace hb {

SurfaceSubcells::SurfaceSubcells(const Vec3& origin, float cell, const std::vector<std::array<int, 3>>& cell_of,
                                 const std::vector<std::uint32_t>& offsets, const std::vector<std::uint32_t>& slots,
                                 const SurfaceTriangles& surface, std::uint32_t crowded) {
  const std::size_t cells = cell_of.size();
  if (offsets.size() != cells + 1) return;
  entry_.assign(cells, kNone);
  std::vector<std::uint32_t> crowded_cells;
  for (std::size_t c = 0; c < cells; ++c)
    if (offsets[c + 1] - offsets[c] > crowded) {
      entry_[c] = std::uint32_t(crowded_cells.size());
      crowded_cells.push_back(std::uint32_t(c));
    }
  if (crowded_cells.empty()) {
    entry_.clear();
    return;
  }
  threshold_ = crowded;
  // The side: listings per sub-cell fall about with the square of the side.
  double listed = 0.0;
  for (std::uint32_t c : crowded_cells) listed += double(offsets[c + 1] - offsets[c]);
  const double mean = listed / double(crowded_cells.size());
  side_ = 4;
  while (side_ < kMaxSide && mean / (double(side_) * double(side_)) > double(crowded)) side_ *= 2;
  const int side = side_, sub_count = side * side * side;
  words_ = sub_count / 64;
  const float sub = cell / float(side);
  const float half = 0.5f * sub * (1.f + 1e-4f);
  // Per crowded cell, its sub-lists (built side by side, then joined in cell order).
  struct Lists {
    std::vector<std::uint64_t> mask;
    std::vector<std::uint32_t> counts, slots;  // per non-empty sub-cell in bit order
  };
  std::vector<Lists> lists(crowded_cells.size());
  const SurfaceTriangles::Record* records = surface.records();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, crowded_cells.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
    std::vector<std::vector<std::uint32_t>> per_sub(static_cast<std::size_t>(sub_count));
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const std::uint32_t c = crowded_cells[k];
      const std::array<int, 3>& q = cell_of[c];
      const Vec3 low = origin + cell * Vec3(float(q[0]), float(q[1]), float(q[2]));
      for (auto& v : per_sub) v.clear();
      for (std::uint32_t j = offsets[c]; j < offsets[c + 1]; ++j) {
        const std::uint32_t t = slots[j];
        if (t >= surface.size()) continue;
        const SurfaceTriangles::Record& r = records[t];
        const Vec3 a(r.a[0], r.a[1], r.a[2]);
        const Vec3 b = a + Vec3(r.e1[0], r.e1[1], r.e1[2]), cc = a + Vec3(r.e2[0], r.e2[1], r.e2[2]);
        int lo[3], hi[3];
        for (int k3 = 0; k3 < 3; ++k3) {
          const float mn = std::min({a[k3], b[k3], cc[k3]}), mx = std::max({a[k3], b[k3], cc[k3]});
          // Cut to the cell before the conversion (a damaged file's 1e31 is no int).
          const auto at = [&](float f) { return int(std::floor(std::clamp(f, -2.f, float(side) + 1.f))); };
          lo[k3] = std::max(0, at((mn - low[k3]) / sub - 1e-3f));
          hi[k3] = std::min(side - 1, at((mx - low[k3]) / sub + 1e-3f));
        }
        for (int z = lo[2]; z <= hi[2]; ++z)
          for (int y = lo[1]; y <= hi[1]; ++y)
            for (int x = lo[0]; x <= hi[0]; ++x) {
              const Vec3 centre = low + sub * Vec3(float(x) + 0.5f, float(y) + 0.5f, float(z) + 0.5f);
              if (triangle_meets_box(a, b, cc, centre, half)) per_sub[std::size_t((z * side + y) * side + x)].push_back(t);
            }
      }
      Lists& out = lists[k];
      out.mask.assign(std::size_t(words_), 0);
      for (int bit = 0; bit < sub_count; ++bit) {
        if (per_sub[std::size_t(bit)].empty()) continue;
        out.mask[std::size_t(bit >> 6)] |= std::uint64_t(1) << (bit & 63);
        out.counts.push_back(std::uint32_t(per_sub[std::size_t(bit)].size()));
        out.slots.insert(out.slots.end(), per_sub[std::size_t(bit)].begin(), per_sub[std::size_t(bit)].end());
      }
    }
  });
  mask_.reserve(lists.size() * std::size_t(words_));
  rank_.reserve(lists.size() * std::size_t(words_));
  offsets_.push_back(0);
  for (std::size_t k = 0; k < lists.size(); ++k) {
    std::uint32_t first = std::uint32_t(offsets_.size() - 1);
    for (int w = 0; w < words_; ++w) {
      mask_.push_back(lists[k].mask[std::size_t(w)]);
      rank_.push_back(first);
      first += std::uint32_t(__builtin_popcountll(lists[k].mask[std::size_t(w)]));
    }
    for (std::uint32_t n : lists[k].counts) offsets_.push_back(offsets_.back() + n);
    slots_.insert(slots_.end(), lists[k].slots.begin(), lists[k].slots.end());
  }
}

namespace {

// The DDA over a crowded cell's sub-cells, in sub-cell units from the cell's low corner: a =
// (fa - cell) side, the direction fd side, and 1 / (fd side) = inv / side (no division here),
// started at s_enter. One setup for the tests' walk and the prefetching walk's.
struct SubWalk {
  float a[3], ds[3], inv[3];
  int n[3];
  CellDda dda;
  SubWalk(int side, const int cell[3], const Vec3& fa, const Vec3& fd, const float inv_cell[3], float s_enter) noexcept
      : n{side, side, side}, dda(kZero) {
    const float to_sub = 1.f / float(side);
    for (int k = 0; k < 3; ++k) {
      a[k] = (fa[k] - float(cell[k])) * float(side);
      ds[k] = fd[k] * float(side);
      inv[k] = inv_cell[k] * to_sub;
    }
    dda = CellDda(inv);
    dda.start(a, ds, inv, s_enter, n);
  }
  static constexpr float kZero[3] = {0.f, 0.f, 0.f};
};

} // namespace

void SurfaceSubcells::prefetch(std::uint32_t crowded, int stage) const noexcept {
  if (crowded >= crowded_count()) return;
  const std::size_t word0 = std::size_t(crowded) * std::size_t(words_), next = word0 + std::size_t(words_);
  if (stage == 0) {
    for (std::size_t w = word0; w < next; w += 8) {
      hb::prefetch(mask_.data() + w);
      hb::prefetch(rank_.data() + w);
    }
    if (next < rank_.size()) hb::prefetch(rank_.data() + next);
    return;
  }
  // The cell's lists are [first, last): the next crowded cell's first, or the end.
  const std::uint32_t first = rank_[word0];
  const std::uint32_t last = next < rank_.size() ? rank_[next] : std::uint32_t(offsets_.size() - 1);
  if (first > last || last >= offsets_.size()) return;
  for (std::uint32_t k = first; k <= last; k += 16) hb::prefetch(offsets_.data() + k);
  hb::prefetch(offsets_.data() + last);
}

int SurfaceSubcells::lists_along(std::uint32_t crowded, const int cell[3], const Vec3& fa, const Vec3& fd,
                                 const float inv[3], float s_enter, float s_exit, std::uint32_t* first,
                                 std::uint32_t* count, int max) const noexcept {
  if (crowded >= crowded_count()) return 0;
  const std::size_t word0 = std::size_t(crowded) * std::size_t(words_);
  const int side = side_;
  SubWalk walk(side, cell, fa, fd, inv, s_enter);
  CellDda& dda = walk.dda;
  const int* n = walk.n;
  int found = 0;
  for (int it = 0; it < 3 * side && found < max; ++it) {
    const unsigned bit = unsigned((dda.z * side + dda.y) * side + dda.x);
    const std::size_t word = word0 + (bit >> 6);
    const std::uint64_t mask = mask_[word];
    if ((mask >> (bit & 63)) & 1u) {
      const std::uint32_t list = rank_[word] + SurfaceCells::cells_below(mask, bit & 63);
      first[found] = offsets_[list];
      count[found++] = offsets_[list + 1] - offsets_[list];
    }
    bool inside = true;
    const float s = dda.step(n, inside);
    if (s > s_exit || !inside) break;
  }
  return found;
}

bool SurfaceSubcells::first_crossing(std::uint32_t crowded, const int cell[3], const Vec3& fa, const Vec3& fd,
                                     const float inv[3], float s_enter, float s_exit, float s_cap, const float o[3],
                                     const float d[3], const SurfaceTriangles& surface, float& best, bool& front,
                                     std::uint32_t& id) const noexcept {
  if (crowded >= crowded_count()) return false;
  const std::size_t word0 = std::size_t(crowded) * std::size_t(words_);
  const int side = side_;
  SubWalk walk(side, cell, fa, fd, inv, s_enter);
  CellDda& dda = walk.dda;
  const int* n = walk.n;
  bool found = false;
  float s = s_enter;
  for (int it = 0; it < 3 * side; ++it) {
    if (s > best) break;
    const unsigned bit = unsigned((dda.z * side + dda.y) * side + dda.x);
    const std::size_t word = word0 + (bit >> 6);
    const std::uint64_t mask = mask_[word];
    if ((mask >> (bit & 63)) & 1u) {
      const std::uint32_t list = rank_[word] + SurfaceCells::cells_below(mask, bit & 63);
      float cs = 0.f;
      bool cf = false;
      std::uint32_t ct = kNoTriangle;
      if (surface.first_crossing(slots_.data() + offsets_[list], std::size_t(offsets_[list + 1] - offsets_[list]), o, d,
                                 0.f, std::min(best, s_cap), cs, cf, ct) &&
          cs < best) {
        best = cs, front = cf, id = ct;
        found = true;
      }
    }
    bool inside = true;
    s = dda.step(n, inside);
    if (s > s_exit || !inside) break;
  }
  return found;
}

} // namespace hb
