#pragma once
// The window's logic (3D Slicer's "Logic" apart from the widgets): owns the mesh, the boxes,
// the exact query, the device and its servo thread, and the long jobs. Widgets call it and
// listen to its signals; it holds no widget and renders nothing.
#include "exact/exact_query.h"
#include "device/device_choice.h"
#include "device/servo_loop.h"
#include "evaluation/error_field.h"
#include "evaluation/sweep.h"
#include "haptic_box/bake_recipe.h"
#include "haptic_box/box_cache.h"
#include "haptic_box/box_scene.h"
#include "mesh/triangle_mesh.h"
#include <QObject>
#include <QString>
#include <QStringList>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <chrono>
#include <future>
#include <memory>
#include <optional>

class BackgroundJob;
namespace hb {
struct StabilityReport;
}
class vtkHapticBoxReferenceQueries;

/// What the bake panel sets: densities, padding, pieces (none: one box, a piece file, or
/// automatic: hb::decompose_auto) and the table codec ("none", "block", "haar"; compressed at
/// the codec's default error bound).
struct BakeSettings {
  enum class Pieces { None, File, Automatic };
  int m = 16;                     ///< position points per PBB face edge.
  int n = 8;                      ///< directional points per sub-block face edge.
  float padding = 0.01f;          ///< PBB padding, fraction of its diagonal.
  Pieces pieces = Pieces::None;
  QString piecesFile;             ///< text: one integer piece id per triangle.
  QString codec = QStringLiteral("none");
  bool refine = false;            ///< store triangle ids: queries refine exactly (hb::BakeOptions::refine).
  bool useCache = true;           ///< load/save baked boxes in the box cache (hb::BoxCache).
  /// The bake these settings ask for (seams and decomposition at their defaults, the codec at
  /// its default error bound). Throws hb::InvalidInput for an unknown codec.
  hb::BakeRecipe recipe() const;
};

/// The surface metric the error-field view colours by.
enum class ErrorMetric { RelativeForce = 0, Direction = 1, ContactDisagreement = 2 };

enum class DeviceKind { Virtual = 0, Replay = 1, Falcon = 2 };

/// One display frame's worth of probe state (read by the readout and the probe view).
struct ProbeReading {
  bool placed = false;            ///< the probe has a position.
  hb::Segment segment;            ///< handle (start) to tip (end), model units.
  hb::Contact exact;              ///< the exact Embree answer on `segment`.
  hb::Contact approx;             ///< the haptic box's answer (from the servo thread when running).
  bool haveBoxes = false;
  double exactQueryNs = 0.0;      ///< this frame's exact query, GUI thread.
  double approxQueryNs = 0.0;     ///< the servo thread's last box query.
  double relativeError = 0.0;     ///< |F1 - F0| / |F0| when both are in contact.
  double angleDeg = 0.0;          ///< angle between the normals when both are in contact.
  bool deviceRunning = false;
  QString deviceName;
  double rateHz = 0.0;            ///< measured over the last window (~0.5 s).
  double p99PeriodUs = 0.0;
};

class HapticSession : public QObject {
  Q_OBJECT
public:
  explicit HapticSession(QObject* parent = nullptr);
  ~HapticSession() override;

  /// How the sessions of this process run, from hapticbox-gui's command line (--no-realtime,
  /// --spin-us, --timing; no hidden environment settings). Set before the first session.
  struct RunSettings {
    bool realtime = true;   ///< ask for SCHED_FIFO for the servo thread.
    double spinUs = 0.0;    ///< servo busy-wait before each deadline, us (0: sleep only; the window renders on the same cores).
    bool timing = false;    ///< print where opening a model spends its time (stderr).
  };
  static void setRunSettings(const RunSettings& s);
  static RunSettings runSettings();

  // --- model ---------------------------------------------------------------------------
  /// Reads a mesh (any format read_mesh takes), builds the exact query and, when a cached
  /// bake for the current settings exists, loads it. On failure the previous model stays and
  /// `error` names the file and the cause.
  bool openMesh(const QString& path, QString* error = nullptr);
  bool hasMesh() const { return mesh_ != nullptr; }
  QString meshPath() const { return meshPath_; }
  const hb::TriangleMesh& mesh() const { return *mesh_; }
  float diagonal() const { return diagonal_; }
  QStringList meshWarnings() const { return warnings_; }
  /// The surface: cell i = triangle i, cell "PieceId", point "Normals" and, after an error
  /// field, the point arrays named by errorArrayName().
  vtkPolyData* surface() const { return surface_; }
  /// PBB outlines of the current boxes (12 lines per box, cell "BoxId"); empty when none.
  vtkPolyData* outlines() const { return outlines_; }
  /// File filter of every format the reader takes.
  static QString meshFileFilter();

