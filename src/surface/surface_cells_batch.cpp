// SurfaceCells::first_crossings_along: many segments' walks through the surface cells, several
// in flight at a time (asynchronous memory access chaining). A walk is first_crossing_along's
// loop cut where it waits for memory: the clearance byte of its next cell, the brick's mask
// and base, the cell's list bounds and slab, the list, the records; in a crowded cell its mask
// and rank words, its lists' bounds, the lists of the sub-cells the segment passes and their
// records. At each cut it prefetches what it reads next and the next walk in the round goes
// on, so the loads of many walks overlap. The float operations and the cells skipped are
// first_crossing_along's, in its order: the same crossings bit for bit.
#include "surface/surface_cells.h"
#include "geometry/cell_dda.h"
#include "prefetch.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <unistd.h>

namespace hb {

namespace {

// Where a walk stands: what it reads when it runs next (prefetched when it stopped).
enum class Phase : std::uint8_t { clearance, cell, list, records, crowded_entry, crowded_bounds, crowded_lists,
                                  crowded_records, test };

struct Walk {
  SurfaceCells::WalkStart seg;  // the segment and its part in the grid
  float s = 0.f;
  float best = std::numeric_limits<float>::infinity();
  bool best_front = false;
  std::uint32_t best_id = kNoTriangle;
  CellDda dda{kNoStep};
  int it = 0;
  std::size_t brick = 0;
  unsigned bit = 0;
  std::uint32_t index = 0, begin = 0, count = 0, crowded = SurfaceSubcells::kNone;
  Phase phase = Phase::clearance;
  static constexpr int kMaxLists = 16;
  std::uint32_t list_first[kMaxLists], list_count[kMaxLists];  // a crowded cell's sub-cell lists passed
  int lists = 0;
  std::size_t segment = 0;
  static constexpr float kNoStep[3] = {0.f, 0.f, 0.f};
};

// The last-level cache's bytes (the process's first call reads it).
std::size_t last_level_cache_bytes() noexcept {
  static const std::size_t bytes = [] {
    const long l3 = ::sysconf(_SC_LEVEL3_CACHE_SIZE);
    return l3 > 0 ? std::size_t(l3) : std::size_t(32) << 20;
  }();
  return bytes;
}

} // namespace

bool SurfaceCells::walks_side_by_side() const noexcept {
  return surface_ && 5 * (surface_->bytes() + surface_->normal_map_bytes() + bytes()) > last_level_cache_bytes();
}

// The walks of one first_crossings_along call: each phase of a walk is one method, which
// reads what the previous one prefetched and prefetches what the next reads. Methods defined
// in the class body (inline, as the lambdas they were), so the round loop below compiles to
// the same code.
struct SurfaceCells::Walker {
  const SurfaceCells& c;
  const Vec3* a;
  const Vec3* b;
  const int* n;  // the grid's dimensions
  int limit;     // most steps of a walk (first_crossing_along's)

  std::size_t brick_of(const CellDda& dda) const {
    return (std::size_t(dda.z >> 2) * std::size_t(c.bricks_y_) + std::size_t(dda.y >> 2)) * std::size_t(c.bricks_x_) +
           std::size_t(dda.x >> 2);
  }
  static unsigned bit_of(const CellDda& dda) { return unsigned(((dda.z & 3) << 4) | ((dda.y & 3) << 2) | (dda.x & 3)); }

