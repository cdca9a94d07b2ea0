#pragma once
// The one rule by which a bake chooses what answers from timings it takes while baking: exact
// Embree (over the surface, or over the full mesh along strokes) unless the other route (the
// surface cells, a refined or raw box) is clearly faster on the same queries, one core, paired
// rounds. Near-ties, which a shared machine's noise tips either way, always go to Embree, the
// simpler route that is exact and never slower than exact, so the same model bakes to the same
// route every time; the timings themselves are kept in the file (BudgetReport).

namespace hb {

/// The other route's time must be at most this share of Embree's to be chosen.
constexpr double kClearlyFasterShare = 0.8;

/// Whether a route timed at `route_ns` a query answers instead of Embree timed at `embree_ns`
/// on the same queries (false when either time is missing).
inline bool clearly_faster_than_embree(double route_ns, double embree_ns) noexcept {
  return route_ns > 0.0 && embree_ns > 0.0 && route_ns <= kClearlyFasterShare * embree_ns;
}

/// Along strokes a probe's successive queries find both routes' data in cache and their times
/// sit close: a route already clearly faster at random answers unless it is slower there.
inline bool not_slower_than_embree(double route_ns, double embree_ns) noexcept {
  return route_ns > 0.0 && embree_ns > 0.0 && route_ns <= embree_ns;
}

} // namespace hb
