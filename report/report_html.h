#pragma once
// report.html: one self-contained file (charts as SVG data URIs, the rendered error field as a
// PNG data URI), stamped with date, machine, command line and version, verdicts first.
#include "report.h"
#include <string>

namespace hb {

/// The chart files write_report drew (empty path: none).
struct ChartFiles {
  std::string speed, difference, histogram, compression;  ///< SVG files
  std::string stability_dir;                  ///< where the stability section draws its charts
};

/// The HTML text of the report. Throws hb::IoError when a chart file cannot be read.
std::string report_html(const ReportData& data, const ChartFiles& charts);

} // namespace hb
