#include "perception/budget_report.h"
#include "errors.h"
#include "spec_parse.h"
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace hb {
namespace {
// The longest surface_rejected_why a file holds (one line of a budget report).
constexpr std::size_t kMaxWhy = 1000;

std::string trim(const std::string& s) { return spec_trim(s); }
double number(const std::string& text, const std::string& what, double lo, double hi) {
  return spec_number(text, what, lo, hi);
}
std::string fmt(double v) { return spec_format(v); }

} // namespace

ErrorBudget parse_budget(const std::string& spec) {
  ErrorBudget b;
  const std::string all = trim(spec);
  if (all.empty() || all == "default") return b;
  const auto on_off = [](const std::string& value, const std::string& what) {
    const std::string v = trim(value);
    if (v == "on" || v == "1" || v == "yes") return true;
    if (v == "off" || v == "0" || v == "no") return false;
    throw InvalidInput(what + ": '" + v + "' is not on or off");
  };
  std::stringstream ss(all);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos)
      throw InvalidInput("--budget: '" + item + "' is not key=value (keys: felt, raw, memory, relative, p95, median, dir99, agree)");
    const std::string key = trim(item.substr(0, eq)), value = item.substr(eq + 1);
    const bool relative_key = key == "p95" || key == "median" || key == "dir99" || key == "agree";
    if (relative_key) b.relative = true;
    if (key == "p95")
      b.force_p95 = number(value, "--budget p95 (percent)", 0.0, 1e4) / 100.0;
    else if (key == "median")
      b.force_median = number(value, "--budget median (percent)", 0.0, 1e4) / 100.0;
    else if (key == "dir99")
      b.direction_p99_deg = number(value, "--budget dir99 (degrees)", 0.0, 180.0);
    else if (key == "agree")
      b.agreement = number(value, "--budget agree (percent)", 0.0, 100.0) / 100.0;
    else if (key == "relative")
      b.relative = on_off(value, "--budget relative");
    else if (key == "raw")
      b.raw = on_off(value, "--budget raw");
    else if (key == "memory")
      b.raw_memory_bytes = number(value, "--budget memory (MB, the raw box's cap)", 0.001, 1e7) * 1e6;
    else if (key == "felt")
      b.perceptible = number(value, "--budget felt (percent of probes perceptibly different)", 0.0, 100.0) / 100.0;
    else
      throw InvalidInput("--budget: unknown key '" + key + "' (keys: felt, raw, memory, relative, p95, median, dir99, agree)");
  }
  return b;
}

std::string budget_spec(const ErrorBudget& b) {
  std::string spec = "felt=" + fmt(b.perceptible * 100.0);
  if (b.relative)
    spec += ",p95=" + fmt(b.force_p95 * 100.0) + ",median=" + fmt(b.force_median * 100.0) +
            ",dir99=" + fmt(b.direction_p99_deg) + ",agree=" + fmt(b.agreement * 100.0);
  if (!b.raw) spec += ",raw=off";
  if (b.raw_memory_bytes != ErrorBudget{}.raw_memory_bytes) spec += ",memory=" + fmt(b.raw_memory_bytes / 1e6);
  return spec;
}

