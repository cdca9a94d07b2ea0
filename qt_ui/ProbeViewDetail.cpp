// ProbeView's level of detail: models above 30K triangles get a quadric-clustering proxy
// (~15K triangles, the error field's point arrays carried over from the nearest model vertex)
// drawn while the camera or the probe moves; and the Surface panel's preview drawn in place of
// the model.
#include "ProbeView.h"
#include <QTimer>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkIdTypeArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkQuadricClustering.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStaticPointLocator.h>
#include <vtkTextActor.h>
#include <algorithm>
#include <chrono>
#include <cmath>

void ProbeView::buildProxy() {
  proxy_ = nullptr;
  proxySource_ = nullptr;
  proxyMapper_->SetInputData(nullptr);
  constexpr vtkIdType kProxyAbove = 30000;  // triangles; smaller models are drawn as they are
  constexpr vtkIdType kProxyTarget = 15000;
  if (!surface_ || surface_->GetNumberOfCells() <= kProxyAbove) return;
  // Quadric clustering: fast (one pass) and keeps the silhouette; the grid is refined once
  // towards the target triangle count.
  int divisions = 96;
  vtkSmartPointer<vtkPolyData> coarse;
  for (int attempt = 0; attempt < 3; ++attempt) {
    auto cluster = vtkSmartPointer<vtkQuadricClustering>::New();
    cluster->SetInputData(surface_);
    cluster->SetNumberOfDivisions(divisions, divisions, divisions);
    cluster->AutoAdjustNumberOfDivisionsOn();
    cluster->CopyCellDataOn();
    cluster->Update();
    coarse = cluster->GetOutput();
    const double ratio = static_cast<double>(coarse->GetNumberOfCells()) / kProxyTarget;
    if (ratio < 1.3 && ratio > 0.5) break;
    divisions = std::max(16, static_cast<int>(divisions / std::sqrt(ratio)));
  }
  auto normals = vtkSmartPointer<vtkPolyDataNormals>::New();
  normals->SetInputData(coarse);
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->Update();
  proxy_ = normals->GetOutput();
  // Nearest model vertex of each proxy point, to carry the error field's point arrays over.
  auto locator = vtkSmartPointer<vtkStaticPointLocator>::New();
  locator->SetDataSet(surface_);
  locator->BuildLocator();
  proxySource_ = vtkSmartPointer<vtkIdTypeArray>::New();
  proxySource_->SetNumberOfTuples(proxy_->GetNumberOfPoints());
  for (vtkIdType i = 0; i < proxy_->GetNumberOfPoints(); ++i)
    proxySource_->SetValue(i, locator->FindClosestPoint(proxy_->GetPoint(i)));
  proxyMapper_->SetInputData(proxy_);
}

void ProbeView::updateProxyColors() {
  if (!proxy_) return;
  // Point arrays of the error field: copied from the nearest model vertex.
  vtkPointData* from = surface_->GetPointData();
  for (ErrorMetric m : kErrorMetrics) {
    const char* name = HapticSession::errorArrayName(m);
    vtkDataArray* a = from->GetArray(name);
    if (!a) {
      proxy_->GetPointData()->RemoveArray(name);
      continue;
    }
    vtkDataArray* b = proxy_->GetPointData()->GetArray(name);
    if (!b || b->GetMTime() < a->GetMTime()) {
      vtkSmartPointer<vtkDataArray> copy;
      copy.TakeReference(a->NewInstance());
      copy->SetName(name);
      copy->SetNumberOfComponents(1);
      copy->SetNumberOfTuples(proxy_->GetNumberOfPoints());
      for (vtkIdType i = 0; i < proxy_->GetNumberOfPoints(); ++i)
        copy->SetTuple1(i, a->GetTuple1(proxySource_->GetValue(i)));
      proxy_->GetPointData()->AddArray(copy);
    }
  }
  proxyMapper_->SetLookupTable(surfaceMapper_->GetLookupTable());
  proxyMapper_->SetScalarMode(surfaceMapper_->GetScalarMode());
  proxyMapper_->SelectColorArray(surfaceMapper_->GetArrayName());
  proxyMapper_->SetScalarRange(surfaceMapper_->GetScalarRange());
  proxyMapper_->SetScalarVisibility(surfaceMapper_->GetScalarVisibility());
  proxy_->Modified();
  proxyMapper_->Modified();
}

void ProbeView::setPreview(vtkPolyData* preview, const QString& caption) {
  if (!preview && !preview_) return;
  const bool first = preview && !preview_;
  preview_ = preview;
  previewMapper_->SetInputData(preview);
  previewActor_->SetVisibility(preview != nullptr);
  previewCaption_->SetInput(caption.toUtf8().constData());
  previewCaption_->SetVisibility(preview != nullptr && !caption.isEmpty());
  interacting_ = !interacting_;  // re-apply the visibility of the model and its proxy
  setInteracting(!interacting_);
  // The first preview is framed (a bone inside a skin is much smaller); later ones keep the
  // camera the user chose.
  if (first) renderer_->ResetCamera(preview->GetBounds());
  renderNow();
}

vtkIdType ProbeView::previewTriangles() const { return preview_ ? preview_->GetNumberOfPolys() : 0; }

vtkIdType ProbeView::proxyTriangles() const { return proxy_ ? proxy_->GetNumberOfCells() : 0; }

void ProbeView::setInteracting(bool on) {
  if (on == interacting_) return;
  interacting_ = on;
  const bool proxy = on && proxy_ != nullptr;
  const bool preview = preview_ != nullptr;
  surfaceActor_->SetVisibility(surface_ != nullptr && !proxy && !preview);
  proxyActor_->SetVisibility(proxy && !preview);
}

double ProbeView::measureFrameRate(int frames, bool interactive) {
  vtkCamera* c = renderer_->GetActiveCamera();
  stillTimer_->stop();
  setInteracting(interactive);
  renderWindow()->Render();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < frames; ++i) {
    c->Azimuth(360.0 / frames);
    renderWindow()->Render();
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  setInteracting(false);
  return s > 0 ? frames / s : 0.0;
}
