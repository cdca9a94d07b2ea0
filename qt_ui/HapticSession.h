#pragma once
// The window's logic (3D Slicer's "Logic" apart from the widgets), composed of three parts,
// a file each:
//  - SessionModel:  the mesh (through the pipeline's reader), its hash, surface, references,
//                   the boxes in use and their error field;
//  - SessionJobs:   bake (the default recipe of `hapticbox bake`), error field, sweep, report
//                   on the one background worker, and the box cache;
//  - SessionDevice: the device choice, the servo thread's lifecycle and rate, the probe.
// HapticSession owns the three, forwards their signals, and gives the widgets one object to
// call; it computes nothing itself. It holds no widget and renders nothing.
#include "SessionDevice.h"
#include "SessionJobs.h"
#include "SessionModel.h"
#include "SessionRunSettings.h"
#include <QObject>
#include <QString>
#include <QStringList>
#include <memory>
#include <optional>

class BackgroundJob;

class HapticSession : public QObject {
  Q_OBJECT
public:
  explicit HapticSession(QObject* parent = nullptr);
  ~HapticSession() override;  ///< stops the job, then the servo thread.

  /// The parts (for code that needs one concern only).
  SessionModel* model() const { return model_.get(); }
  SessionJobs* jobs() const { return jobs_.get(); }
  SessionDevice* device() const { return device_.get(); }

  /// How the sessions of this process run (SessionRunSettings). Set before the first session.
  using RunSettings = SessionRunSettings;
  static void setRunSettings(const RunSettings& s) { sessionRunSettings() = s; }
  static RunSettings runSettings() { return sessionRunSettings(); }

  // --- model (SessionModel) --------------------------------------------------------------
  /// Reads a model (SessionModel::openMesh) and, when a cached bake for the current settings
  /// exists, loads it. Fails while a job runs. On failure the previous model stays and
  /// `error` names the file and the cause.
  bool openMesh(const QString& path, QString* error = nullptr, const hb::vtk::ModelOptions& options = {});
  bool hasMesh() const { return model_->hasMesh(); }
  QString meshPath() const { return model_->meshPath(); }
  const hb::TriangleMesh& mesh() const { return model_->mesh(); }
  std::uint64_t meshHash() const { return model_->meshHash(); }
  float diagonal() const { return model_->diagonal(); }
  QStringList meshWarnings() const { return model_->meshWarnings(); }
  vtkPolyData* surface() const { return model_->surface(); }
  vtkPolyData* outlines() const { return model_->outlines(); }
  static QString meshFileFilter() { return SessionModel::meshFileFilter(); }
  bool hasBoxes() const { return model_->hasBoxes(); }
  const hb::BoxScene* boxes() const { return model_->boxes(); }
  double bakeSeconds() const { return model_->bakeSeconds(); }
  bool boxesFromCache() const { return model_->boxesFromCache(); }
  /// Installs a loaded .hbox file (checked against the mesh hash); fails while a job runs.
  bool openBoxFile(const QString& path, QString* error = nullptr);
  bool saveBoxFile(const QString& path, QString* error = nullptr) const { return model_->saveBoxFile(path, error); }
  bool hasErrorField() const { return model_->hasErrorField(); }
  const hb::ErrorField* errorField() const { return model_->errorField(); }
  static const char* errorArrayName(ErrorMetric metric) { return SessionModel::errorArrayName(metric); }
  static QString errorMetricTitle(ErrorMetric metric) { return SessionModel::errorMetricTitle(metric); }

  // --- jobs (SessionJobs) ----------------------------------------------------------------
  BackgroundJob* job() const { return jobs_->job(); }
  void setBakeSettings(const BakeSettings& s) { jobs_->setBakeSettings(s); }
  const BakeSettings& bakeSettings() const { return jobs_->bakeSettings(); }
  bool loadCachedBoxes() { return jobs_->loadCachedBoxes(); }
  QString cacheDir() const { return jobs_->cacheDir(); }
  hb::BoxCacheUsage cacheUsage() const { return jobs_->cacheUsage(); }
  bool clearCache(QString* error = nullptr) { return jobs_->clearCache(error); }
  bool startBake(QString* error = nullptr) { return jobs_->startBake(error); }
  bool startErrorField(int probesPerPoint = 1, QString* error = nullptr) {
    return jobs_->startErrorField(probesPerPoint, error);
  }
  bool startSweep(const std::vector<int>& ms, const std::vector<int>& ns, std::size_t samples = 5000,
                  QString* error = nullptr) {
    return jobs_->startSweep(ms, ns, samples, error);
  }
  bool startReport(const QString& dir, const QString& errorFieldImage, std::size_t samples = 20000,
                   QString* error = nullptr) {
    return jobs_->startReport(dir, errorFieldImage, samples, error);
  }
  /// Runs the stability suite on the model's boxes (SessionJobs::startStability).
  bool startStability(std::size_t sites = 12, bool generated = true, QString* error = nullptr,
                      hb::ContactLaw law = hb::ContactLaw::penalty) {
    return jobs_->startStability(sites, generated, error, law);
  }
  const hb::StabilityReport* stabilityReport() const { return jobs_->stabilityReport(); }
  const std::vector<hb::SweepRow>& sweepRows() const { return jobs_->sweepRows(); }
  const std::vector<std::pair<double, double>>& compressionCurve() const { return jobs_->compressionCurve(); }

  // --- probe and device (SessionDevice) --------------------------------------------------
  void setProbeTarget(const hb::Vec3& surfacePoint) { device_->setProbeTarget(surfacePoint); }
  void setProbeDirection(const hb::Vec3& direction) { device_->setProbeDirection(direction); }
  hb::Vec3 probeDirection() const { return device_->probeDirection(); }
  void aimProbe(const hb::Vec3& view, const hb::Vec3& right) { device_->aimProbe(view, right); }
  double tiltDegrees() const { return device_->tiltDegrees(); }
  void setTiltDegrees(double d) { device_->setTiltDegrees(d); }
  void tilt() { device_->tilt(); }
  double forceDisplayScale() const { return device_->forceDisplayScale(); }
  void setDepthFraction(double f) { device_->setDepthFraction(f); }
  double depthFraction() const { return device_->depthFraction(); }
  float probeLength() const { return device_->probeLength(); }
  std::optional<hb::Vec3> surfacePoint() const { return device_->surfacePoint(); }
  ProbeReading reading() { return device_->reading(); }
  bool setDevice(DeviceKind kind, const QString& replayPath = {}, QString* message = nullptr,
                 const QString& falconFirmware = {}) {
    return device_->setDevice(kind, replayPath, message, falconFirmware);
  }
  DeviceKind deviceKind() const { return device_->deviceKind(); }
  bool servoRunning() const { return device_->servoRunning(); }
  void setContactLaw(hb::ContactLaw law) { device_->setContactLaw(law); }
  hb::ContactLaw contactLaw() const { return device_->contactLaw(); }
  void setEmergencyStop(bool on) { device_->setEmergencyStop(on); }
  bool emergencyStopped() const { return device_->emergencyStopped(); }

signals:
  void stabilityChanged();
  void meshChanged();
  void boxesChanged();
  void cacheChanged();
  void errorFieldChanged();
  void sweepChanged();
  void deviceChanged(const QString& description);
  void jobFinished(const QString& name, bool ok, const QString& message);
  void statusMessage(const QString& message);

private:
  // Destroyed in reverse: the job first (it writes into the jobs' results), then the servo
  // thread, then the model both read.
  std::unique_ptr<SessionModel> model_;
  std::unique_ptr<SessionDevice> device_;
  std::unique_ptr<SessionJobs> jobs_;
};
