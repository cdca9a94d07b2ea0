#include "ProbeView.h"
#include "ProbeInteractorStyle.h"
#include "errors.h"
#include <QFile>
#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkCamera.h>
#include <vtkCellData.h>
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkLineSource.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkStaticCellLocator.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>
#include <chrono>
#include <cmath>

namespace {

const double kExactColor[3] = {0.15, 0.75, 0.25};   // green
const double kApproxColor[3] = {1.0, 0.45, 0.0};    // orange

vtkSmartPointer<vtkActor> makeArrow(const double color[3]) {
  auto source = vtkSmartPointer<vtkArrowSource>::New();
  source->SetShaftRadius(0.04);
  source->SetTipRadius(0.1);
  source->SetTipLength(0.3);
  source->SetShaftResolution(16);
  source->SetTipResolution(16);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(source->GetOutputPort());
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(color[0], color[1], color[2]);
  actor->GetProperty()->SetAmbient(0.3);
  actor->VisibilityOff();
  return actor;
}

/// Places the unit arrow (along +x from the origin) at `from`, pointing along `v`, `length` long.
void placeArrow(vtkActor* arrow, const hb::Vec3& from, const hb::Vec3& v, double length) {
  const float n = v.norm();
  if (!(n > 0.f) || !(length > 0.0)) {
    arrow->VisibilityOff();
    return;
  }
  const hb::Vec3 x = v / n;
  hb::Vec3 helper = std::abs(x.x()) < 0.9f ? hb::Vec3::UnitX() : hb::Vec3::UnitY();
  const hb::Vec3 y = x.cross(helper).normalized();
  const hb::Vec3 z = x.cross(y);
  auto m = vtkSmartPointer<vtkMatrix4x4>::New();
  for (int r = 0; r < 3; ++r) {
    m->SetElement(r, 0, x[r] * length);
    m->SetElement(r, 1, y[r] * length);
    m->SetElement(r, 2, z[r] * length);
    m->SetElement(r, 3, from[r]);
  }
  arrow->SetUserMatrix(m);
  arrow->VisibilityOn();
}

vtkSmartPointer<vtkTextActor> makeLegend(const char* text, const double color[3], int row) {
  auto t = vtkSmartPointer<vtkTextActor>::New();
  t->SetInput(text);
  t->GetTextProperty()->SetColor(color[0], color[1], color[2]);
  t->GetTextProperty()->SetFontSize(16);
  t->GetTextProperty()->BoldOn();
  t->GetPositionCoordinate()->SetCoordinateSystemToNormalizedDisplay();
  t->GetPositionCoordinate()->SetValue(0.01, 0.95 - 0.04 * row);
  return t;
}

}  // namespace

