// ProbeView: what the 3D view draws, and how.
//  1. The model (cell i = triangle i) coloured by "PieceId" (golden-angle hues) or by an error
//     array with a scalar bar: the perceptible ratio on its fixed scale anchored at 1 (below it
//     the plain colour), the other metrics viridis over [0, p95], NaN = no data in grey.
//  2. Models above 30K triangles get a quadric-clustering proxy (~15K triangles) drawn while the
//     camera or the probe moves; the full model returns 250 ms after the view is still.
//  3. The probe (handle to tip, light grey) and two arrows on one force scale, in the series
//     colours of the charts and the report: exact red, box blue.
//  4. Picking casts the mouse ray against a static cell locator of the model, so it works
//     whichever of model or proxy is on screen.
//  5. Renders are coalesced to one per event-loop pass and skipped when nothing moved.
// This file builds the view and draws the probe; the colouring is in ProbeViewColoring.cpp, the
// level-of-detail proxy and the surface preview in ProbeViewDetail.cpp, the camera and the
// screenshot in ProbeViewCamera.cpp.
#include "ProbeView.h"
#include "series_colours.h"
#include "ProbeInteractorStyle.h"
#include "errors.h"
#include <QFile>
#include <QTimer>
#include <QtGlobal>
#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkAxesActor.h>
#include <vtkCaptionActor2D.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkIdTypeArray.h>
#include <vtkPolyDataNormals.h>
#include <vtkQuadricClustering.h>
#include <vtkStaticPointLocator.h>
#include <vtkCellData.h>
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
#include <vtkFloatArray.h>
#include "error_colour_map.h"
#include <vtkSphereSource.h>
#include <vtkStaticCellLocator.h>
#include <vtkCoordinate.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>
#include <chrono>
#include <cmath>

namespace {

// The series colours of every chart and the report (series_colours.h): exact red, box blue.
const double kExactColor[3] = {hb::kExactSeries.rf(), hb::kExactSeries.gf(), hb::kExactSeries.bf()};
const double kApproxColor[3] = {hb::kBoxSeries.rf(), hb::kBoxSeries.gf(), hb::kBoxSeries.bf()};
// The probe itself: a neutral light grey, so it is never taken for either force.
const double kProbeColor[3] = {0.86, 0.86, 0.86};

vtkSmartPointer<vtkActor> makeArrow(const double color[3], double thickness) {
  auto source = vtkSmartPointer<vtkArrowSource>::New();
  source->SetShaftRadius(0.04 * thickness);
  source->SetTipRadius(0.1 * thickness);
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
  // Pixels below the view's top-left corner: the rows never overlap however short the view.
  auto corner = vtkSmartPointer<vtkCoordinate>::New();
  corner->SetCoordinateSystemToNormalizedDisplay();
  corner->SetValue(0.0, 1.0);
  t->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
  t->GetPositionCoordinate()->SetReferenceCoordinate(corner);
  t->GetPositionCoordinate()->SetValue(8, -26 - 24 * row);
  return t;
}

}  // namespace

ProbeView::ProbeView(QWidget* parent) : QVTKOpenGLNativeWidget(parent) {
  window_ = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  // No multisampling: under software OpenGL (Mesa llvmpipe) 8x MSAA multiplies the fragment
  // work for little visual gain; the frame-rate target is met without it.
  window_->SetMultiSamples(0);
  setRenderWindow(window_);
  renderer_ = vtkSmartPointer<vtkRenderer>::New();
  renderer_->SetBackground(0.32, 0.34, 0.43);
  renderer_->SetBackground2(0.08, 0.08, 0.12);
  renderer_->GradientBackgroundOn();
  window_->AddRenderer(renderer_);
  addModelActors();
  addProbeActors();
  connectInteraction();
  addOverlays();
  setFocusPolicy(Qt::StrongFocus);
}