  // first_crossing_along's start: false when the segment misses the grid (no crossing).
  bool start(Walk& w, std::size_t i) const {
    if (!c.walk_start(a[i], b[i], 1.f, w.seg)) return false;
    w.dda = CellDda(w.seg.inv);
    w.best = std::numeric_limits<float>::infinity();
    w.best_front = false;
    w.best_id = kNoTriangle;
    w.s = w.seg.s0;
    w.dda.start(w.seg.fa, w.seg.fd, w.seg.inv, w.s, n);
    w.it = 0;
    w.phase = Phase::clearance;
    w.segment = i;
    hb::prefetch(c.clear_.data() + brick_of(w.dda) * 64);
    return true;
  }
  // Steps walk w past a surface cell: false at the segment's or the grid's end.
  bool step_on(Walk& w) const {
    bool inside = true;
    w.s = w.dda.step(n, inside);
    ++w.it;
    if (w.s > w.seg.s1 || !inside) return false;
    w.phase = Phase::clearance;
    hb::prefetch(c.clear_.data() + brick_of(w.dda) * 64);
    return true;
  }
  // Starts loading the records of walk w's cell list (up to 32), to be tested next.
  bool prefetch_records(Walk& w) const {
    const std::uint32_t* ids = c.slots_.data() + w.begin;
    for (std::uint32_t k = 0; k < std::min<std::uint32_t>(w.count, 32); ++k) c.surface_->prefetch(ids[k]);
    w.phase = Phase::test;
    return true;
  }
  // Phase::clearance: jumps over empty space and steps through cells near the surface until
  // a surface cell (then its mask and base are loading) or another brick's clearance line.
  bool at_clearance(Walk& w) const {
    for (;;) {
      if (w.it >= limit || w.s > w.best) return false;
      w.brick = brick_of(w.dda);
      w.bit = bit_of(w.dda);
      const int clear = c.clear_[w.brick * 64 + w.bit];
      if (clear >= 2) {
        const float jump = w.s + (float(clear - 1) - 0.01f) * w.seg.s_per_cell;
        if (jump > w.seg.s1) return false;
        w.s = jump;
        w.dda.start(w.seg.fa, w.seg.fd, w.seg.inv, w.s, n);
        ++w.it;
        hb::prefetch(c.clear_.data() + brick_of(w.dda) * 64);
        return true;
      }
      if (clear == 0) {
        hb::prefetch(c.masks_.data() + w.brick);
        hb::prefetch(c.base_.data() + w.brick);
        w.phase = Phase::cell;
        return true;
      }
      bool inside = true;
      w.s = w.dda.step(n, inside);
      ++w.it;
      if (w.s > w.seg.s1 || !inside) return false;
      const std::size_t next = brick_of(w.dda);
      if (next != w.brick) {  // another brick's clearance line: wait for it
        hb::prefetch(c.clear_.data() + next * 64);
        return true;
      }
    }
  }
  // Phase::cell: the surface cell's index; its list bounds and slab start loading.
  bool at_cell(Walk& w) const {
    w.index = c.base_[w.brick] + cells_below(c.masks_[w.brick], w.bit);
    hb::prefetch(c.offsets_.data() + w.index);
    hb::prefetch(c.slabs_.data() + w.index);
    w.phase = Phase::list;
    return true;
  }
  // Phase::list: past a cell whose slab the segment passes by; else its list (and, when it
  // may be crowded, its sub-cell entry) starts loading.
  bool at_list(Walk& w) const {
    if (!c.slab_may_cross(w.index, w.seg.o, w.seg.d, w.s, std::min(w.dda.exit(), w.seg.s1))) return step_on(w);
    w.begin = c.offsets_[w.index];
    w.count = c.offsets_[w.index + 1] - w.begin;
    for (std::uint32_t k = 0; k < std::min<std::uint32_t>(w.count, 64); k += 16) hb::prefetch(c.slots_.data() + w.begin + k);
    w.crowded = SurfaceSubcells::kNone;
    if (c.subcells_.may_be_crowded(w.count)) {
      c.subcells_.prefetch_entry(w.index);
      w.phase = Phase::crowded_entry;
    } else {
      w.phase = Phase::records;
    }
    return true;
  }
  // Phase::crowded_entry: whether the cell has sub-cells (else its own list is tested).
  bool at_crowded_entry(Walk& w) const {
    w.crowded = c.subcells_.crowded(w.index);
    if (w.crowded == SurfaceSubcells::kNone) return prefetch_records(w);  // its list came with the entry
    c.subcells_.prefetch(w.crowded, 0);
    w.phase = Phase::crowded_bounds;
    return true;
  }
  // Phase::crowded_lists: the lists of the sub-cells the segment passes in this cell (what
  // the test reads).
  bool at_crowded_lists(Walk& w) const {
    const int cell[3] = {w.dda.x, w.dda.y, w.dda.z};
    const Vec3 fa(w.seg.fa[0], w.seg.fa[1], w.seg.fa[2]), fd(w.seg.fd[0], w.seg.fd[1], w.seg.fd[2]);
    w.lists = c.subcells_.lists_along(w.crowded, cell, fa, fd, w.seg.inv, w.s, std::min(w.dda.exit(), w.seg.s1), w.list_first,
                                      w.list_count, Walk::kMaxLists);
    for (int k = 0; k < w.lists; ++k)
      for (std::uint32_t j = 0; j < w.list_count[k]; j += 16) hb::prefetch(c.subcells_.list_slots() + w.list_first[k] + j);
    w.phase = Phase::crowded_records;
    return true;
  }
  // Phase::crowded_records: the records of those lists (up to 48) start loading.
  bool at_crowded_records(Walk& w) const {
    int prefetched = 0;
    for (int k = 0; k < w.lists && prefetched < 48; ++k)
      for (std::uint32_t j = 0; j < w.list_count[k] && prefetched < 48; ++j, ++prefetched)
        c.surface_->prefetch(c.subcells_.list_slots()[w.list_first[k] + j]);
    w.phase = Phase::test;
    return true;
  }
  // Phase::test: the cell's (or its sub-cells') triangles against the segment, then on.
  bool test(Walk& w) const {
    const std::uint32_t crowded = w.crowded;
    if (crowded != SurfaceSubcells::kNone) {
      const int cell[3] = {w.dda.x, w.dda.y, w.dda.z};
      const Vec3 fa(w.seg.fa[0], w.seg.fa[1], w.seg.fa[2]), fd(w.seg.fd[0], w.seg.fd[1], w.seg.fd[2]);
      c.subcells_.first_crossing(crowded, cell, fa, fd, w.seg.inv, w.s, std::min(w.dda.exit(), w.seg.s1), w.seg.s1, w.seg.o,
                                 w.seg.d, *c.surface_, w.best, w.best_front, w.best_id);
    } else {
      float cs = 0.f;
      bool cf = false;
      std::uint32_t ct = kNoTriangle;
      if (c.surface_->first_crossing(c.slots_.data() + w.begin, w.count, w.seg.o, w.seg.d, 0.f, std::min(w.best, w.seg.s1), cs,
                                     cf, ct) &&
          cs < w.best)
        w.best = cs, w.best_front = cf, w.best_id = ct;
    }
    return step_on(w);
  }
  // Runs walk w up to its next wait for memory: true while it walks on, false when done.
  bool advance(Walk& w) const {
    switch (w.phase) {
    case Phase::clearance:
      return at_clearance(w);
    case Phase::cell:
      return at_cell(w);
    case Phase::list:
      return at_list(w);
    case Phase::records:
      return prefetch_records(w);
    case Phase::crowded_entry:
      return at_crowded_entry(w);
    case Phase::crowded_bounds:
      c.subcells_.prefetch(w.crowded, 1);
      w.phase = Phase::crowded_lists;
      return true;
    case Phase::crowded_lists:
      return at_crowded_lists(w);
    case Phase::crowded_records:
      return at_crowded_records(w);
    case Phase::test:
      return test(w);
    }
    return false;
  }
};

void SurfaceCells::first_crossings_along(const Vec3* a, const Vec3* b, std::size_t count,
                                         Crossing* out) const noexcept {
  for (std::size_t i = 0; i < count; ++i) out[i] = Crossing{};
  if (masks_.empty()) return;
  const Walker walker{*this, a, b, dims_.data(), dims_[0] + dims_[1] + dims_[2]};
  constexpr int kInFlight = 8;
  Walk walks[kInFlight];
  bool live[kInFlight] = {};
  int running = 0;
  std::size_t next = 0;
  const auto refill = [&](int k) {
    while (next < count) {
      const std::size_t i = next++;
      if (walker.start(walks[k], i)) {
        live[k] = true;
        ++running;
        return;
      }
    }
  };
  for (int k = 0; k < kInFlight; ++k) refill(k);
  while (running > 0) {
    for (int k = 0; k < kInFlight; ++k) {
      if (!live[k] || walker.advance(walks[k])) continue;
      const Walk& w = walks[k];
      if (w.best_id != kNoTriangle) out[w.segment] = Crossing{w.best_front, w.best, w.best_id};
      live[k] = false;
      --running;
      refill(k);
    }
  }
}

} // namespace hb
