#pragma once
// The stability section of report.html: the suite's table (test, metric, box, exact,
// difference, threshold, verdict) and a plot of the force along one trajectory.
#include "stability/stability_suite.h"
#include <string>

namespace hb {

/// Plots |F| of the box and of exact along a trajectory into a PNG (PLplot, no display).
/// Throws hb::IoError when the file cannot be written.
void plot_force_trace(const ForceTrace& trace, const std::string& png_path);

/// The HTML of the section (self-contained: the plot as a data URI); its chart goes into
/// `charts_dir` (created by the caller).
std::string stability_html_section(const StabilityReport& report, const std::string& charts_dir);

} // namespace hb