ProbeView::ProbeView(QWidget* parent) : QVTKOpenGLNativeWidget(parent) {
  window_ = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  setRenderWindow(window_);
  renderer_ = vtkSmartPointer<vtkRenderer>::New();
  renderer_->SetBackground(0.32, 0.34, 0.43);
  renderer_->SetBackground2(0.08, 0.08, 0.12);
  renderer_->GradientBackgroundOn();
  window_->AddRenderer(renderer_);

  surfaceMapper_ = vtkSmartPointer<vtkPolyDataMapper>::New();
  surfaceMapper_->SetStatic(1);  // the surface changes only through setSurface
  surfaceActor_ = vtkSmartPointer<vtkActor>::New();
  surfaceActor_->SetMapper(surfaceMapper_);
  surfaceActor_->GetProperty()->SetSpecular(0.15);
  surfaceActor_->VisibilityOff();
  renderer_->AddActor(surfaceActor_);

  outlineMapper_ = vtkSmartPointer<vtkPolyDataMapper>::New();
  outlineMapper_->ScalarVisibilityOff();
  outlineActor_ = vtkSmartPointer<vtkActor>::New();
  outlineActor_->SetMapper(outlineMapper_);
  outlineActor_->GetProperty()->SetColor(1.0, 1.0, 0.4);
  outlineActor_->GetProperty()->SetLineWidth(1.5);
  outlineActor_->GetProperty()->LightingOff();
  outlineActor_->VisibilityOff();
  renderer_->AddActor(outlineActor_);

  probeLine_ = vtkSmartPointer<vtkLineSource>::New();
  auto probeMapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  probeMapper->SetInputConnection(probeLine_->GetOutputPort());
  probeActor_ = vtkSmartPointer<vtkActor>::New();
  probeActor_->SetMapper(probeMapper);
  probeActor_->GetProperty()->SetColor(0.3, 0.7, 1.0);
  probeActor_->GetProperty()->SetLineWidth(4);
  probeActor_->GetProperty()->SetRenderLinesAsTubes(true);
  probeActor_->VisibilityOff();
  renderer_->AddActor(probeActor_);

  auto tip = vtkSmartPointer<vtkSphereSource>::New();
  tip->SetThetaResolution(16);
  tip->SetPhiResolution(12);
  auto tipMapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  tipMapper->SetInputConnection(tip->GetOutputPort());
  tipActor_ = vtkSmartPointer<vtkActor>::New();
  tipActor_->SetMapper(tipMapper);
  tipActor_->GetProperty()->SetColor(0.3, 0.7, 1.0);
  tipActor_->VisibilityOff();
  renderer_->AddActor(tipActor_);

  exactArrow_ = makeArrow(kExactColor);
  approxArrow_ = makeArrow(kApproxColor);
  renderer_->AddActor(exactArrow_);
  renderer_->AddActor(approxArrow_);
  legendExact_ = makeLegend("-> exact force (Embree)", kExactColor, 0);
  legendApprox_ = makeLegend("-> haptic box force", kApproxColor, 1);
  renderer_->AddViewProp(legendExact_);
  renderer_->AddViewProp(legendApprox_);

  scalarBar_ = vtkSmartPointer<vtkScalarBarActor>::New();
  scalarBar_->SetNumberOfLabels(5);
  scalarBar_->SetMaximumWidthInPixels(90);
  scalarBar_->GetPositionCoordinate()->SetValue(0.88, 0.1);
  scalarBar_->SetWidth(0.1);
  scalarBar_->SetHeight(0.8);
  scalarBar_->VisibilityOff();
  renderer_->AddViewProp(scalarBar_);

  picker_ = vtkSmartPointer<vtkCellPicker>::New();
  picker_->SetTolerance(0.0005);
  picker_->PickFromListOn();
  picker_->AddPickList(surfaceActor_);

  style_ = vtkSmartPointer<ProbeInteractorStyle>::New();
  style_->SetDefaultRenderer(renderer_);
  style_->ProbeCallback = [this](int x, int y, bool press) {
    hb::Vec3 p;
    if (!pickSurface(x, y, p)) return false;
    emit surfaceDragged(p, press);
    return true;
  };
  style_->DepthCallback = [this](int step) { emit depthStepped(step); };
  interactor()->SetInteractorStyle(style_);
  setFocusPolicy(Qt::StrongFocus);
}

ProbeView::~ProbeView() = default;

void ProbeView::setSurface(vtkPolyData* surface, float diagonal) {
  surface_ = surface;
  diagonal_ = diagonal > 0.f ? diagonal : 1.f;
  surfaceMapper_->SetInputData(surface);
  surfaceActor_->SetVisibility(surface != nullptr);
  picker_->RemoveAllLocators();
  if (surface) {
    locator_ = vtkSmartPointer<vtkStaticCellLocator>::New();
    locator_->SetDataSet(surface);
    locator_->BuildLocator();
    picker_->AddLocator(locator_);
  }
  auto* tipSource = vtkSphereSource::SafeDownCast(tipActor_->GetMapper()->GetInputAlgorithm());
  if (tipSource) tipSource->SetRadius(0.006 * diagonal_);
  probeActor_->VisibilityOff();
  tipActor_->VisibilityOff();
  exactArrow_->VisibilityOff();
  approxArrow_->VisibilityOff();
  lastShown_.fill(0.f);
  updateColoring();
  resetCamera();
}

void ProbeView::setOutlines(vtkPolyData* outlines) {
  outlineMapper_->SetInputData(outlines);
  outlineMapper_->Modified();
}

void ProbeView::setOutlinesVisible(bool on) {
  outlineActor_->SetVisibility(on);
  renderNow();
}