void ProbeView::addModelActors() {
  surfaceMapper_ = vtkSmartPointer<vtkPolyDataMapper>::New();
  surfaceMapper_->SetStatic(1);  // the surface changes only through setSurface
  surfaceActor_ = vtkSmartPointer<vtkActor>::New();
  surfaceActor_->SetMapper(surfaceMapper_);
  surfaceActor_->GetProperty()->SetSpecular(0.0);  // cheaper fragments under software GL
  surfaceActor_->VisibilityOff();
  renderer_->AddActor(surfaceActor_);

  proxyMapper_ = vtkSmartPointer<vtkPolyDataMapper>::New();
  proxyMapper_->SetStatic(1);
  proxyActor_ = vtkSmartPointer<vtkActor>::New();
  proxyActor_->SetMapper(proxyMapper_);
  proxyActor_->SetProperty(surfaceActor_->GetProperty());
  proxyActor_->VisibilityOff();
  proxyActor_->PickableOff();
  renderer_->AddActor(proxyActor_);
  // The Surface panel's preview: its own colour (a pale blue, never the model's beige), in
  // place of the model until it is extracted or dropped.
  previewMapper_ = vtkSmartPointer<vtkPolyDataMapper>::New();
  previewMapper_->ScalarVisibilityOff();
  previewActor_ = vtkSmartPointer<vtkActor>::New();
  previewActor_->SetMapper(previewMapper_);
  previewActor_->GetProperty()->SetColor(0.72, 0.84, 0.96);
  previewActor_->GetProperty()->SetSpecular(0.0);
  previewActor_->PickableOff();
  previewActor_->VisibilityOff();
  renderer_->AddActor(previewActor_);
  previewCaption_ = vtkSmartPointer<vtkTextActor>::New();
  previewCaption_->GetTextProperty()->SetFontSize(15);
  previewCaption_->GetTextProperty()->SetColor(0.72, 0.84, 0.96);
  previewCaption_->GetTextProperty()->BoldOn();
  previewCaption_->GetTextProperty()->SetJustificationToCentered();
  previewCaption_->GetTextProperty()->SetVerticalJustificationToBottom();
  previewCaption_->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  previewCaption_->GetPositionCoordinate()->SetValue(0.5, 0.03);  // bottom centre: clear of the legend
  previewCaption_->VisibilityOff();
  renderer_->AddViewProp(previewCaption_);
  stillTimer_ = new QTimer(this);
  stillTimer_->setSingleShot(true);
  stillTimer_->setInterval(250);
  connect(stillTimer_, &QTimer::timeout, this, [this] {
    setInteracting(false);
    renderNow();
  });

  outlineMapper_ = vtkSmartPointer<vtkPolyDataMapper>::New();
  outlineMapper_->ScalarVisibilityOff();
  outlineActor_ = vtkSmartPointer<vtkActor>::New();
  outlineActor_->SetMapper(outlineMapper_);
  outlineActor_->GetProperty()->SetColor(1.0, 1.0, 0.4);
  outlineActor_->GetProperty()->SetLineWidth(1.5);
  outlineActor_->GetProperty()->LightingOff();
  outlineActor_->VisibilityOff();
  renderer_->AddActor(outlineActor_);
}