// The file form leaves out `seconds` and the stages' (this run's wall times of the budgeted
// bake). It keeps the query times measured at bake time (answer_ns, ..., each raw sampling's),
// which the speed chart of a loaded box shows: the same inputs give the same bytes but for
// them, and without_times() gives what the byte-for-byte comparisons compare. parse() also
// reads the older forms: a `seconds=` line and six-field raw_tried lines (no times).
std::string BudgetReport::serialize() const {
  std::ostringstream os;
  os.precision(9);
  os << "budget=" << budget_spec(budget) << "\n"
     << "met=" << (met ? 1 : 0) << "\n"
     << "probes=" << probes << "\nseed=" << seed << "\n"
     << "agreement=" << agreement << "\nforce_median=" << force_median << "\nforce_p95=" << force_p95
     << "\ndirection_p99_deg=" << direction_p99_deg << "\nperceptible=" << perceptible << "\n"
     << "tuning_probes=" << tuning_probes << "\ntuning_seed=" << tuning_seed << "\n"
     << "tuning_agreement=" << tuning_agreement << "\ntuning_force_median=" << tuning_force_median
     << "\ntuning_force_p95=" << tuning_force_p95 << "\ntuning_direction_p99_deg=" << tuning_direction_p99_deg << "\n"
     << "candidates_tried=" << candidates_tried << "\n";  // no wall time: same inputs, same bytes
  if (surface_triangles > 0)
    os << "full_triangles=" << full_triangles << "\nsurface_triangles=" << surface_triangles
       << "\nsurface_bound=" << surface_bound << "\nsurface_deviation_mean=" << surface_deviation_mean
       << "\nsurface_deviation_p99=" << surface_deviation_p99 << "\nsurface_deviation_max=" << surface_deviation_max
       << "\nsurface_normal_median_deg=" << surface_normal_median_deg
       << "\nsurface_normal_p99_deg=" << surface_normal_p99_deg << "\n";
  if (surface_map_side > 0) os << "surface_map_side=" << surface_map_side << "\n";
  if (surface_rejected > 0) os << "surface_rejected=" << surface_rejected << "\n";
  if (!surface_rejected_why.empty()) {
    std::string why = surface_rejected_why.substr(0, kMaxWhy);
    for (char& c : why)
      if (c == '\n' || c == '\r') c = ' ';
    os << "surface_rejected_why=" << why << "\n";
  }
  for (const PieceChoice& p : pieces)
    os << "piece=" << p.cell << " " << p.n << " " << (p.refine ? 1 : 0) << " " << p.probes << "\n";
  if (answer != Answerer::none) os << "answer=" << answerer_name(answer) << "\n";
  if (stroke_answer != Answerer::none) os << "stroke_answer=" << answerer_name(stroke_answer) << "\n";
  for (const RawTried& t : raw_tried) {
    os << "raw_tried=" << t.m << " " << t.n << " " << t.bytes << " " << t.probes_felt << " " << t.ticks_felt << " "
       << t.outcome << " " << t.box_ns << " " << t.exact_ns;
    if (t.box_stroke_ns > 0 || t.light_felt >= 0) os << " " << t.box_stroke_ns << " " << t.exact_stroke_ns;
    if (t.light_felt >= 0) os << " " << t.light_felt;
    os << "\n";
  }
  // Measured at bake time: the only lines two bakes of the same inputs differ in.
  if (answer_ns > 0) os << "answer_ns=" << answer_ns << "\nexact_ns=" << exact_ns << "\n";
  if (cells_ns > 0) os << "cells_ns=" << cells_ns << "\nembree_ns=" << embree_ns << "\n";
  if (stroke_cells_ns > 0) os << "stroke_cells_ns=" << stroke_cells_ns << "\nstroke_embree_ns=" << stroke_embree_ns << "\n";
  return os.str();
}

BudgetReport BudgetReport::without_times() const {
  BudgetReport r = *this;
  r.answer_ns = r.exact_ns = r.cells_ns = r.embree_ns = r.stroke_cells_ns = r.stroke_embree_ns = 0;
  for (RawTried& t : r.raw_tried) t.box_ns = t.exact_ns = t.box_stroke_ns = t.exact_stroke_ns = 0;
  return r;
}