  // --- bake ----------------------------------------------------------------------------
  void setBakeSettings(const BakeSettings& s) { bake_ = s; }
  const BakeSettings& bakeSettings() const { return bake_; }
  /// Loads the cached bake for the current settings; false when there is none or it is stale.
  bool loadCachedBoxes();
  /// The box cache shared with the command line (hb::BoxCache at hb::default_box_cache_dir(),
  /// read when the session is made).
  QString cacheDir() const { return QString::fromStdString(cache_.dir()); }
  hb::BoxCacheUsage cacheUsage() const { return cache_.usage(); }
  /// Removes every cached box (the boxes in use stay loaded); false with `error` on failure.
  bool clearCache(QString* error = nullptr);
  /// Starts the bake on the worker thread (progress and cancel through job()).
  bool startBake(QString* error = nullptr);
  bool hasBoxes() const { return boxes_ != nullptr; }
  const hb::BoxScene* boxes() const { return boxes_.get(); }
  double bakeSeconds() const { return bakeSeconds_; }
  bool boxesFromCache() const { return boxesFromCache_; }
  /// Installs a loaded .hbox file (checked against the mesh hash when it records one).
  bool openBoxFile(const QString& path, QString* error = nullptr);
  bool saveBoxFile(const QString& path, QString* error = nullptr) const;

  /// The one worker: bake, error field, report. One job at a time.
  BackgroundJob* job() const { return job_; }

  // --- error field ---------------------------------------------------------------------
  bool startErrorField(int probesPerPoint = 1, QString* error = nullptr);
  bool hasErrorField() const { return errorField_ != nullptr; }
  const hb::ErrorField* errorField() const { return errorField_.get(); }
  static const char* errorArrayName(ErrorMetric metric);
  static QString errorMetricTitle(ErrorMetric metric);

  // --- probe ---------------------------------------------------------------------------
  /// Places the tip `depth` past `surfacePoint` along the probe direction (mouse drag).
  void setProbeTarget(const hb::Vec3& surfacePoint);
  /// Handle -> tip direction (unit). Restarts the servo thread when it changes.
  void setProbeDirection(const hb::Vec3& direction);
  hb::Vec3 probeDirection() const { return probeDirection_; }
  /// Aims the probe along the view direction `view`, tilted by tiltDegrees() about `right`.
  void aimProbe(const hb::Vec3& view, const hb::Vec3& right);
  /// Tilt of the probe away from the view direction, degrees; tilt() steps it by 15 (0..60).
  double tiltDegrees() const { return tiltDegrees_; }
  void setTiltDegrees(double d) { tiltDegrees_ = d; }
  void tilt() { tiltDegrees_ = tiltDegrees_ >= 60.0 ? 0.0 : tiltDegrees_ + 15.0; }
  /// Arrow length per newton, model units, so that the force at 1 % depth is 8 % of the diagonal.
  double forceDisplayScale() const;
  /// Sweep rows of the last report or sweep (the charts).
  const std::vector<hb::SweepRow>& sweepRows() const { return sweepRows_; }
  const std::vector<std::pair<double, double>>& compressionCurve() const { return compression_; }
  /// Runs a small sweep (m x n grid, codec none) with the exact and VTK-locator references.
  bool startSweep(const std::vector<int>& ms, const std::vector<int>& ns, std::size_t samples = 5000,
                  QString* error = nullptr);
  /// Push depth past the picked point, fraction of the diagonal; clamped to [-0.05, 0.1].
  void setDepthFraction(double f);
  double depthFraction() const { return depthFraction_; }
  float probeLength() const { return mapping_.probe_length; }
  std::optional<hb::Vec3> surfacePoint() const { return picked_; }
  /// The state to show now (GUI thread, display rate; lock-free read of the servo snapshot).
  ProbeReading reading();

