#include "error_colour_map.h"
#include <vtkLookupTable.h>
#include <vtkScalarBarActor.h>
#include <vtkTextProperty.h>
#include <vtkVariant.h>
#include <algorithm>
#include <cmath>

namespace hb::vtk {

namespace {

// matplotlib's viridis at 0, 0.1, ..., 1 (sRGB 0-255); linear in between.
constexpr unsigned char kViridis[11][3] = {{68, 1, 84},    {72, 36, 117},  {65, 68, 135},  {53, 95, 141},
                                           {42, 120, 142}, {33, 145, 140}, {34, 168, 132}, {68, 191, 112},
                                           {122, 209, 81}, {189, 223, 38}, {253, 231, 37}};
constexpr double kNoData[3] = {0.62, 0.62, 0.62};
constexpr double kPlain[3] = {0.93, 0.82, 0.66};
// The perceptible ramp at ratios 1, 2, 3, 4: amber, orange, red, dark crimson (none of them
// near the plain beige, so the first feelable difference stands out).
constexpr double kFelt[4][3] = {{1.0, 0.78, 0.10}, {0.96, 0.45, 0.06}, {0.80, 0.10, 0.10}, {0.42, 0.0, 0.22}};

} // namespace

void viridis(double t, double rgb[3]) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 10.0;
  const int i = std::min(9, int(std::floor(t)));
  const double f = t - i;
  for (int c = 0; c < 3; ++c) rgb[c] = ((1.0 - f) * kViridis[i][c] + f * kViridis[i + 1][c]) / 255.0;
}

vtkSmartPointer<vtkLookupTable> viridis_table(double range_max) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  const int n = 256;
  lut->SetNumberOfTableValues(n);
  for (int i = 0; i < n; ++i) {
    double rgb[3];
    viridis(double(i) / (n - 1), rgb);
    lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
  lut->SetTableRange(0.0, range_max > 0.0 ? range_max : 1.0);
  lut->SetNanColor(kNoData[0], kNoData[1], kNoData[2], 1.0);
  double top[3];
  viridis(1.0, top);
  lut->SetUseAboveRangeColor(true);
  lut->SetAboveRangeColor(top[0], top[1], top[2], 1.0);
  return lut;
}

void plain_surface_colour(double rgb[3]) {
  for (int c = 0; c < 3; ++c) rgb[c] = kPlain[c];
}

std::string perceptible_title() {
  return "force difference / what a hand feels  (below 1: no one can feel it)";
}

vtkSmartPointer<vtkLookupTable> perceptible_table(const double plain[3]) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  const int n = 256;
  lut->SetNumberOfTableValues(n);
  for (int i = 0; i < n; ++i) {
    // Entry i covers [i, i + 1) * top / n: below 1 plain; from 1 on the ramp.
    const double r = double(i) * kPerceptibleTop / n;
    double rgb[3];
    if (r < 1.0) {
      for (int c = 0; c < 3; ++c) rgb[c] = plain[c];
    } else {
      const double t = std::min(2.999999, (r - 1.0) * 3.0 / (kPerceptibleTop - 1.0));
      const int k = int(t);
      const double f = t - k;
      for (int c = 0; c < 3; ++c) rgb[c] = (1.0 - f) * kFelt[k][c] + f * kFelt[k + 1][c];
    }
    lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
  lut->SetTableRange(0.0, kPerceptibleTop);
  lut->SetNanColor(kNoData[0], kNoData[1], kNoData[2], 1.0);
  lut->SetUseAboveRangeColor(true);
  lut->SetAboveRangeColor(kFelt[3][0], kFelt[3][1], kFelt[3][2], 1.0);
  lut->SetUseBelowRangeColor(true);
  lut->SetBelowRangeColor(plain[0], plain[1], plain[2], 1.0);
  return lut;
}

void style_perceptible_bar(vtkScalarBarActor* bar, vtkLookupTable* table, bool dark_background) {
  style_scalar_bar(bar, table, perceptible_title(), false, dark_background);
  bar->SetDrawNanAnnotation(false);  // the ratio is defined everywhere (a missed contact counts)
  bar->SetLabelFormat("%-#.2g");
  bar->SetNumberOfLabels(int(kPerceptibleTop) + 1);
}

vtkSmartPointer<vtkLookupTable> agreement_table() {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->IndexedLookupOn();
  lut->SetNumberOfTableValues(2);
  double lo[3], hi[3];
  viridis(0.0, lo);
  viridis(1.0, hi);
  lut->SetTableValue(0, lo[0], lo[1], lo[2], 1.0);
  lut->SetTableValue(1, hi[0], hi[1], hi[2], 1.0);
  lut->SetAnnotation(vtkVariant(0.0), "contacts agree");
  lut->SetAnnotation(vtkVariant(1.0), "contacts disagree");
  lut->SetTableRange(0.0, 1.0);
  lut->SetNanColor(kNoData[0], kNoData[1], kNoData[2], 1.0);
  return lut;
}

void style_scalar_bar(vtkScalarBarActor* bar, vtkLookupTable* table, const std::string& title, bool categorical,
                      bool dark_background) {
  const double ink = dark_background ? 0.95 : 0.1;
  bar->SetLookupTable(table);
  bar->SetTitle(title.c_str());
  bar->SetUnconstrainedFontSize(true);
  bar->GetTitleTextProperty()->SetFontSize(16);
  bar->GetTitleTextProperty()->SetColor(ink, ink, ink);
  bar->GetTitleTextProperty()->ShadowOff();
  bar->GetTitleTextProperty()->BoldOn();
  bar->GetLabelTextProperty()->SetFontSize(14);
  bar->GetLabelTextProperty()->SetColor(ink, ink, ink);
  bar->GetLabelTextProperty()->ShadowOff();
  bar->GetAnnotationTextProperty()->SetFontSize(14);
  bar->GetAnnotationTextProperty()->SetColor(ink, ink, ink);
  bar->GetAnnotationTextProperty()->ShadowOff();
  bar->SetDrawNanAnnotation(true);
  bar->SetDrawAnnotations(categorical);
  bar->SetDrawTickLabels(!categorical);
  bar->SetNanAnnotation("no data");
  bar->SetDrawAboveRangeSwatch(!categorical);
  bar->SetAboveRangeAnnotation("and above");
  bar->SetLabelFormat("%-#.3g");
  bar->SetNumberOfLabels(categorical ? 0 : 5);
}

} // namespace hb::vtk
