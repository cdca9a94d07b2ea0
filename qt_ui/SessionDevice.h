#pragma once
// The window's device (the "device" third of HapticSession): the device choice (through the
// device layer's one hb::open_device, as `hapticbox servo`), the servo thread's lifecycle
// against the model's boxes, its rate (the servo snapshot's own), the emergency stop, and the
// probe the device moves (direction, depth, tilt, the mouse's target for the virtual device).
#include "SessionModel.h"
#include "SessionRunSettings.h"
#include "device/device_choice.h"
#include "device/servo_loop.h"
#include "contact/workspace.h"
#include "scene/box_scene.h"
#include "geometry/segment.h"
#include <QObject>
#include <QString>
#include <memory>
#include <optional>

enum class DeviceKind { Virtual = 0, Replay = 1, Falcon = 2 };

/// One display frame's worth of probe state (read by the readout and the probe view).
struct ProbeReading {
  bool placed = false;            ///< the probe has a position.
  hb::Segment segment;            ///< handle (start) to tip (end), model units.
  hb::Contact exact;              ///< the exact Embree answer on `segment`.
  hb::Contact approx;             ///< the haptic box's answer (from the servo thread when running).
  bool haveBoxes = false;
  /// Both answers timed the same way, on the GUI thread on this segment: the median of
  /// kTimingRepeats back-to-back queries each (warm caches, as `hapticbox bench` times them).
  double exactQueryNs = 0.0;
  double approxQueryNs = 0.0;
  static constexpr int kTimingRepeats = 15;
  double servoQueryNs = 0.0;      ///< the servo thread's last box query (its own tick, primed).
  double relativeError = 0.0;     ///< |F1 - F0| / |F0| when both are in contact.
  double angleDeg = 0.0;          ///< angle between the normals when both are in contact.
  double maxForceN = 8.0;         ///< the device's force limit (forces are felt clamped to it).
  bool deviceRunning = false;
  QString deviceName;
  double rateHz = 0.0;            ///< measured over the last window (~0.5 s).
  double p99PeriodUs = 0.0;
};

class SessionDevice : public QObject {
  Q_OBJECT
public:
  /// Follows `model`: a new mesh stops the servo thread and takes the model's workspace, new
  /// boxes take theirs (hb::scene_workspace, as `hapticbox servo` does of the same box file)
  /// and restart it. `model` outlives this object.
  explicit SessionDevice(SessionModel* model, QObject* parent = nullptr);
  ~SessionDevice() override;  ///< stops the servo thread.

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
  /// Push depth past the picked point, fraction of the diagonal; clamped to [-0.05, 0.1].
  void setDepthFraction(double f);
  double depthFraction() const { return depthFraction_; }
  float probeLength() const { return workspace_.probe_length; }
  /// The model at the device: the servo thread's probe and force law (its probe direction is
  /// probeDirection()).
  const hb::Workspace& workspace() const { return workspace_; }
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
  /// How the servo turns answers into forces (`servo --law`): the penalty law (default) or a
  /// proxy (god-object, calm in crisp creases; docs/stability.md). A change restarts the servo
  /// thread, which ramps its force in again.
  void setContactLaw(hb::ContactLaw law);
  hb::ContactLaw contactLaw() const { return contactLaw_; }
  /// The law the running servo thread uses (the chosen one; nullopt when it is not running).
  std::optional<hb::ContactLaw> servoContactLaw() const;
  /// The options the running servo thread uses (its stiffness limited to the device's);
  /// nullopt when it is not running.
  std::optional<hb::ServoOptions> servoOptions() const;

signals:
  void deviceChanged(const QString& description);
  void statusMessage(const QString& message);

private:
  void meshChanged();
  void boxesChanged();
  void startServo();
  void stopServo();

  SessionModel* model_;
  hb::Workspace workspace_;
  hb::Vec3 probeDirection_{0.f, 0.f, -1.f};
  double depthFraction_ = 0.01;
  double tiltDegrees_ = 0.0;
  std::optional<hb::Vec3> picked_;

  DeviceKind deviceKind_ = DeviceKind::Virtual;
  hb::OpenedDevice opened_;   ///< the device (hb::open_device) and its hotplug monitor.
  QString deviceName_;
  /// The boxes the servo thread runs against (kept alive while it runs, whatever the model holds).
  std::shared_ptr<const hb::BoxScene> servoBoxes_;
  /// The servo thread's probe of them: its query state carries each tick to the next, as
  /// `hapticbox servo`'s (hb::SceneProbe; declared before loop_, which uses it, so it outlives it).
  std::unique_ptr<hb::SceneProbe> servoProbe_;
  std::unique_ptr<hb::ServoLoop> loop_;
  bool estop_ = false;
  hb::ContactLaw contactLaw_ = hb::ContactLaw::penalty;
};
