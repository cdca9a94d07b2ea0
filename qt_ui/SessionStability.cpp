// HapticSession::startStability: the stability suite of `hapticbox stability` on the window's
// model and boxes (kept apart from HapticSession.cpp: one small job, its own result).
#include "BackgroundJob.h"
#include "HapticSession.h"
#include "device/safety_tick_filter.h"
#include "evaluation/stability_suite.h"
#include "errors.h"
#include <QFileInfo>
#include <memory>

bool HapticSession::startStability(std::size_t sites, bool generated, QString* error) {
  if (!mesh_ || !boxes_) {
    if (error) *error = tr("Bake (or open) the boxes first: the suite runs the box against exact on the same trajectories");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = mesh_;
  auto boxes = boxes_;
  const std::string name = QFileInfo(meshPath_).fileName().toStdString();
  auto result = std::make_shared<hb::StabilityReport>();
  auto done = std::make_shared<QMetaObject::Connection>();
  *done = connect(job_, &BackgroundJob::finished, this, [this, done, result](bool ok, bool, const QString&) {
    disconnect(*done);
    if (!ok) return;
    stability_ = result;
    emit stabilityChanged();
  });
  const bool started = job_->start(tr("Stability"), [mesh, boxes, name, sites, generated, result](const auto& progress) {
    // The options of hb::cli::default_stability (what `hapticbox stability` runs by default).
    hb::StabilityOptions so;
    so.sites = sites;
    so.generated = generated;
    so.generated_refine = boxes->refines();
    so.model_name = name;
    hb::SafetyOptions safety;
    safety.fault_response = hb::FaultResponse::hold_and_ramp;
    hb::EnergyGuardOptions guard;
    guard.enabled = false;
    const hb::DeviceSpec spec = hb::device_spec_of(so.device);
    const double dt = so.device.period_s;
    so.filter = [spec, safety, guard, dt] {
      return std::unique_ptr<hb::TickFilter>(new hb::SafetyTickFilter(spec, safety, guard, dt));
    };
    so.filter_name = "safety hold-and-ramp";
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