BudgetReport BudgetReport::parse(const std::string& text) {
  BudgetReport r;
  r.present = true;
  std::stringstream ss(text);
  std::string line;
  const auto count = [](const std::string& v, const std::string& key) {
    return std::uint64_t(number(v, "budget report " + key, 0.0, 1e15));
  };
  while (std::getline(ss, line)) {
    if (line.empty()) continue;
    const auto eq = line.find('=');
    if (eq == std::string::npos) throw InvalidInput("budget report: line '" + line.substr(0, 80) + "' is not key=value");
    const std::string key = line.substr(0, eq), v = line.substr(eq + 1);
    if (key == "budget") r.budget = parse_budget(v);
    else if (key == "met") r.met = count(v, key) != 0;
    else if (key == "probes") r.probes = count(v, key);
    else if (key == "seed") r.seed = count(v, key);
    else if (key == "agreement") r.agreement = number(v, key, 0, 1);
    else if (key == "force_median") r.force_median = number(v, key, 0, 1e30);
    else if (key == "force_p95") r.force_p95 = number(v, key, 0, 1e30);
    else if (key == "direction_p99_deg") r.direction_p99_deg = number(v, key, 0, 180);
    else if (key == "perceptible") r.perceptible = number(v, key, 0, 1);
    else if (key == "tuning_probes") r.tuning_probes = count(v, key);
    else if (key == "tuning_seed") r.tuning_seed = count(v, key);
    else if (key == "tuning_agreement") r.tuning_agreement = number(v, key, 0, 1);
    else if (key == "tuning_force_median") r.tuning_force_median = number(v, key, 0, 1e30);
    else if (key == "tuning_force_p95") r.tuning_force_p95 = number(v, key, 0, 1e30);
    else if (key == "tuning_direction_p99_deg") r.tuning_direction_p99_deg = number(v, key, 0, 180);
    else if (key == "seconds") r.seconds = number(v, key, 0, 1e9);  // older files
    else if (key == "candidates_tried") r.candidates_tried = std::uint32_t(number(v, key, 0, 1e6));
    else if (key == "full_triangles") r.full_triangles = count(v, key);
    else if (key == "surface_triangles") r.surface_triangles = count(v, key);
    else if (key == "surface_bound") r.surface_bound = number(v, key, 0, 1e30);
    else if (key == "surface_deviation_mean") r.surface_deviation_mean = number(v, key, 0, 1e30);
    else if (key == "surface_deviation_p99") r.surface_deviation_p99 = number(v, key, 0, 1e30);
    else if (key == "surface_deviation_max") r.surface_deviation_max = number(v, key, 0, 1e30);
    else if (key == "surface_normal_median_deg") r.surface_normal_median_deg = number(v, key, 0, 180);
    else if (key == "surface_normal_p99_deg") r.surface_normal_p99_deg = number(v, key, 0, 180);
    else if (key == "surface_rejected") r.surface_rejected = count(v, key);
    else if (key == "surface_rejected_why") {
      if (v.size() > kMaxWhy) throw InvalidInput("budget report: surface_rejected_why longer than " + std::to_string(kMaxWhy));
      r.surface_rejected_why = v;
    }
    else if (key == "surface_map_side") r.surface_map_side = std::uint32_t(number(v, key, 1, 64));
    else if (key == "simplify_seconds") r.simplify_seconds = number(v, key, 0, 1e9);
    else if (key == "answer_ns") r.answer_ns = number(v, key, 0, 1e12);
    else if (key == "exact_ns") r.exact_ns = number(v, key, 0, 1e12);
    else if (key == "cells_ns") r.cells_ns = number(v, key, 0, 1e12);
    else if (key == "embree_ns") r.embree_ns = number(v, key, 0, 1e12);
    else if (key == "stroke_cells_ns") r.stroke_cells_ns = number(v, key, 0, 1e12);
    else if (key == "stroke_embree_ns") r.stroke_embree_ns = number(v, key, 0, 1e12);
    else if (key == "piece") {
      std::stringstream ps(v);
      std::string cell, n, refine, probes, extra;
      if (!(ps >> cell >> n >> refine >> probes) || (ps >> extra))
        throw InvalidInput("budget report: piece line '" + v.substr(0, 80) + "' is not 'cell n refine probes'");
      PieceChoice p;
      p.cell = float(number(cell, "budget report piece cell", 0, 1));
      p.n = int(number(n, "budget report piece n", 0, 4096));
      p.refine = number(refine, "budget report piece refine", 0, 1) != 0;
      p.probes = std::uint32_t(number(probes, "budget report piece probes", 0, 4e9));
      r.pieces.push_back(p);
      if (r.pieces.size() > (1u << 20)) throw InvalidInput("budget report: too many pieces");
    } else if (key == "answer") {
      const std::optional<Answerer> a = parse_answerer(v);
      if (!a || *a == Answerer::none)
        throw InvalidInput("budget report: answer '" + v.substr(0, 40) + "' is not raw, cells, embree or boxes");
      r.answer = *a;
    } else if (key == "stroke_answer") {
      const std::optional<Answerer> a = parse_answerer(v);
      if (!a || (*a != Answerer::cells && *a != Answerer::embree))
        throw InvalidInput("budget report: stroke_answer '" + v.substr(0, 40) + "' is not cells or embree");
      r.stroke_answer = *a;
    } else if (key == "raw_tried") {
      std::stringstream ps(v);
      std::string m, n, bytes, probes, ticks, outcome, box_ns, exact_ns, stroke_ns, exact_stroke_ns, light, extra;
      // Six fields in older files; then the query times (random order, then along strokes
      // when timed) and the light touches' share.
      if (!(ps >> m >> n >> bytes >> probes >> ticks >> outcome) || ((ps >> box_ns) && !(ps >> exact_ns)) ||
          ((ps >> stroke_ns) && !(ps >> exact_stroke_ns)) || ((ps >> light) && (ps >> extra)))
        throw InvalidInput("budget report: raw_tried line '" + v.substr(0, 80) +
                           "' is not 'm n bytes probes ticks outcome [box_ns exact_ns [stroke_ns exact_stroke_ns "
                           "[light]]]'");
      RawTried t;
      t.m = int(number(m, "budget report raw_tried m", 2, 4096));
      t.n = int(number(n, "budget report raw_tried n", 2, 4096));
      t.bytes = number(bytes, "budget report raw_tried bytes", 0, 1e15);
      t.probes_felt = number(probes, "budget report raw_tried probes", 0, 1);
      t.ticks_felt = number(ticks, "budget report raw_tried ticks", -1, 1);
      if (outcome != "kept" && outcome != "serves" && outcome != "felt-probes" && outcome != "felt-light" &&
          outcome != "felt-slides" && outcome != "over-cap" && outcome != "slower" && outcome != "slower-strokes")
        throw InvalidInput("budget report: raw_tried outcome '" + outcome.substr(0, 40) + "' unknown");
      t.outcome = outcome;
      if (!box_ns.empty()) {
        t.box_ns = number(box_ns, "budget report raw_tried box_ns", 0, 1e12);
        t.exact_ns = number(exact_ns, "budget report raw_tried exact_ns", 0, 1e12);
      }
      if (!stroke_ns.empty()) {
        t.box_stroke_ns = number(stroke_ns, "budget report raw_tried stroke_ns", 0, 1e12);
        t.exact_stroke_ns = number(exact_stroke_ns, "budget report raw_tried exact_stroke_ns", 0, 1e12);
      }
      if (!light.empty()) t.light_felt = number(light, "budget report raw_tried light", -1, 1);
      r.raw_tried.push_back(t);
      if (r.raw_tried.size() > 64) throw InvalidInput("budget report: too many raw_tried lines");
    } else
      throw InvalidInput("budget report: unknown key '" + key.substr(0, 40) + "'");
  }
  return r;
}