bool ProbeView::outlinesVisible() const { return outlineActor_->GetVisibility() != 0; }

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
  if (colorMode_ == ColorMode::ErrorField && field) {
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
    auto lut = vtkSmartPointer<vtkLookupTable>::New();
    lut->SetHueRange(0.667, 0.0);  // blue (small error) to red (large)
    lut->SetTableRange(range);
    lut->SetNanColor(0.55, 0.55, 0.55, 1.0);  // no data: grey, not zero error
    lut->SetUseAboveRangeColor(true);
    lut->SetAboveRangeColor(0.6, 0.0, 0.0, 1.0);
    lut->Build();
    surfaceMapper_->SetLookupTable(lut);
    surfaceMapper_->SetScalarModeToUsePointFieldData();
    surfaceMapper_->SelectColorArray(name);
    surfaceMapper_->SetScalarRange(range);
    surfaceMapper_->ScalarVisibilityOn();
    scalarBar_->SetLookupTable(lut);
    scalarBar_->SetTitle(HapticSession::errorMetricTitle(metric_).toUtf8().constData());
    scalarBar_->VisibilityOn();
  } else {
    vtkDataArray* pieces = surface_->GetCellData()->GetArray("PieceId");
    const double count = pieces ? pieces->GetRange()[1] + 1.0 : 1.0;
    if (count <= 1.0) {
      surfaceMapper_->ScalarVisibilityOff();
      surfaceActor_->GetProperty()->SetColor(0.93, 0.82, 0.66);
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
}

void ProbeView::setReading(const ProbeReading& r, double forceScale) {
  std::array<float, 12> key{};
  if (r.placed) {
    key = {r.segment.end.x(), r.segment.end.y(), r.segment.end.z(), r.segment.start.x(),
           r.segment.start.y(), r.segment.start.z(), r.exact.force.x(), r.exact.force.y(),
           r.exact.force.z(), r.approx.force.x(), r.approx.force.y(), r.approx.force.z()};
  }
  if (key == lastShown_) return;  // nothing moved: no render
  lastShown_ = key;
  probeActor_->SetVisibility(r.placed);
  tipActor_->SetVisibility(r.placed);
  if (!r.placed) {
    exactArrow_->VisibilityOff();
    approxArrow_->VisibilityOff();
    renderNow();
    return;
  }
  probeLine_->SetPoint1(r.segment.start.x(), r.segment.start.y(), r.segment.start.z());
  probeLine_->SetPoint2(r.segment.end.x(), r.segment.end.y(), r.segment.end.z());
  tipActor_->SetPosition(r.segment.end.x(), r.segment.end.y(), r.segment.end.z());
  if (r.exact.contact)
    placeArrow(exactArrow_, r.exact.point, r.exact.force, r.exact.force.norm() * forceScale);
  else
    exactArrow_->VisibilityOff();
  if (r.approx.contact)
    placeArrow(approxArrow_, r.approx.point, r.approx.force, r.approx.force.norm() * forceScale);
  else
    approxArrow_->VisibilityOff();
  renderNow();
}

void ProbeView::setProbeMode(bool on) { style_->SetProbeMode(on); }

bool ProbeView::pickSurface(int x, int y, hb::Vec3& point) const {
  if (!surface_) return false;
  if (!picker_->Pick(x, y, 0.0, renderer_)) return false;
  if (picker_->GetCellId() < 0) return false;
  const double* p = picker_->GetPickPosition();
  point = hb::Vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2]));
  return true;
}

hb::Vec3 ProbeView::viewDirection() const {
  double d[3];
  renderer_->GetActiveCamera()->GetDirectionOfProjection(d);
  return hb::Vec3(static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[2])).normalized();
}

hb::Vec3 ProbeView::viewRight() const {
  double up[3];
  renderer_->GetActiveCamera()->GetViewUp(up);
  const hb::Vec3 u(static_cast<float>(up[0]), static_cast<float>(up[1]), static_cast<float>(up[2]));
  return viewDirection().cross(u).normalized();
}

void ProbeView::resetCamera() {
  renderer_->ResetCamera();
  renderNow();
}

CameraState ProbeView::cameraState() const {
  CameraState s;
  vtkCamera* c = renderer_->GetActiveCamera();
  c->GetPosition(s.position.data());
  c->GetFocalPoint(s.focalPoint.data());
  c->GetViewUp(s.viewUp.data());
  s.viewAngle = c->GetViewAngle();
  s.parallelScale = c->GetParallelScale();
  return s;
}

void ProbeView::setCameraState(const CameraState& s) {
  vtkCamera* c = renderer_->GetActiveCamera();
  c->SetPosition(s.position.data());
  c->SetFocalPoint(s.focalPoint.data());
  c->SetViewUp(s.viewUp.data());
  c->SetViewAngle(s.viewAngle);
  c->SetParallelScale(s.parallelScale);
  renderer_->ResetCameraClippingRange();
  renderNow();
}

void ProbeView::renderNow() {
  if (isVisible()) renderWindow()->Render();
}

void ProbeView::saveScreenshot(const QString& path) {
  renderWindow()->Render();
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(renderWindow());
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  auto writer = vtkSmartPointer<vtkPNGWriter>::New();
  writer->SetFileName(QFile::encodeName(path).constData());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0 || !QFile::exists(path))
    throw hb::IoError(QFile::encodeName(path).toStdString() + ": cannot write the screenshot");
}

double ProbeView::measureFrameRate(int frames) {
  vtkCamera* c = renderer_->GetActiveCamera();
  renderWindow()->Render();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < frames; ++i) {
    c->Azimuth(360.0 / frames);
    renderWindow()->Render();
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s > 0 ? frames / s : 0.0;
}

bool ProbeView::exactArrowShown() const { return exactArrow_->GetVisibility() != 0; }
bool ProbeView::approxArrowShown() const { return approxArrow_->GetVisibility() != 0; }
bool ProbeView::scalarBarShown() const { return scalarBar_->GetVisibility() != 0; }