void ProbeView::addProbeActors() {
  probeLine_ = vtkSmartPointer<vtkLineSource>::New();
  auto probeMapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  probeMapper->SetInputConnection(probeLine_->GetOutputPort());
  probeActor_ = vtkSmartPointer<vtkActor>::New();
  probeActor_->SetMapper(probeMapper);
  probeActor_->GetProperty()->SetColor(kProbeColor[0], kProbeColor[1], kProbeColor[2]);
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
  tipActor_->GetProperty()->SetColor(kProbeColor[0], kProbeColor[1], kProbeColor[2]);
  tipActor_->VisibilityOff();
  renderer_->AddActor(tipActor_);

  // When the two agree they coincide: the exact arrow is a thicker sleeve drawn from inside
  // (front faces culled: its far wall shows, opaque and lit from both sides) and the box's a
  // thinner solid core, so the blue shows whole inside a red rim instead of behind it.
  exactArrow_ = makeArrow(kExactColor, 2.0);
  exactArrow_->GetProperty()->FrontfaceCullingOn();
  approxArrow_ = makeArrow(kApproxColor, 1.0);
  // An arrow seen end on is a disc: a caption at its tip says which way it points.
  const auto caption = [this](const double color[3], bool below) {
    auto t = vtkSmartPointer<vtkTextActor>::New();
    t->GetTextProperty()->SetColor(color[0], color[1], color[2]);
    t->GetTextProperty()->SetFontSize(15);
    t->GetTextProperty()->BoldOn();
    t->GetTextProperty()->ShadowOn();
    t->GetTextProperty()->SetVerticalJustification(below ? VTK_TEXT_TOP : VTK_TEXT_BOTTOM);
    t->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    t->VisibilityOff();
    t->PickableOff();
    renderer_->AddViewProp(t);
    return t;
  };
  exactCaption_ = caption(kExactColor, false);
  approxCaption_ = caption(kApproxColor, true);
  auto beforeRender = vtkSmartPointer<vtkCallbackCommand>::New();
  beforeRender->SetClientData(this);
  beforeRender->SetCallback(
      [](vtkObject*, unsigned long, void* self, void*) { static_cast<ProbeView*>(self)->updateArrowCaptions(); });
  renderer_->AddObserver(vtkCommand::StartEvent, beforeRender);
  renderer_->AddActor(exactArrow_);
  renderer_->AddActor(approxArrow_);
  legendExact_ = makeLegend("-> exact force (Embree)", kExactColor, 0);
  legendApprox_ = makeLegend("-> haptic box force", kApproxColor, 1);
  renderer_->AddViewProp(legendExact_);
  renderer_->AddViewProp(legendApprox_);
}

void ProbeView::addOverlays() {
  // A horizontal bar along the bottom: its title reads whole, whatever its length.
  scalarBar_ = vtkSmartPointer<vtkScalarBarActor>::New();
  scalarBar_->SetOrientationToHorizontal();
  scalarBar_->SetUnconstrainedFontSize(true);
  scalarBar_->GetPositionCoordinate()->SetValue(0.2, 0.06);
  scalarBar_->SetWidth(0.6);
  scalarBar_->SetHeight(0.12);
  scalarBar_->SetBarRatio(0.3);
  scalarBar_->SetVerticalTitleSeparation(4);
  scalarBar_->VisibilityOff();
  renderer_->AddViewProp(scalarBar_);
  // Orientation axes in the lower-left corner, as ParaView and Slicer show them.
  auto axes = vtkSmartPointer<vtkAxesActor>::New();
  axes->SetShaftTypeToCylinder();
  axes->SetCylinderRadius(0.04);
  axes->SetConeRadius(0.5);
  for (vtkCaptionActor2D* c : {axes->GetXAxisCaptionActor2D(), axes->GetYAxisCaptionActor2D(), axes->GetZAxisCaptionActor2D()}) {
    c->GetCaptionTextProperty()->ItalicOff();
    c->GetCaptionTextProperty()->ShadowOff();
    c->GetCaptionTextProperty()->BoldOn();
  }
  axesWidget_ = vtkSmartPointer<vtkOrientationMarkerWidget>::New();
  axesWidget_->SetOrientationMarker(axes);
  axesWidget_->SetInteractor(interactor());
  axesWidget_->SetViewport(0.0, 0.0, 0.14, 0.2);
  axesWidget_->SetEnabled(1);
  axesWidget_->InteractiveOff();
}

