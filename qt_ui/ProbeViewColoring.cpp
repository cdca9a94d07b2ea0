// ProbeView's colouring of the model: by piece (golden-angle hues of the cell array "PieceId"),
// or by an error metric of the error field with its scalar bar (the perceptible ratio on its
// fixed scale anchored at 1, fractions in percent on viridis over [0, p95], the contact
// disagreement as a two-colour legend).
#include "ProbeView.h"
#include "error_colour_map.h"
#include <vtkActor.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkScalarBarActor.h>
#include <vtkUnsignedCharArray.h>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

void ProbeView::setColorMode(ColorMode mode, ErrorMetric metric) {
  colorMode_ = mode;
  metric_ = metric;
  updateColoring();
  renderNow();
}

void ProbeView::updateColoring() {
  scalarBar_->VisibilityOff();
  if (!surface_) return;
  const char* name = HapticSession::errorArrayName(metric_);
  vtkDataArray* field = surface_->GetPointData()->GetArray(name);
  if (colorMode_ == ColorMode::ErrorField && field && metric_ == ErrorMetric::Perceptible) {
    // Anchored at what a hand feels: below a ratio of 1 the model's plain colour (nothing to
    // see), from 1 on a ramp to kPerceptibleTop and above: only feelable differences show.
    double plain[3];
    hb::vtk::plain_surface_colour(plain);
    vtkSmartPointer<vtkLookupTable> lut = hb::vtk::perceptible_table(plain);
    surfaceMapper_->SetLookupTable(lut);
    surfaceMapper_->SetScalarModeToUsePointFieldData();
    surfaceMapper_->SelectColorArray(name);
    surfaceMapper_->SetScalarRange(0.0, hb::vtk::kPerceptibleTop);
    surfaceMapper_->ScalarVisibilityOn();
    hb::vtk::style_perceptible_bar(scalarBar_, lut, true);
    scalarBar_->VisibilityOn();
  } else if (colorMode_ == ColorMode::ErrorField && field) {
    double range[2] = {0.0, 1.0};
    // Robust range: the 95th percentile of the finite values, so a few outliers do not wash
    // the map out (the bar's top label then means "this or more").
    std::vector<double> v;
    v.reserve(static_cast<std::size_t>(field->GetNumberOfTuples()));
    for (vtkIdType i = 0; i < field->GetNumberOfTuples(); ++i) {
      const double x = field->GetTuple1(i);
      if (std::isfinite(x)) v.push_back(x);
    }
    if (!v.empty()) {
      const std::size_t k = std::min(v.size() - 1, static_cast<std::size_t>(0.95 * v.size()));
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
      range[1] = v[k] > 0.0 ? v[k] : 1.0;
    }
    if (metric_ == ErrorMetric::ContactDisagreement) range[1] = std::max(range[1], 0.05);
    // One probe a vertex makes the disagreement yes/no: a categorical legend, not a bar.
    bool categorical = metric_ == ErrorMetric::ContactDisagreement;
    for (vtkIdType i = 0; categorical && i < field->GetNumberOfTuples(); ++i) {
      const double x = field->GetTuple1(i);
      categorical = std::isnan(x) || x == 0.0 || x == 1.0;
    }
    // Fractions are shown in percent (the panel's text says %): a display copy times 100.
    const char* shown = name;
    std::string title = HapticSession::errorMetricTitle(metric_).toStdString();
    if (metric_ == ErrorMetric::Direction) title += ", deg";
    if (!categorical && metric_ != ErrorMetric::Direction) {
      static const char* kPercent = "DisplayPercent";
      auto percent = vtkSmartPointer<vtkFloatArray>::New();
      percent->SetName(kPercent);
      percent->SetNumberOfValues(field->GetNumberOfTuples());
      for (vtkIdType i = 0; i < field->GetNumberOfTuples(); ++i) percent->SetValue(i, float(100.0 * field->GetTuple1(i)));
      surface_->GetPointData()->RemoveArray(kPercent);
      surface_->GetPointData()->AddArray(percent);
      shown = kPercent;
      range[1] *= 100.0;
      title += metric_ == ErrorMetric::ContactDisagreement ? ", % of probes" : ", %";
    }
    vtkSmartPointer<vtkLookupTable> lut = categorical ? hb::vtk::agreement_table() : hb::vtk::viridis_table(range[1]);
    surfaceMapper_->SetLookupTable(lut);
    surfaceMapper_->SetScalarModeToUsePointFieldData();
    surfaceMapper_->SelectColorArray(shown);
    surfaceMapper_->SetScalarRange(categorical ? 0.0 : range[0], categorical ? 1.0 : range[1]);
    surfaceMapper_->ScalarVisibilityOn();
    hb::vtk::style_scalar_bar(scalarBar_, lut, title + "  (grey: no data)", categorical, true);
    scalarBar_->VisibilityOn();
  } else {
    vtkDataArray* pieces = surface_->GetCellData()->GetArray("PieceId");
    const double count = pieces ? pieces->GetRange()[1] + 1.0 : 1.0;
    if (count <= 1.0) {
      surfaceMapper_->ScalarVisibilityOff();
      double plain[3];
      hb::vtk::plain_surface_colour(plain);
      surfaceActor_->GetProperty()->SetColor(plain);
    } else {
      auto lut = vtkSmartPointer<vtkLookupTable>::New();
      lut->SetNumberOfTableValues(static_cast<vtkIdType>(count));
      lut->SetTableRange(0.0, count - 1.0);
      for (vtkIdType i = 0; i < static_cast<vtkIdType>(count); ++i) {
        // Golden-angle hues: neighbouring ids get distinct colours.
        const double h = std::fmod(0.61803398875 * static_cast<double>(i), 1.0);
        double rgb[3];
        vtkMath::HSVToRGB(h, 0.45, 0.95, rgb + 0, rgb + 1, rgb + 2);
        lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
      }
      surfaceMapper_->SetLookupTable(lut);
      surfaceMapper_->SetScalarModeToUseCellFieldData();
      surfaceMapper_->SelectColorArray("PieceId");
      surfaceMapper_->SetScalarRange(0.0, count - 1.0);
      surfaceMapper_->ScalarVisibilityOn();
    }
  }
  surfaceMapper_->Modified();
  updateProxyColors();
}

vtkScalarsToColors* ProbeView::surfaceColorTable() const { return surfaceMapper_->GetLookupTable(); }

bool ProbeView::surfaceColoredByScalars() const { return surfaceMapper_->GetScalarVisibility() != 0; }

vtkUnsignedCharArray* ProbeView::mappedSurfaceColors() { return surfaceMapper_->MapScalars(1.0); }

std::string ProbeView::scalarBarTitle() const { return scalarBar_->GetTitle() ? scalarBar_->GetTitle() : ""; }
