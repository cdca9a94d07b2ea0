#pragma once
// The report in a few plain sentences: what was measured, how accurate, where it was worst and
// why, and whether the box was faster or slower than exact and by how much. `hapticbox report`
// prints it, summary.txt and summary.json ("summary_text") hold it, ./run.sh shows it.
#include "report.h"
#include <string>

namespace hb {

/// The summary of `data`; `dir` (may be empty) is named as where the full report is.
std::string report_summary_text(const ReportData& data, const std::string& dir);

/// "m 8..37, n 8" (or "m 32, n 16" for one density): hb::range_text over the boxes.
std::string densities_text(const ReportData& data);


} // namespace hb
