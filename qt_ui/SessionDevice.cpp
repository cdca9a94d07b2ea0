// SessionDevice: the window's device and probe.
//  1. setDevice opens the chosen device through the device layer (hb::open_device: virtual,
//     replay:LOG, Falcon with firmware and hotplug monitor), falling back to the virtual one.
//  2. With boxes, the servo thread (hb::ServoLoop) runs that device against them at 1 kHz;
//     it restarts when the boxes or the probe direction change; its snapshot carries the live
//     rate and p99 period.
//  3. reading() is called at display rate: the latest servo snapshot (lock-free) gives the tip
//     and the box's answer; the exact answer is computed here on the same segment.
#include "SessionDevice.h"
#include "evaluation/comparison.h"
#include "scene/scene_extent.h"
#include <QFile>
#include <algorithm>
#include <chrono>
#include <vector>

namespace {

double elapsedNs(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
}

/// The median time of `repeats` back-to-back calls of `query` (the first one warms the caches,
/// as a benchmark's warm-up does) and the last answer.
template <class Query>
double medianQueryNs(int repeats, Query&& query) {
  std::vector<double> ns;
  ns.reserve(std::size_t(repeats));
  query();
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    query();
    ns.push_back(elapsedNs(t0));
  }
  std::nth_element(ns.begin(), ns.begin() + repeats / 2, ns.end());
  return ns[std::size_t(repeats / 2)];
}

}  // namespace

SessionDevice::SessionDevice(SessionModel* model, QObject* parent) : QObject(parent), model_(model) {
  connect(model_, &SessionModel::meshChanged, this, &SessionDevice::meshChanged);
  connect(model_, &SessionModel::boxesChanged, this, &SessionDevice::boxesChanged);
}

SessionDevice::~SessionDevice() { stopServo(); }

void SessionDevice::meshChanged() {
  stopServo();
  workspace_ = model_->workspace();
  workspace_.probe_direction = probeDirection_;
  picked_.reset();
}

void SessionDevice::boxesChanged() {
  stopServo();
  // The boxes' workspace, the one `hapticbox servo` computes from their box file: the same
  // model at the same device position then gives the CLI's newtons, bit for bit.
  if (const hb::BoxScene* boxes = model_->boxes()) {
    try {
      workspace_ = hb::scene_workspace(*boxes);
    } catch (const std::exception& e) {
      emit statusMessage(tr("Device workspace: %1").arg(QString::fromStdString(e.what())));
      workspace_ = model_->workspace();
    }
  } else if (model_->hasMesh()) {
    workspace_ = model_->workspace();
  }
  workspace_.probe_direction = probeDirection_;
  if (picked_) setProbeTarget(*picked_);
  startServo();
}

// --- probe -----------------------------------------------------------------------------

void SessionDevice::setProbeTarget(const hb::Vec3& surfacePoint) {
  picked_ = surfacePoint;
  if (opened_.virtual_device) {
    const hb::Vec3 tip = surfacePoint + probeDirection_ * static_cast<float>(depthFraction_ * model_->diagonal());
    opened_.virtual_device->set_target(workspace_.to_device(tip).cast<float>());
  }
}

void SessionDevice::setProbeDirection(const hb::Vec3& direction) {
  const hb::Vec3 d = direction.normalized();
  if (!d.allFinite() || d.dot(probeDirection_) > 0.99996f) return;  // < ~0.5 degree: keep
  probeDirection_ = d;
  workspace_.probe_direction = d;
  if (loop_) {
    stopServo();
    startServo();
  }
  if (picked_) setProbeTarget(*picked_);
}

void SessionDevice::setDepthFraction(double f) {
  depthFraction_ = std::clamp(f, -0.05, 0.1);
  if (picked_) setProbeTarget(*picked_);
}

void SessionDevice::aimProbe(const hb::Vec3& view, const hb::Vec3& right) {
  const float a = static_cast<float>(tiltDegrees_ * 3.14159265358979 / 180.0);
  setProbeDirection(Eigen::AngleAxisf(a, right.normalized()) * view.normalized());
}

double SessionDevice::forceDisplayScale() const {
  const hb::ForceLaw& law = model_->law();
  const double diagonal = model_->diagonal();
  const double f = law.stiffness_n_per_m * 0.01 * diagonal * law.metres_per_unit;
  return f > 0.0 ? 0.08 * diagonal / f : 1.0;
}

ProbeReading SessionDevice::reading() {
  ProbeReading r;
  if (!model_->hasMesh()) return r;
  const hb::BoxScene* boxes = model_->boxes();
  r.haveBoxes = boxes != nullptr;
  r.deviceName = deviceName_;
  hb::ForceLaw law = model_->law();
  hb::Vec3 tip;
  const bool servo = loop_ && loop_->running();
  r.deviceRunning = servo;
  if (servo) {
    const hb::ServoSnapshot s = loop_->snapshot();
    law = loop_->options().workspace.law();
    tip = hb::Vec3(s.tip_model[0], s.tip_model[1], s.tip_model[2]);
    r.placed = opened_.virtual_device ? picked_.has_value() : s.tick > 0;
    r.segment = hb::Segment{tip - probeDirection_ * workspace_.probe_length, tip};
    r.approx.contact = s.contact != 0;
    r.approx.depth = s.depth;
    r.approx.normal = hb::Vec3(s.normal[0], s.normal[1], s.normal[2]);
    r.approx.point = tip - probeDirection_ * s.depth;
    r.approx.force = hb::Vec3(s.desired_force_n[0], s.desired_force_n[1], s.desired_force_n[2]);
    r.servoQueryNs = s.query_ns;
    r.rateHz = s.rate_hz;  // the servo loop's own live window (about 0.5 s)
    r.p99PeriodUs = s.period_p99_us;
  } else {
    if (!picked_) return r;
    r.placed = true;
    tip = *picked_ + probeDirection_ * static_cast<float>(depthFraction_ * model_->diagonal());
    r.segment = hb::Segment{tip - probeDirection_ * workspace_.probe_length, tip};
    if (boxes) r.approx = boxes->query(r.segment, law);
  }
  if (!r.placed) return r;
  const hb::ExactQuery* exact = model_->readyExact();
  if (!exact) return r;  // the exact query is still building (a fraction of a second after open)
  // One timing story: both answers on this thread, this segment, the same repeats and median.
  r.exactQueryNs = medianQueryNs(ProbeReading::kTimingRepeats, [&] { r.exact = exact->query(r.segment, law); });
  if (boxes) {
    hb::Contact box;
    r.approxQueryNs = medianQueryNs(ProbeReading::kTimingRepeats, [&] { box = boxes->query(r.segment, law); });
    if (!servo) r.approx = box;
  }
  if (r.exact.contact && r.approx.contact) {
    r.relativeError = hb::relative_force_error(r.exact, r.approx);
    r.angleDeg = hb::angle_error_degrees(r.exact, r.approx);
  }
  return r;
}