std::string BudgetReport::summary() const {
  if (!present) return "none (not baked to a budget)";
  std::ostringstream os;
  os.precision(4);
  os << budget_spec(budget) << ": " << (met ? "met" : "MISSED") << " on " << probes << " fresh probes (seed " << seed
     << "): perceptibly different " << perceptible * 100.0 << "% of them, agreement " << agreement * 100.0
     << "%, force error median " << force_median * 100.0 << "% p95 "
     << force_p95 * 100.0 << "%, direction p99 " << direction_p99_deg << " deg";
  if (surface_triangles > 0)
    os << "; refined against " << surface_triangles << " of " << full_triangles << " triangles (simplified within "
       << surface_bound << ", measured max " << surface_deviation_max << ", p99 " << surface_deviation_p99
       << (surface_map_side > 0 ? "; shaded by a normal map of side " + std::to_string(surface_map_side)
                                : "; shading fitted, normals within " + fmt(surface_normal_median_deg) +
                                      " deg median, " + fmt(surface_normal_p99_deg) + " p99")
       << ")";
  if (answer != Answerer::none) os << "; answered by " << answerer_words(answer);
  if (cells_ns > 0 && embree_ns > 0)
    os << " (a query at bake time: the cells " << cells_ns << " ns, Embree " << embree_ns << " ns)";
  else if (answer_ns > 0 && exact_ns > 0)
    os << " (" << answer_ns << " ns a query against exact's " << exact_ns << " at bake time)";
  if (stroke_answer == Answerer::embree)
    os << "; along strokes by exact Embree over the full mesh (" << stroke_embree_ns << " ns a query against the cells' "
       << stroke_cells_ns << " at bake time)";
  else if (stroke_answer == Answerer::cells && stroke_cells_ns > 0)
    os << "; along strokes by the cells too (" << stroke_cells_ns << " ns a query against Embree's " << stroke_embree_ns
       << " over the full mesh at bake time)";
  else if (stroke_answer == Answerer::cells)
    os << "; along strokes by the cells too (the full mesh too large to keep for Embree)";
  for (const RawTried& t : raw_tried) {
    os << "; raw m" << t.m << " n" << t.n << " " << t.outcome << ": " << t.probes_felt * 100.0 << "% of probes";
    if (t.light_felt >= 0) os << ", " << t.light_felt * 100.0 << "% of light touches";
    if (t.ticks_felt >= 0) os << ", " << t.ticks_felt * 100.0 << "% of slide ticks";
    os << " felt, " << t.bytes / 1e6 << " MB";
    if (t.box_ns > 0) os << ", " << t.box_ns << " ns a query against exact's " << t.exact_ns;
    if (t.box_stroke_ns > 0) os << ", along strokes " << t.box_stroke_ns << " ns against " << t.exact_stroke_ns;
  }
  if (surface_rejected > 0)
    os << "; a surface simplified to " << surface_rejected << " triangles missed the budget ("
       << (surface_rejected_why.empty() ? std::string("fresh probes or T2's trajectories") : surface_rejected_why) << "): "
       << (surface_triangles > 0 ? "simplified again within a tighter bound" : "baked on the full mesh");
  return os.str();
}

} // namespace hb
