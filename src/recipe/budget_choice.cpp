// The budgeted bake's choice of variants (step 3 of budget_search.cpp): the failures of a
// choice summed over the pieces, their excess over the budget's allowances, and the choice
// itself: the cheapest uniform variant within the allowances, each piece down, or the best
// moves per byte; unrefined pieces answering off the surface are refined.
#include "recipe/budget_search.h"
#include <algorithm>
#include <cmath>
#include <vector>

namespace hb {

// The failures of the current choice, summed over the pieces.
BudgetSearch::Counts BudgetSearch::totals() const {
  Counts t;
  for (std::size_t p = 0; p < pieces_; ++p) {
    const Counts& n = counts_[p][choice_[p]];
    t.disagree += n.disagree, t.both += n.both, t.over_median += n.over_median;
    t.over_p95 += n.over_p95, t.over_dir += n.over_dir, t.off_surface += n.off_surface;
    t.felt += n.felt;
  }
  return t;
}

// Excess over the allowances, each relative to its allowance (0: within the budget). The
// budget as allowances over all owned probes, with a margin for the probes the choice does
// not see (the fresh check, the scene's own routing); failures add up over pieces.
double BudgetSearch::excess(const Counts& t) const {
  const ErrorBudget& b = br_.budget;
  const double allow_disagree = kBudgetMargin * (1.0 - b.agreement) * owned_probes_;
  const double allow_median = 0.5 * t.both * (b.force_median > 0 ? 1.0 : 0.0);
  const double allow_p95 = kBudgetMargin * 0.05 * t.both, allow_dir = kBudgetMargin * 0.01 * t.both;
  const auto over = [](double count, double allow) { return count > allow ? (count - allow) / std::max(allow, 1.0) : 0.0; };
  const double felt_excess = over(t.felt, kBudgetMargin * b.perceptible * owned_probes_);
  if (!b.relative) return felt_excess;
  return felt_excess + over(t.disagree, allow_disagree) + over(t.over_median, kBudgetMargin * allow_median) +
         over(t.over_p95, allow_p95) + over(t.over_dir, allow_dir);
}

// Step 3's choice: from the cheapest uniform variant within the allowances, each piece
// down; beyond them, the best moves; then unrefined pieces whose blends answer their probes
// from off the surface are refined at their sampling (the refined variant is the next one).
void BudgetSearch::select_variants() {
  start_at_cheapest_uniform();
  lower_each_piece();
  make_best_moves();
  for (std::size_t p = 0; p < pieces_; ++p)
    if (choice_[p] % 2 == 0 && counts_[p][choice_[p]].off_surface > 0) choice_[p] += 1;
}

// The cheapest uniform variant that is within the allowances (or, when none is, the one with
// the least excess).
void BudgetSearch::start_at_cheapest_uniform() {
  std::size_t start = variants_;
  double start_bytes = 0, least = 0;
  std::size_t least_v = variants_ - 1;
  for (std::size_t v = 0; v < variants_; ++v) {
    choice_.assign(pieces_, v);
    const double e = excess(totals());
    double bytes = 0;
    for (std::size_t p = 0; p < pieces_; ++p) bytes += piece_bytes(p, v);
    if (e <= 0.0 && (start == variants_ || bytes < start_bytes)) start = v, start_bytes = bytes;
    if (v == 0 || e < least) least = e, least_v = v;
  }
  choice_.assign(pieces_, start < variants_ ? start : least_v);
}

// Within the allowances: each piece, largest first, down to the cheapest of its variants
// that keeps the scene within them.
void BudgetSearch::lower_each_piece() {
  std::vector<std::size_t> by_size(pieces_);
  for (std::size_t p = 0; p < pieces_; ++p) by_size[p] = p;
  std::sort(by_size.begin(), by_size.end(),
            [&](std::size_t x, std::size_t y) { return piece_bytes(x, choice_[x]) > piece_bytes(y, choice_[y]); });
  if (excess(totals()) > 0.0) return;
  for (std::size_t p : by_size) {
    // A piece that owns no probe is not measured: it keeps its refinement (its blends could
    // answer other pieces' probes, uncharged).
    if (owned_[p].empty()) {
      choice_[p] = std::min(choice_[p], std::size_t(1));
      continue;
    }
    std::vector<std::size_t> cheaper;
    for (std::size_t v = 0; v < variants_; ++v)
      if (piece_bytes(p, v) < piece_bytes(p, choice_[p])) cheaper.push_back(v);
    std::sort(cheaper.begin(), cheaper.end(), [&](std::size_t x, std::size_t y) { return piece_bytes(p, x) < piece_bytes(p, y); });
    const std::size_t keep = choice_[p];
    for (std::size_t v : cheaper) {
      choice_[p] = v;
      if (excess(totals()) <= 0.0) break;
      choice_[p] = keep;
    }
  }
}

// Still beyond the allowances (no uniform variant met them): the move that removes the most
// excess per byte added, until within them or no move helps.
void BudgetSearch::make_best_moves() {
  for (std::size_t step = 0; step < pieces_ * variants_; ++step) {
    const Counts t = totals();
    const double now = excess(t);
    if (now <= 0.0) break;
    double best_gain = 0.0;
    std::size_t best_p = pieces_, best_v = 0;
    for (std::size_t p = 0; p < pieces_; ++p)
      for (std::size_t v = choice_[p] + 1; v < variants_; ++v) {
        Counts u = t;
        const Counts &from = counts_[p][choice_[p]], &to = counts_[p][v];
        u.disagree += to.disagree - from.disagree, u.both += to.both - from.both;
        u.over_median += to.over_median - from.over_median, u.over_p95 += to.over_p95 - from.over_p95;
        u.over_dir += to.over_dir - from.over_dir;
        u.felt += to.felt - from.felt;
        const double gain = (now - excess(u)) / std::max(1.0, to.bytes - from.bytes);
        if (gain > best_gain) best_gain = gain, best_p = p, best_v = v;
      }
    if (best_p == pieces_) break;  // no move helps: the finest variants are the best there is
    choice_[best_p] = best_v;
  }
}

} // namespace hb