// --- device ----------------------------------------------------------------------------

bool SessionDevice::setDevice(DeviceKind kind, const QString& replayPath, QString* message,
                              const QString& falconFirmware) {
  stopServo();
  opened_ = hb::OpenedDevice();
  bool ok = true;
  QString note;
  hb::DeviceChoice choice;
  if (kind == DeviceKind::Replay) {
    choice.kind = hb::DeviceChoice::Kind::replay;
    choice.replay_log = QFile::encodeName(replayPath).toStdString();
  } else if (kind == DeviceKind::Falcon) {
    choice.kind = hb::DeviceChoice::Kind::falcon;
    choice.falcon_firmware = QFile::encodeName(falconFirmware).toStdString();
  }
  hb::DeviceOpenOptions open;
  open.on_hotplug = [this](bool arrived, int bus, int address) {  // the monitor's thread
    QMetaObject::invokeMethod(this, [this, arrived, bus, address] {
      emit statusMessage(tr("Falcon %1 (USB bus %2 address %3)")
                             .arg(arrived ? tr("plugged in") : tr("unplugged"))
                             .arg(bus)
                             .arg(address));
    }, Qt::QueuedConnection);
  };
  try {
    opened_ = hb::open_device(choice, open);
  } catch (const std::exception& e) {
    ok = false;
    note = tr("%1; using the virtual (mouse) device").arg(QString::fromStdString(e.what()));
    kind = DeviceKind::Virtual;
    opened_ = hb::open_device(hb::DeviceChoice{});
  }
  deviceName_ = QString::fromStdString(opened_.description);
  deviceKind_ = kind;
  if (picked_) setProbeTarget(*picked_);
  startServo();
  if (message) *message = note;
  emit deviceChanged(note.isEmpty() ? deviceName_ : note);
  return ok;
}

bool SessionDevice::servoRunning() const { return loop_ && loop_->running(); }

void SessionDevice::startServo() {
  if (!model_->hasBoxes() || !model_->hasMesh()) return;
  if (!opened_.device) {
    opened_ = hb::open_device(hb::DeviceChoice{});
    deviceName_ = QString::fromStdString(opened_.description);
  }
  hb::ServoOptions o;
  o.workspace = workspace_;
  o.contact_law = contactLaw_;
  o.request_realtime = sessionRunSettings().realtime;
  // No busy-wait before each deadline: the window renders on the same cores (software GL
  // uses every core), and a real-time thread spinning 50 us per tick halves its frame rate
  // while sleeping to the deadline keeps the p99 period within a few tens of us.
  o.spin_s = sessionRunSettings().spinUs * 1e-6;
  if (opened_.rate_hz > 0.0) o.rate_hz = opened_.rate_hz;  // a replay runs at its recorded rate
  try {
    servoBoxes_ = model_->sharedBoxes();
    servoProbe_ = std::make_unique<hb::SceneProbe>(*servoBoxes_);
    loop_ = std::make_unique<hb::ServoLoop>(*opened_.device, *servoProbe_, o);
    if (estop_) loop_->emergency_stop();
    loop_->start();
  } catch (const std::exception& e) {
    loop_.reset();
    servoProbe_.reset();
    servoBoxes_.reset();
    emit statusMessage(tr("Device thread not started: %1").arg(QString::fromStdString(e.what())));
  }
}

void SessionDevice::setContactLaw(hb::ContactLaw law) {
  if (law == contactLaw_) return;
  contactLaw_ = law;
  if (loop_) {
    stopServo();
    startServo();
  }
  emit statusMessage(tr("Contact law: %1").arg(QString::fromLatin1(hb::to_string(law))));
}

std::optional<hb::ContactLaw> SessionDevice::servoContactLaw() const {
  if (!servoRunning()) return std::nullopt;
  return loop_->options().contact_law;
}

std::optional<hb::ServoOptions> SessionDevice::servoOptions() const {
  if (!servoRunning()) return std::nullopt;
  return loop_->options();
}

void SessionDevice::setEmergencyStop(bool on) {
  estop_ = on;
  if (loop_) {
    if (on) loop_->emergency_stop();
    else loop_->clear_emergency_stop();
  }
  emit statusMessage(on ? tr("Emergency stop: no force until released (Space)") : tr("Emergency stop released"));
}

void SessionDevice::stopServo() {
  if (loop_) loop_->stop();
  loop_.reset();
  servoProbe_.reset();
  servoBoxes_.reset();
}