void ProbeView::connectInteraction() {
  style_ = vtkSmartPointer<ProbeInteractorStyle>::New();
  style_->SetDefaultRenderer(renderer_);
  style_->ProbeCallback = [this](int x, int y, bool press) {
    hb::Vec3 p;
    if (press) setInteracting(true);
    if (!pickSurface(x, y, p)) return false;
    emit surfaceDragged(p, press);
    return true;
  };
  style_->DepthCallback = [this](int step) { emit depthStepped(step); };
  interactor()->SetInteractorStyle(style_);
  auto interaction = vtkSmartPointer<vtkCallbackCommand>::New();
  interaction->SetClientData(this);
  interaction->SetCallback([](vtkObject*, unsigned long event, void* self, void*) {
    auto* view = static_cast<ProbeView*>(self);
    if (event == vtkCommand::StartInteractionEvent) {
      view->stillTimer_->stop();
      view->setInteracting(true);
    } else {
      view->stillTimer_->start();
    }
  });
  style_->AddObserver(vtkCommand::StartInteractionEvent, interaction);
  style_->AddObserver(vtkCommand::EndInteractionEvent, interaction);
}

ProbeView::~ProbeView() = default;

void ProbeView::setSurface(vtkPolyData* surface, float diagonal) {
  surface_ = surface;
  diagonal_ = diagonal > 0.f ? diagonal : 1.f;
  surfaceMapper_->SetInputData(surface);
  surfaceActor_->SetVisibility(surface != nullptr);
  locator_ = nullptr;
  if (surface) {
    locator_ = vtkSmartPointer<vtkStaticCellLocator>::New();
    locator_->SetDataSet(surface);
    locator_->BuildLocator();
  }
  auto* tipSource = vtkSphereSource::SafeDownCast(tipActor_->GetMapper()->GetInputAlgorithm());
  if (tipSource) tipSource->SetRadius(0.006 * diagonal_);
  probeActor_->VisibilityOff();
  tipActor_->VisibilityOff();
  exactArrow_->VisibilityOff();
  approxArrow_->VisibilityOff();
  lastShown_.fill(0.f);
  buildProxy();
  interacting_ = true;
  setInteracting(false);
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
  // A moving probe redraws at display rate: use the proxy until it is still again.
  setInteracting(true);
  stillTimer_->start();
  if (!r.placed) {
    exactArrow_->VisibilityOff();
    approxArrow_->VisibilityOff();
    renderNow();
    return;
  }
  probeLine_->SetPoint1(r.segment.start.x(), r.segment.start.y(), r.segment.start.z());
  probeLine_->SetPoint2(r.segment.end.x(), r.segment.end.y(), r.segment.end.z());
  tipActor_->SetPosition(r.segment.end.x(), r.segment.end.y(), r.segment.end.z());
  // Both arrows on one scale (so their lengths compare), capped at a fifth of the model.
  const double cap = 0.2 * diagonal_;
  const auto place = [&](vtkActor* arrow, const hb::Contact& c, hb::Vec3& tip, hb::Vec3& dir) {
    dir = hb::Vec3::Zero();
    if (!c.contact) {
      arrow->VisibilityOff();
      return;
    }
    const double length = std::min(cap, c.force.norm() * forceScale);
    placeArrow(arrow, c.point, c.force, length);
    if (arrow->GetVisibility()) {
      dir = c.force.normalized();
      tip = c.point + dir * static_cast<float>(length);
    }
  };
  place(exactArrow_, r.exact, exactTip_, exactDir_);
  exactLength_ = r.exact.contact ? static_cast<float>(std::min(cap, r.exact.force.norm() * forceScale))
                                 : static_cast<float>(std::min(cap, r.approx.force.norm() * forceScale));
  place(approxArrow_, r.approx, approxTip_, approxDir_);
  renderNow();
}

