#pragma once
// Where the approximation is most wrong, probe by probe, and why: the probes a report lists
// and the window offers to go to. A relative force error |F1 - F0| / |F0| is largest where the
// exact force is tiny (a contact barely touching the surface, or a probe nearly tangent to it):
// a small absolute error is then a large fraction. Each entry says which case it is.
#include "evaluation/comparison.h"
#include <string>
#include <vector>

namespace hb {

/// One probe of the worst list.
struct WorstProbe {
  enum class Kind { force_error, false_contact, missed_contact };
  Kind kind = Kind::force_error;
  std::size_t index = 0;            ///< the probe's row (samples.csv row `probe`).
  Segment segment;
  double relative_error = 0.0;      ///< |F1 - F0| / |F0| (force_error only, else 0).
  double exact_force_n = 0.0;       ///< |F0|, N.
  double approx_force_n = 0.0;      ///< |F1|, N.
  double force_difference_n = 0.0;  ///< |F1 - F0|, N.
  double exact_depth_fraction = 0.0;  ///< exact depth over the mesh diagonal.
  double approx_depth_fraction = 0.0; ///< approximated depth over the diagonal.
  /// Angle between the probe (handle -> tip) and the surface's inward normal, degrees: 0
  /// head-on, near 90 grazing. From the exact normal (the approximated one for false contacts).
  double incidence_deg = 0.0;
  std::string cause;                ///< one plain sentence: why this probe is wrong.
};

/// Options of worst_probes.
struct WorstProbeOptions {
  std::size_t force_errors = 10;    ///< largest relative force errors listed.
  std::size_t disagreements = 5;    ///< deepest false and missed contacts listed.
  double shallow_fraction = 1e-3;   ///< exact depth under this fraction of the diagonal: "shallow".
  double grazing_deg = 70.0;        ///< incidence over this: "near-grazing".
};

/// The worst probes of `records`: first the largest relative force errors (largest first),
/// then the deepest contact disagreements (deepest first). `diagonal` > 0.
std::vector<WorstProbe> worst_probes(const std::vector<ProbeRecord>& records, float diagonal,
                                     const WorstProbeOptions& options = {});

/// "force error", "false contact", "missed contact".
const char* to_string(WorstProbe::Kind kind) noexcept;

} // namespace hb
