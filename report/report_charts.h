#pragma once
// The report's charts, drawn with PLplot's cairo drivers (a path ending .svg: SVG, otherwise
// PNG): no display needed.
#include "evaluation/sweep.h"
#include <string>
#include <utility>
#include <vector>

namespace hb {

/// Speed against accuracy: query ns (log scale) against median force error (%), one point
/// per sweep row, references and the Pareto front marked and labelled (labels kept inside the plot and apart), a legend of the series present.
/// Writes SVG (path ending .svg) or PNG.
/// Throws hb::IoError when the file cannot be written.
void plot_speed_accuracy(const std::vector<SweepRow>& rows, const std::string& png_path);

/// Histogram of relative force errors (fractions; shown in %), `bins` bins over [0, p99].
void plot_force_error_histogram(const std::vector<double>& errors, const std::string& png_path, int bins = 40);

/// Compression curve: (compression rate, median relative force error against the raw
/// tables) points joined by a line.
void plot_compression_curve(const std::vector<std::pair<double, double>>& curve, const std::string& png_path);

} // namespace hb
