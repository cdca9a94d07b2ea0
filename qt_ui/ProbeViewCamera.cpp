// ProbeView's camera (reset, centre, standard views along the axes, orbit, saved state), the
// orientation axes, and the screenshot (magnified in tiles, optionally on a transparent
// background).
#include "ProbeView.h"
#include "errors.h"
#include <QFile>
#include <QTimer>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPNGWriter.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>
#include <string>

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

void ProbeView::centreOn(const hb::Vec3& point) {
  vtkCamera* c = renderer_->GetActiveCamera();
  double focal[3], position[3];
  c->GetFocalPoint(focal);
  c->GetPosition(position);
  for (int a = 0; a < 3; ++a) {
    const double shift = double(point[a]) - focal[a];
    focal[a] += shift;
    position[a] += shift;
  }
  c->SetFocalPoint(focal);
  c->SetPosition(position);
  renderer_->ResetCameraClippingRange();
  renderNow();
}

hb::Vec3 ProbeView::focalPoint() const {
  double f[3];
  renderer_->GetActiveCamera()->GetFocalPoint(f);
  return hb::Vec3(float(f[0]), float(f[1]), float(f[2]));
}

void ProbeView::viewAlong(int axis, int sign) {
  vtkCamera* c = renderer_->GetActiveCamera();
  double focal[3];
  c->GetFocalPoint(focal);
  const double distance = c->GetDistance();
  double position[3] = {focal[0], focal[1], focal[2]};
  position[axis] -= (sign > 0 ? 1.0 : -1.0) * distance;  // looking toward +axis: the camera on the - side
  c->SetPosition(position);
  if (axis == 2) c->SetViewUp(0.0, 1.0, 0.0);
  else c->SetViewUp(0.0, 0.0, 1.0);
  renderer_->ResetCamera();
  renderNow();
}

void ProbeView::setOrientationAxesVisible(bool on) {
  axesWidget_->SetEnabled(on ? 1 : 0);
  if (on) axesWidget_->InteractiveOff();
  renderNow();
}

bool ProbeView::orientationAxesVisible() const { return axesWidget_->GetEnabled() != 0; }

void ProbeView::orbitCamera(double azimuth, double elevation) {
  vtkCamera* c = renderer_->GetActiveCamera();
  c->Azimuth(azimuth);
  c->Elevation(elevation);
  c->OrthogonalizeViewUp();
  renderer_->ResetCameraClippingRange();
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

QSize ProbeView::viewPixels() const {
  const int* size = const_cast<ProbeView*>(this)->renderWindow()->GetSize();
  return QSize(size[0], size[1]);
}

void ProbeView::saveScreenshot(const QString& path, int magnification, bool transparent) {
  if (magnification < 1 || magnification > 8)
    throw hb::InvalidInput("screenshot magnification " + std::to_string(magnification) + " is outside [1, 8]");
  stillTimer_->stop();
  setInteracting(false);  // a screenshot shows the full model, never the proxy
  const bool gradient = renderer_->GetGradientBackground() != 0;
  if (transparent) {
    // ParaView's "transparent background": the background's alpha at 0, everything drawn opaque.
    renderer_->GradientBackgroundOff();
    renderer_->SetBackgroundAlpha(0.0);
    window_->SetAlphaBitPlanes(1);
  }
  renderWindow()->Render();
  auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New();
  grab->SetInput(renderWindow());
  // Magnified: VTK renders the view in tiles at the window's size and stitches them (text
  // and bars are placed per tile and keep their pixel size).
  grab->SetScale(magnification, magnification);
  grab->FixBoundaryOn();
  if (transparent) grab->SetInputBufferTypeToRGBA();
  else grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  if (transparent) {
    renderer_->SetBackgroundAlpha(1.0);
    renderer_->SetGradientBackground(gradient);
  }
  renderNow();
  auto writer = vtkSmartPointer<vtkPNGWriter>::New();
  writer->SetFileName(QFile::encodeName(path).constData());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0 || !QFile::exists(path))
    throw hb::IoError(QFile::encodeName(path).toStdString() + ": cannot write the screenshot");
}