void ProbeView::updateArrowCaptions() {
  // Within 30 degrees of the line of sight an arrow's shape no longer tells its direction.
  double d[3];
  renderer_->GetActiveCamera()->GetDirectionOfProjection(d);
  const hb::Vec3 view(static_cast<float>(d[0]), static_cast<float>(d[1]), static_cast<float>(d[2]));
  const hb::Vec3 right = viewRight();
  const float rimRadius = 0.2f * exactLength_;  // makeArrow: tip radius 0.1 x thickness 2, scaled by the length
  const auto update = [&](vtkTextActor* caption, vtkActor* arrow, const hb::Vec3& dir, const hb::Vec3& tip, const char* who) {
    const float c = dir.dot(view);
    if (!arrow->GetVisibility() || std::abs(c) < 0.866f) {
      caption->VisibilityOff();
      return;
    }
    const std::string text = std::string("  ") + who + (c < 0.f ? ": toward you" : ": away from you");
    const char* shown = caption->GetInput();
    if (!shown || text != shown) caption->SetInput(text.c_str());
    // Beside the disc, not over it: right of the exact arrow's rim (the wider of the two).
    double centre[3], rim[3];
    const hb::Vec3 edge = tip + right * rimRadius;
    renderer_->SetWorldPoint(tip.x(), tip.y(), tip.z(), 1.0);
    renderer_->WorldToDisplay();
    renderer_->GetDisplayPoint(centre);
    renderer_->SetWorldPoint(edge.x(), edge.y(), edge.z(), 1.0);
    renderer_->WorldToDisplay();
    renderer_->GetDisplayPoint(rim);
    const double gap = std::hypot(rim[0] - centre[0], rim[1] - centre[1]) + 4.0;
    caption->GetPositionCoordinate()->SetValue(centre[0] + gap, centre[1] + (caption == exactCaption_ ? 2.0 : -2.0));
    caption->VisibilityOn();
  };
  update(exactCaption_, exactArrow_, exactDir_, exactTip_, "exact");
  update(approxCaption_, approxArrow_, approxDir_, approxTip_, "box");
}

QString ProbeView::exactArrowCaption() const {
  return exactCaption_->GetVisibility() ? QString::fromUtf8(exactCaption_->GetInput()).trimmed() : QString();
}

QString ProbeView::approxArrowCaption() const {
  return approxCaption_->GetVisibility() ? QString::fromUtf8(approxCaption_->GetInput()).trimmed() : QString();
}

void ProbeView::setProbeMode(bool on) { style_->SetProbeMode(on); }

bool ProbeView::pickSurface(int x, int y, hb::Vec3& point) const {
  // The mouse ray against the model's cell locator: independent of which actor (model or
  // level-of-detail proxy) is on screen.
  if (!surface_ || !locator_) return false;
  if (preview_) return false;  // the model is hidden behind a surface preview: nothing to probe
  double p0[4], p1[4];
  renderer_->SetDisplayPoint(x, y, 0.0);
  renderer_->DisplayToWorld();
  renderer_->GetWorldPoint(p0);
  renderer_->SetDisplayPoint(x, y, 1.0);
  renderer_->DisplayToWorld();
  renderer_->GetWorldPoint(p1);
  if (p0[3] == 0.0 || p1[3] == 0.0) return false;
  for (int i = 0; i < 3; ++i) {
    p0[i] /= p0[3];
    p1[i] /= p1[3];
  }
  double t = 0.0, hit[3], pcoords[3];
  int subId = 0;
  vtkIdType cellId = -1;
  if (!locator_->IntersectWithLine(p0, p1, 0.0, t, hit, pcoords, subId, cellId) || cellId < 0) return false;
  point = hb::Vec3(static_cast<float>(hit[0]), static_cast<float>(hit[1]), static_cast<float>(hit[2]));
  return true;
}

void ProbeView::renderNow() {
  // Coalesced: every change of one event-loop pass (surface, colours, probe) costs one render.
  if (renderPending_) return;
  renderPending_ = true;
  QTimer::singleShot(0, this, [this] {
    renderPending_ = false;
    if (isVisible()) renderWindow()->Render();
  });
}

bool ProbeView::exactArrowShown() const { return exactArrow_->GetVisibility() != 0; }
bool ProbeView::approxArrowShown() const { return approxArrow_->GetVisibility() != 0; }
bool ProbeView::scalarBarShown() const { return scalarBar_->GetVisibility() != 0; }
std::array<double, 3> ProbeView::arrowColor(bool exact) const {
  std::array<double, 3> c{};
  (exact ? exactArrow_ : approxArrow_)->GetProperty()->GetColor(c.data());
  return c;
}