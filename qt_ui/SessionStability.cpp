// SessionJobs::startStability: the stability suite of `hapticbox stability` on the window's
// model and boxes (kept apart from SessionJobs.cpp: one small job, its own result).
#include "BackgroundJob.h"
#include "SessionJobs.h"
#include "device/safety_tick_filter.h"
#include "stability/stability_suite.h"
#include "errors.h"
#include <QFileInfo>
#include <memory>

bool SessionJobs::startStability(std::size_t sites, bool generated, QString* error, hb::ContactLaw law) {
  if (!model_->hasMesh() || !model_->hasBoxes()) {
    if (error) *error = tr("Bake (or open) the boxes first: the suite runs the box against exact on the same trajectories");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = model_->sharedMesh();
  auto boxes = model_->sharedBoxes();
  const std::string name = QFileInfo(model_->meshPath()).fileName().toStdString();
  auto result = std::make_shared<hb::StabilityReport>();
  auto done = std::make_shared<QMetaObject::Connection>();
  *done = connect(job_, &BackgroundJob::finished, this, [this, done, result](bool ok, bool, const QString&) {
    disconnect(*done);
    if (!ok) return;
    stability_ = result;
    emit stabilityChanged();
  });
  const bool started = job_->start(tr("Stability"), [mesh, boxes, name, sites, generated, law, result](const auto& progress) {
    hb::StabilityOptions so = hb::default_stability_options(*boxes, name, sites);
    hb::use_servo_force_path(so.filter, so.filter_name, so.device);
    so.generated = generated;
    so.contact_law = law;
    // One test at a time: the suite has no progress of its own; between tests the bar moves
    // and a cancel is seen. The calibration gate runs with each; the first one's is kept.
    const char* tests[] = {"T1", "T2", "T3", "T4", "T5", "T6", "T7", "T8"};
    for (int t = 0; t < 8; ++t) {
      if (!progress(t / 8.0)) throw hb::Cancelled("stability cancelled");
      so.tests = {tests[t]};
      hb::StabilityReport part = hb::run_stability_suite(*boxes, *mesh, so);
      if (t == 0) {
        result->device = part.device;
        result->filter = part.filter;
        result->depth_law = part.depth_law;
        result->contact_law = part.contact_law;
        result->calibration = part.calibration;
        result->calibration_pass = part.calibration_pass;
      }
      result->metrics.insert(result->metrics.end(), part.metrics.begin(), part.metrics.end());
      result->traces.insert(result->traces.end(), part.traces.begin(), part.traces.end());
      result->passed += part.passed;
      result->failed += part.failed;
      result->failed_law += part.failed_law;
      result->seconds += part.seconds;
    }
    progress(1.0);
  });
  if (!started) {
    disconnect(*done);
    if (error) *error = tr("%1 is running: wait for it or cancel it first").arg(job_->name());
  }
  return started;
}
