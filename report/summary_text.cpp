#include "summary_text.h"
#include "figure_text.h"
#include "perceptible_text.h"
#include <filesystem>
#include <sstream>

namespace hb {

std::string densities_text(const ReportData& d) {
  const DensityRange& r = d.densities;
  return "m " + range_text(r.m_min, r.m_max) + ", n " + range_text(r.n_min, r.n_max);
}

std::string report_summary_text(const ReportData& d, const std::string& dir) {
  const ComparisonStats& s = d.stats;
  const ReportTolerances& tol = d.options.tolerances;
  std::ostringstream o;
  const std::string mesh = std::filesystem::path(d.mesh_path).filename().string();
  o << "measured: the haptic box (" << (d.box_path.empty() ? std::string("baked for the report") : d.box_path) << ": "
    << d.pieces << (d.pieces == 1 ? " box, " : " boxes, ") << densities_text(d) << ", codec " << d.codec
    << (d.refine ? ", exact refinement" : "")
    << (d.route == Answerer::boxes ? "" : std::string(", answered by ") + answerer_words(d.route)) << ") against the exact answer (Embree on the "
    << count_text(double(d.triangles)) << "-triangle mesh " << mesh << "), on the same " << count_text(double(s.samples))
    << " random probes (seed " << d.options.probes.seed << ")\n";
  o << "workspace: " << d.workspace.describe() << "\n";
  o << "accuracy: " << perceptible_headline(s) << ": " << (d.pass() ? "within" : "OUTSIDE")
    << " the budget (at most " << percent(tol.perceptible) << "; a difference is perceptible beyond "
    << thresholds_text(s.thresholds) << ", or a contact on one side only above " << sig(s.thresholds.floor_n)
    << " N); force difference median " << sig(s.force_difference_median_n) << " N, p95 "
    << sig(s.force_difference_p95_n) << " N (exact's median force " << sig(s.exact_force_median_n) << " N)\n";
  o << "light touches at any angle (" << light_touch_words() << "): " << perceptible_headline(d.light_touch) << "\n";
  o << "secondary: contact agreement " << agreement_percent(s.contact_agreement) << " (" << s.false_contacts
    << " false, " << s.missed_contacts << " missed contacts); relative force error median "
    << percent(s.force_error_median) << ", p95 " << percent(s.force_error_p95) << " (the former budget: median <= "
    << percent(tol.force_error_median) << ", p95 <= " << percent(tol.force_error_p95) << ", agreement >= "
    << percent(tol.contact_agreement) << ": " << (d.pass_median && d.pass_p95 && d.pass_agreement ? "within" : "outside")
    << ")\n";
  const WorstProbe* worst = nullptr;
  for (const WorstProbe& w : d.worst)
    if (w.kind == WorstProbe::Kind::force_error) {
      worst = &w;
      break;
    }
  if (worst)
    o << "largest force error: " << percent(worst->relative_error) << " at probe " << worst->index << ", a "
      << worst->cause << "\n";
  const std::string where = dir.empty() ? std::string("report.html") : (std::filesystem::path(dir) / "report.html").string();
  if (!d.worst.empty())
    o << "worst probes: " << d.worst.size() << " listed (where, how wrong, why) in " << where
      << " and summary.json (\"worst_probes\"); rows of samples.csv by probe number\n";
  double exact_ns = 0.0;
  for (const SweepRow& r : d.rows)
    if (r.method == "exact_embree") exact_ns = r.query_ns;
  if (d.box_ns > 0 && exact_ns > 0)
    o << "speed: the box is " << speed_verdict(d.box_ns, exact_ns) << " on this mesh (" << duration_text(d.box_ns * 1e-9)
      << " against " << duration_text(exact_ns * 1e-9) << " a query, one at a time, one core, same probes)";
  else
    o << "speed: not measured";
  if (d.stroke_route == Answerer::embree && d.stroke_route != d.route)
    o << "\nalong strokes (the servo loop, the window): exact Embree over the full mesh answers a probe's successive "
         "queries, measured faster there by the bake ("
      << duration_text(d.stroke_embree_ns * 1e-9) << " against the cells' " << duration_text(d.stroke_cells_ns * 1e-9) << ")";
  return o.str();
}

} // namespace hb
