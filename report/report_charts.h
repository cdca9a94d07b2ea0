#pragma once
// The report's charts, drawn with PLplot's cairo drivers (a path ending .svg: SVG, otherwise
// PNG): no display needed.
#include "perception/perceptible.h"
#include "recipe/sweep.h"
#include <string>
#include <utility>
#include <vector>

namespace hb {

/// Where a chart's point labels go (plot_speed_accuracy), in axis units: each label beside its
/// point without covering another label or point, trying right above, left above, right below,
/// left below, then a line further up or down; never more than 1.6 lines from its point. A
/// label that finds no free place is left out unless `must` (a reference, a point of the
/// front, the default bake), which then takes the place inside the axes across that covers
/// the least of the labels and marks already there.
class LabelPlacer {
public:
  /// Width of a character of the charts' label font, as a share of the x axis' span.
  static constexpr double kCharWidth = 0.0125;
  struct Rect { double x0 = 0, x1 = 0, y0 = 0, y1 = 0; };
  struct Placement {
    bool shown = false;
    double x = 0, y = 0;  ///< the text's anchor (its right end when `left`), baseline
    bool left = false;    ///< to the left of the point
    Rect box;             ///< what the text covers
  };
  /// The axes' extent: x0..x1 across (the span), y0..y1 up; a line is 5% of the height.
  LabelPlacer(double x0, double x1, double y0, double y1);
  /// A label of `chars` characters for the point (x, y); `big`: a reference's bigger mark.
  Placement place(double x, double y, std::size_t chars, bool must, bool big);
  /// Keeps labels off a point's mark.
  void mark(double x, double y, bool big);
  /// Keeps labels off a region (other text).
  void reserve(double x0, double x1, double y0, double y1);

private:
  double x0_, x1_, y0_, y1_;
  std::vector<Rect> taken_;
};

/// Speed against accuracy, two panels on one time axis (ns, log scale): the median force error
/// (%) on top, the contact agreement (%) below with the default budget's 99.5%, one point per
/// sweep row; references and the Pareto front marked and labelled (LabelPlacer), a legend of
/// the series present. Writes SVG (path ending .svg) or PNG.
/// Throws hb::IoError when the file cannot be written.
void plot_speed_accuracy(const std::vector<SweepRow>& rows, const std::string& png_path);

/// Histogram of relative force errors (fractions; shown in %), `bins` bins over [0, p99].
/// Histogram of | |F_box| - |F_exact| | in newtons over the probes with a contact on either
/// side, with the perceptual thresholds drawn (F0, and w times exact's median force).
void plot_force_difference_histogram(const std::vector<double>& differences_n, const PerceptualThresholds& t,
                                     double exact_median_n, const std::string& png_path, int bins = 40);

void plot_force_error_histogram(const std::vector<double>& errors, const std::string& png_path, int bins = 40);

/// Compression curve: (compression rate, median relative force error against the raw
/// tables) points joined by a line.
void plot_compression_curve(const std::vector<std::pair<double, double>>& curve, const std::string& png_path);

} // namespace hb
