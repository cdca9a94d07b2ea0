// HapticSession: the composition of the window's model, jobs and device.
//  1. The device follows the model (connected first, so a new mesh stops the servo thread and
//     new boxes restart it before any widget hears of them).
//  2. The parts' signals are forwarded as the session's own.
//  3. openMesh and openBoxFile refuse while a job runs (the job reads the model); opening a
//     mesh then loads the cached bake for the current settings.
#include "HapticSession.h"
#include "BackgroundJob.h"
#include <chrono>
#include <cstdio>

HapticSession::HapticSession(QObject* parent)
    : QObject(parent),
      model_(std::make_unique<SessionModel>()),
      device_(std::make_unique<SessionDevice>(model_.get())),
      jobs_(std::make_unique<SessionJobs>(model_.get())) {
  connect(model_.get(), &SessionModel::meshChanged, this, &HapticSession::meshChanged);
  connect(model_.get(), &SessionModel::boxesChanged, this, &HapticSession::boxesChanged);
  connect(model_.get(), &SessionModel::errorFieldChanged, this, &HapticSession::errorFieldChanged);
  connect(model_.get(), &SessionModel::statusMessage, this, &HapticSession::statusMessage);
  connect(jobs_.get(), &SessionJobs::cacheChanged, this, &HapticSession::cacheChanged);
  connect(jobs_.get(), &SessionJobs::sweepChanged, this, &HapticSession::sweepChanged);
  connect(jobs_.get(), &SessionJobs::stabilityChanged, this, &HapticSession::stabilityChanged);
  connect(jobs_.get(), &SessionJobs::jobFinished, this, &HapticSession::jobFinished);
  connect(jobs_.get(), &SessionJobs::statusMessage, this, &HapticSession::statusMessage);
  connect(device_.get(), &SessionDevice::deviceChanged, this, &HapticSession::deviceChanged);
  connect(device_.get(), &SessionDevice::statusMessage, this, &HapticSession::statusMessage);
}

HapticSession::~HapticSession() {
  jobs_.reset();
  device_.reset();
  model_.reset();
}

bool HapticSession::openMesh(const QString& path, QString* error, const hb::vtk::ModelOptions& options) {
  if (jobs_->busy(error)) return false;
  SessionModel::OpenTiming t;
  if (!model_->openMesh(path, error, &t, options)) return false;
  const auto t0 = std::chrono::steady_clock::now();
  jobs_->loadCachedBoxes();
  if (runSettings().timing)
    std::fprintf(stderr, "open timing: read %.0f ms, hash %.0f ms, exact %.0f ms, surface %.0f ms, view %.0f ms, cache %.0f ms\n",
                 t.readMs, t.hashMs, t.exactMs, t.surfaceMs, t.viewMs,
                 std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  return true;
}

bool HapticSession::openBoxFile(const QString& path, QString* error) {
  if (model_->hasMesh() && jobs_->busy(error)) return false;
  return model_->openBoxFile(path, error);
}