  // --- device --------------------------------------------------------------------------
  /// Chooses the device. Falcon without hardware: false, `message` says so, and the
  /// virtual device is used instead. The servo thread runs while there are boxes.
  /// `falconFirmware`: a firmware file for the Falcon (empty: the device's own), as
  /// `hapticbox servo --firmware`; a hotplug monitor reports plugging in the status bar.
  bool setDevice(DeviceKind kind, const QString& replayPath = {}, QString* message = nullptr,
                 const QString& falconFirmware = {});
  DeviceKind deviceKind() const { return deviceKind_; }
  bool servoRunning() const;
  /// Emergency stop (hb::ServoLoop::emergency_stop): the device's force drops to zero on the
  /// next tick and stays zero until released; the latch survives servo restarts (a new probe,
  /// new boxes, another device).
  void setEmergencyStop(bool on);
  bool emergencyStopped() const { return estop_; }

  // --- export --------------------------------------------------------------------------
  /// Computes and writes the error report (the files of `hapticbox report`) into `dir` on the
  /// worker. `errorFieldImage`: a PNG of the rendered field to embed, or empty.
  bool startReport(const QString& dir, const QString& errorFieldImage, std::size_t samples = 20000,
                   QString* error = nullptr);

  // --- stability (the Stability tab; implemented in SessionStability.cpp) ---------------
  /// Runs the trajectory stability suite on the boxes and mesh in use, on the worker:
  /// hb::run_stability_suite with `hapticbox stability`'s defaults (Falcon profile, the
  /// servo's safety filter hold-and-ramp in T6/T8, generated walls, plates and grooves),
  /// `sites` trajectories per test, one test at a time (progress and cancel between tests);
  /// `generated` false: the model alone (as `--no-generated`).
  bool startStability(std::size_t sites = 12, bool generated = true, QString* error = nullptr);
  /// The last suite's report (null before one finished).
  const hb::StabilityReport* stabilityReport() const { return stability_.get(); }

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
  void installBoxes(std::shared_ptr<const hb::BoxScene> boxes, double seconds, bool fromCache);
  void rebuildOutlines();
  void updatePieceArray(const std::vector<std::uint32_t>& pieces);
  void startServo();
  void stopServo();
  bool busy(QString* error) const;
  hb::SourceInfo sourceInfo() const;

  BakeSettings bake_;
  hb::BoxCache cache_;
  QString meshPath_;
  QStringList warnings_;
  std::shared_ptr<hb::TriangleMesh> mesh_;
  std::uint64_t meshHash_ = 0;
  float diagonal_ = 0.f;
  // The reference methods over the mesh (exact Embree, VTK's cell locator, with their memory
  // and build times: vtkHapticBoxReferenceQueries, as the command line measures them) build
  // beside the window's own setup; readers take them from here (reading() skips the exact
  // answer until it is ready, jobs wait for it).
  std::shared_future<std::shared_ptr<const vtkHapticBoxReferenceQueries>> references_;
  const hb::ExactQuery* readyExact() const;
  vtkSmartPointer<vtkPolyData> surface_;
  vtkSmartPointer<vtkPolyData> outlines_;
  std::shared_ptr<const hb::BoxScene> boxes_;
  std::vector<std::uint32_t> boxPieces_;
  double bakeSeconds_ = 0.0;
  bool boxesFromCache_ = false;
  QString boxPath_;  ///< the box file the boxes were opened from (empty: baked or cached).
  std::unique_ptr<hb::ErrorField> errorField_;

  // Results handed from the worker to the GUI thread on finished().
  std::shared_ptr<const hb::BoxScene> pendingBoxes_;
  std::unique_ptr<hb::ErrorField> pendingField_;
  double pendingSeconds_ = 0.0;
  bool pendingFromCache_ = false;
  QString pendingCacheWarning_;

  hb::ForceLaw law_;
  hb::WorkspaceMapping mapping_;
  hb::Vec3 probeDirection_{0.f, 0.f, -1.f};
  double depthFraction_ = 0.01;
  double tiltDegrees_ = 0.0;
  std::vector<hb::SweepRow> sweepRows_, pendingRows_;
  std::vector<std::pair<double, double>> compression_, pendingCompression_;
  bool pendingRowsReady_ = false;
  std::optional<hb::Vec3> picked_;

  DeviceKind deviceKind_ = DeviceKind::Virtual;
  hb::OpenedDevice opened_;   ///< the device (hb::open_device) and its hotplug monitor.
  QString deviceName_;
  std::unique_ptr<hb::ServoLoop> loop_;
  bool estop_ = false;

  BackgroundJob* job_ = nullptr;
  std::shared_ptr<const hb::StabilityReport> stability_;
};
