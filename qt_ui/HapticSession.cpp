// HapticSession: the window's logic.
//  1. openMesh reads the mesh (hb::read_mesh), hashes the file, builds the exact query
//     (Embree) and the surface polydata, then tries the bake cache for the current settings.
//  2. startBake runs hb::bake on the worker (progress/cancel); the result is installed
//     on the GUI thread and saved to the cache.
//  3. With boxes, the servo thread (hb::ServoLoop) runs the chosen device (hb::open_device)
//     against them at 1 kHz; its snapshot carries the live rate and p99 period.
//  4. reading() is called at display rate: the latest servo snapshot (lock-free) gives the tip
//     and the box's answer; the exact answer is computed here on the same segment.
#include "HapticSession.h"
#include "BackgroundJob.h"
#include "device/device_error.h"
#include "device/device_choice.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/sweep.h"
#include "haptic_box/box_file.h"
#include "mesh/mesh_io.h"
#include "report_request.h"
#include "vtkHapticBoxReferenceQueries.h"
#include "vtkHapticBoxMeshReader.h"
#include "vtkHapticBoxUtilities.h"
#include <QDir>
#include <QFileInfo>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <sstream>

namespace {

// The references over `mesh`, keeping the mesh alive as long as they are (they refer to it).
std::shared_ptr<const vtkHapticBoxReferenceQueries> buildReferences(std::shared_ptr<const hb::TriangleMesh> mesh) {
  struct Held {
    std::shared_ptr<const hb::TriangleMesh> mesh;
    vtkHapticBoxReferenceQueries references;
    explicit Held(std::shared_ptr<const hb::TriangleMesh> m) : mesh(std::move(m)), references(*mesh) {}
  };
  auto held = std::make_shared<const Held>(std::move(mesh));
  return std::shared_ptr<const vtkHapticBoxReferenceQueries>(held, &held->references);
}

HapticSession::RunSettings& processRunSettings() {
  static HapticSession::RunSettings settings;
  return settings;
}

double elapsedNs(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
}



}  // namespace

HapticSession::HapticSession(QObject* parent) : QObject(parent), job_(new BackgroundJob(this)) {
  outlines_ = vtkSmartPointer<vtkPolyData>::New();
  connect(job_, &BackgroundJob::finished, this, [this](bool ok, bool cancelled, const QString& message) {
    const QString name = job_->name();
    if (ok && pendingBoxes_) {
      installBoxes(std::move(pendingBoxes_), pendingSeconds_, pendingFromCache_);
      if (!pendingCacheWarning_.isEmpty()) emit statusMessage(pendingCacheWarning_);
      emit cacheChanged();
    }
    if (ok && pendingField_) {
      errorField_ = std::move(pendingField_);
      vtkPointData* pd = surface_->GetPointData();
      pd->AddArray(vtkHapticBoxUtilities::ToScalarArray(errorArrayName(ErrorMetric::RelativeForce),
                                                        errorField_->force_error));
      pd->AddArray(vtkHapticBoxUtilities::ToScalarArray(errorArrayName(ErrorMetric::Direction),
                                                        errorField_->direction_error));
      pd->AddArray(vtkHapticBoxUtilities::ToScalarArray(errorArrayName(ErrorMetric::ContactDisagreement),
                                                        errorField_->contact_disagreement));
      surface_->Modified();
      emit errorFieldChanged();
    }
    if (ok && pendingRowsReady_) {
      sweepRows_ = std::move(pendingRows_);
      compression_ = std::move(pendingCompression_);
      emit sweepChanged();
    }
    pendingRowsReady_ = false;
    pendingBoxes_.reset();
    pendingField_.reset();
    pendingCacheWarning_.clear();
    emit jobFinished(name, ok, ok ? tr("%1 done").arg(name) : message);
    (void)cancelled;
  });
}

HapticSession::~HapticSession() {
  job_->cancel();
  job_->wait();
  stopServo();
}

QString HapticSession::meshFileFilter() {
  return tr("Meshes (*.off *.obj *.ply *.stl *.om *.vtp *.vtk);;All files (*)");
}

bool HapticSession::busy(QString* error) const {
  if (!job_->isRunning()) return false;
  if (error) *error = tr("%1 is running: wait for it or cancel it first").arg(job_->name());
  return true;
}

// --- model -----------------------------------------------------------------------------

void HapticSession::setRunSettings(const RunSettings& s) { processRunSettings() = s; }
HapticSession::RunSettings HapticSession::runSettings() { return processRunSettings(); }

bool HapticSession::openMesh(const QString& path, QString* error) {
  if (busy(error)) return false;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string p = QFile::encodeName(path).toStdString();
    const std::string ext = vtkHapticBoxUtilities::Extension(p);
    hb::MeshReadReport report;
    std::shared_ptr<hb::TriangleMesh> mesh;
    QString modelNote;
    if (ext == ".vtp" || ext == ".vtk" || hb::vtk::is_volume_or_cad(p)) {
      // VTK's own formats, volumes, CAD and scenes go through the pipeline's reader
      // (hb::vtk::load_model: the same surface as the hapticbox command with default options).
      auto reader = vtkSmartPointer<vtkHapticBoxMeshReader>::New();
      reader->SetFileName(p.c_str());
      reader->Update();
      vtkPolyData* out = reader->GetOutput();
      if (!out || out->GetNumberOfCells() == 0) throw hb::InvalidInput(p + ": no triangles could be read (see the console)");
      mesh = std::make_shared<hb::TriangleMesh>(vtkHapticBoxUtilities::ToTriangleMesh(out));
      const nlohmann::json& f = reader->GetLoadedModel().facts;
      if (f.contains("iso")) modelNote = QStringLiteral(", iso-value %1").arg(f["iso"].get<double>());
      if (f.contains("label")) modelNote = QStringLiteral(", label %1").arg(f["label"].get<long>());
      if (f.contains("chordal_deviation_mm"))
        modelNote = QStringLiteral(", chordal deviation %1 mm").arg(f["chordal_deviation_mm"].get<double>());
      if (!modelNote.isEmpty())
        modelNote = QStringLiteral(" (%1%2, mm)").arg(QString::fromStdString(reader->GetLoadedModel().format), modelNote);
    } else {
      mesh = std::make_shared<hb::TriangleMesh>(hb::read_mesh(p, &report));
    }
    const auto tRead = std::chrono::steady_clock::now();
    const std::uint64_t hash = QFileInfo(path).isDir() ? std::hash<std::string>{}(p) : hb::hash_file(p);
    const auto tHash = std::chrono::steady_clock::now();
    std::shared_future<std::shared_ptr<const vtkHapticBoxReferenceQueries>> exact =
        std::async(std::launch::async, [mesh] { return buildReferences(mesh); }).share();
    const auto tExact = std::chrono::steady_clock::now();

    // Commit: nothing below throws on a valid mesh.
    stopServo();
    boxes_.reset();
    errorField_.reset();
    boxPieces_.clear();
    references_ = std::move(exact);
    mesh_ = std::move(mesh);
    meshHash_ = hash;
    meshPath_ = QFileInfo(path).absoluteFilePath();
    diagonal_ = mesh_->bounds().diagonal();
    warnings_.clear();
    for (const auto& w : report.warnings) warnings_ << QString::fromStdString(w);
    surface_ = vtkHapticBoxUtilities::ToPolyData(*mesh_);
    updatePieceArray({});
    outlines_ = vtkSmartPointer<vtkPolyData>::New();
    const hb::Bounds b = mesh_->bounds();
    mapping_ = hb::fit_workspace(b.min, b.max, hb::virtual_device_spec());
    mapping_.probe_direction = probeDirection_;
    picked_.reset();
    const auto tSurface = std::chrono::steady_clock::now();
    emit meshChanged();
    if (!modelNote.isEmpty()) emit statusMessage(tr("Opened %1%2").arg(QFileInfo(path).fileName(), modelNote));
    const auto tView = std::chrono::steady_clock::now();
    loadCachedBoxes();
    if (runSettings().timing) {
      const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
      std::fprintf(stderr, "open timing: read %.0f ms, hash %.0f ms, exact %.0f ms, surface %.0f ms, view %.0f ms, cache %.0f ms\n",
                   ms(t0, tRead), ms(tRead, tHash), ms(tHash, tExact), ms(tExact, tSurface), ms(tSurface, tView),
                   ms(tView, std::chrono::steady_clock::now()));
    }
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

void HapticSession::updatePieceArray(const std::vector<std::uint32_t>& pieces) {
  auto ids = vtkSmartPointer<vtkIntArray>::New();
  ids->SetName("PieceId");
  ids->SetNumberOfTuples(static_cast<vtkIdType>(mesh_->triangle_count()));
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i)
    ids->SetValue(i, pieces.empty() ? 0 : static_cast<int>(pieces[static_cast<std::size_t>(i)]));
  surface_->GetCellData()->AddArray(ids);
  surface_->Modified();
}

hb::SourceInfo HapticSession::sourceInfo() const {
  hb::SourceInfo s;
  s.mesh_path = QFile::encodeName(meshPath_).toStdString();
  s.mesh_hash = meshHash_;
  s.triangles = mesh_->triangle_count();
  s.diagonal = diagonal_;
  return s;
}

// --- bake ------------------------------------------------------------------------------

hb::BakeRecipe BakeSettings::recipe() const {
  hb::BakeRecipe r;
  r.options.params.m = m;
  r.options.params.n = n;
  r.options.obb.padding = padding;
  r.options.refine = refine;
  switch (pieces) {
  case Pieces::None: break;
  case Pieces::File:
    r.pieces.kind = hb::PiecesRecipe::Kind::file;
    r.pieces.file = QFile::encodeName(piecesFile).toStdString();
    break;
  case Pieces::Automatic: r.pieces.kind = hb::PiecesRecipe::Kind::automatic; break;
  }
  r.codec.codec = hb::parse_codec(codec.toStdString());  // at the codec's default error bound
  return r;
}

bool HapticSession::clearCache(QString* error) {
  try {
    const hb::BoxCacheUsage removed = cache_.clear();
    emit cacheChanged();
    emit statusMessage(tr("Removed %1 cached box file(s), %2 MB")
                           .arg(removed.files)
                           .arg(static_cast<double>(removed.bytes) / 1e6, 0, 'f', 1));
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

bool HapticSession::loadCachedBoxes() {
  if (!mesh_ || !bake_.useCache) return false;
  try {
    const hb::BakeRecipe recipe = bake_.recipe();
    std::optional<hb::BoxScene> scene = cache_.load(meshHash_, recipe);
    if (!scene) return false;
    installBoxes(std::make_shared<hb::BoxScene>(std::move(*scene)), 0.0, true);
    emit statusMessage(tr("Loaded cached boxes %1")
                           .arg(QString::fromStdString(cache_.path_for(meshHash_, recipe))));
    return true;
  } catch (const std::exception& e) {
    emit statusMessage(tr("Ignoring the cached boxes: %1").arg(QString::fromStdString(e.what())));
    return false;
  }
}

bool HapticSession::startBake(QString* error) {
  if (!mesh_) {
    if (error) *error = tr("Open a model first");
    return false;
  }
  if (busy(error)) return false;
  hb::BakeRecipe recipe;
  try {
    recipe = bake_.recipe();
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
  auto mesh = mesh_;
  const hb::SourceInfo source = sourceInfo();
  const std::optional<hb::BoxCache> cache = bake_.useCache ? std::optional<hb::BoxCache>(cache_) : std::nullopt;
  return job_->start(tr("Bake"), [this, mesh, recipe, source, cache](const auto& progress) mutable {
    if (recipe.pieces.kind == hb::PiecesRecipe::Kind::automatic) {
      // The decomposition takes the first third of the bar, the rays the rest.
      recipe.pieces.automatic.progress = [progress](double f) { return progress(f / 3.0); };
      recipe.options.progress = [progress](double f) { return progress((1.0 + 2.0 * f) / 3.0); };
    } else {
      recipe.options.progress = progress;
    }
    hb::CachedBake baked = hb::bake_cached(*mesh, recipe, source, cache ? &*cache : nullptr);
    if (!baked.warning.empty()) pendingCacheWarning_ = QString::fromStdString(baked.warning);
    pendingSeconds_ = baked.result.stats.seconds;
    pendingFromCache_ = baked.from_cache;
    pendingBoxes_ = std::make_shared<hb::BoxScene>(std::move(baked.result.scene));
  });
}

bool HapticSession::openBoxFile(const QString& path, QString* error) {
  if (!mesh_) {
    if (error) *error = tr("Open the model the boxes were baked from first");
    return false;
  }
  if (busy(error)) return false;
  try {
    auto scene = std::make_shared<hb::BoxScene>(hb::load_box_file(QFile::encodeName(path).toStdString()));
    if (scene->source().mesh_hash != 0 && scene->source().mesh_hash != meshHash_)
      throw hb::InvalidInput(QFile::encodeName(path).toStdString() + ": baked from another mesh (" +
                             scene->source().mesh_path + ")");
    installBoxes(std::move(scene), 0.0, true);
    boxPath_ = QFileInfo(path).absoluteFilePath();
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

bool HapticSession::saveBoxFile(const QString& path, QString* error) const {
  try {
    if (!boxes_) throw hb::InvalidInput("no boxes: bake first");
    hb::save_box_file(*boxes_, QFile::encodeName(path).toStdString());
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

void HapticSession::installBoxes(std::shared_ptr<const hb::BoxScene> boxes, double seconds, bool fromCache) {
  stopServo();
  boxes_ = std::move(boxes);
  boxPieces_ = boxes_->piece_of_triangle();
  bakeSeconds_ = seconds;
  boxesFromCache_ = fromCache;
  boxPath_.clear();
  errorField_.reset();
  vtkPointData* pd = surface_->GetPointData();
  for (ErrorMetric m : {ErrorMetric::RelativeForce, ErrorMetric::Direction, ErrorMetric::ContactDisagreement})
    pd->RemoveArray(errorArrayName(m));
  updatePieceArray(boxPieces_);
  rebuildOutlines();
  startServo();
  emit boxesChanged();
  emit errorFieldChanged();
}

void HapticSession::rebuildOutlines() { outlines_ = vtkHapticBoxUtilities::BoxOutlines(*boxes_); }

// --- error field -----------------------------------------------------------------------

const char* HapticSession::errorArrayName(ErrorMetric metric) {
  switch (metric) {
  case ErrorMetric::RelativeForce: return "RelativeForceError";
  case ErrorMetric::Direction: return "DirectionError";
  case ErrorMetric::ContactDisagreement: return "ContactDisagreement";
  }
  return "RelativeForceError";
}

QString HapticSession::errorMetricTitle(ErrorMetric metric) {
  switch (metric) {
  case ErrorMetric::RelativeForce: return tr("Relative force error");
  case ErrorMetric::Direction: return tr("Direction error (deg)");
  case ErrorMetric::ContactDisagreement: return tr("Contact disagreement");
  }
  return {};
}

bool HapticSession::startErrorField(int probesPerPoint, QString* error) {
  if (!boxes_) {
    if (error) *error = tr("Bake or open boxes first");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = mesh_;
  auto boxes = boxes_;
  const auto refsFuture = references_;
  const float diagonal = diagonal_;
  return job_->start(tr("Error field"), [this, mesh, boxes, refsFuture, diagonal, probesPerPoint](const auto& progress) {
    const std::shared_ptr<const vtkHapticBoxReferenceQueries> refs = refsFuture.get();
    const hb::ExactQuery* exact = &refs->Exact();
    hb::ErrorFieldOptions o;
    o.probes_per_point = probesPerPoint;
    o.law = law_;
    o.progress = progress;
    auto field = std::make_unique<hb::ErrorField>(
        hb::compute_error_field(*boxes, *exact, hb::surface_points_at_vertices(*mesh), diagonal, o));
    pendingField_ = std::move(field);
  });
}

// --- probe -----------------------------------------------------------------------------

void HapticSession::setProbeTarget(const hb::Vec3& surfacePoint) {
  picked_ = surfacePoint;
  if (opened_.virtual_device) {
    const hb::Vec3 tip = surfacePoint + probeDirection_ * static_cast<float>(depthFraction_ * diagonal_);
    opened_.virtual_device->set_target((tip - mapping_.model_origin) / mapping_.model_units_per_metre);
  }
}

void HapticSession::setProbeDirection(const hb::Vec3& direction) {
  const hb::Vec3 d = direction.normalized();
  if (!d.allFinite() || d.dot(probeDirection_) > 0.99996f) return;  // < ~0.5 degree: keep
  probeDirection_ = d;
  mapping_.probe_direction = d;
  if (loop_) {
    stopServo();
    startServo();
  }
  if (picked_) setProbeTarget(*picked_);
}

void HapticSession::setDepthFraction(double f) {
  depthFraction_ = std::clamp(f, -0.05, 0.1);
  if (picked_) setProbeTarget(*picked_);
}

ProbeReading HapticSession::reading() {
  ProbeReading r;
  if (!mesh_) return r;
  r.haveBoxes = boxes_ != nullptr;
  r.deviceName = deviceName_;
  hb::ForceLaw law = law_;
  hb::Vec3 tip;
  const bool servo = loop_ && loop_->running();
  r.deviceRunning = servo;
  if (servo) {
    const hb::ServoSnapshot s = loop_->snapshot();
    law = loop_->options().law;
    tip = hb::Vec3(s.tip_model[0], s.tip_model[1], s.tip_model[2]);
    r.placed = opened_.virtual_device ? picked_.has_value() : s.tick > 0;
    r.segment = hb::Segment{tip - probeDirection_ * mapping_.probe_length, tip};
    r.approx.contact = s.contact != 0;
    r.approx.depth = s.depth;
    r.approx.normal = hb::Vec3(s.normal[0], s.normal[1], s.normal[2]);
    r.approx.point = tip - probeDirection_ * s.depth;
    r.approx.force = hb::Vec3(s.desired_force_n[0], s.desired_force_n[1], s.desired_force_n[2]);
    r.approxQueryNs = s.query_ns;
    r.rateHz = s.rate_hz;  // the servo loop's own live window (about 0.5 s)
    r.p99PeriodUs = s.period_p99_us;
  } else {
    if (!picked_) return r;
    r.placed = true;
    tip = *picked_ + probeDirection_ * static_cast<float>(depthFraction_ * diagonal_);
    r.segment = hb::Segment{tip - probeDirection_ * mapping_.probe_length, tip};
    if (boxes_) {
      const auto t0 = std::chrono::steady_clock::now();
      r.approx = boxes_->query(r.segment, law);
      r.approxQueryNs = elapsedNs(t0);
    }
  }
  if (!r.placed) return r;
  const auto t0 = std::chrono::steady_clock::now();
  const hb::ExactQuery* exact = readyExact();
  if (!exact) return r;  // the exact query is still building (a fraction of a second after open)
  r.exact = exact->query(r.segment, law);
  r.exactQueryNs = elapsedNs(t0);
  if (r.exact.contact && r.approx.contact) {
    r.relativeError = hb::relative_force_error(r.exact, r.approx);
    r.angleDeg = hb::angle_error_degrees(r.exact, r.approx);
  }
  return r;
}

// --- device ----------------------------------------------------------------------------

bool HapticSession::setDevice(DeviceKind kind, const QString& replayPath, QString* message,
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

bool HapticSession::servoRunning() const { return loop_ && loop_->running(); }

void HapticSession::startServo() {
  if (!boxes_ || !mesh_) return;
  if (!opened_.device) {
    opened_ = hb::open_device(hb::DeviceChoice{});
    deviceName_ = QString::fromStdString(opened_.description);
  }
  hb::ServoOptions o;
  o.law = law_;
  o.mapping = mapping_;
  o.request_realtime = runSettings().realtime;
  // No busy-wait before each deadline: the window renders on the same cores (software GL
  // uses every core), and a real-time thread spinning 50 us per tick halves its frame rate
  // while sleeping to the deadline keeps the p99 period within a few tens of us.
  o.spin_s = runSettings().spinUs * 1e-6;
  if (opened_.rate_hz > 0.0) o.rate_hz = opened_.rate_hz;  // a replay runs at its recorded rate
  try {
    loop_ = std::make_unique<hb::ServoLoop>(*opened_.device, *boxes_, o);
    if (estop_) loop_->emergency_stop();
    loop_->start();
  } catch (const std::exception& e) {
    loop_.reset();
    emit statusMessage(tr("Device thread not started: %1").arg(QString::fromStdString(e.what())));
  }
}

void HapticSession::setEmergencyStop(bool on) {
  estop_ = on;
  if (loop_) {
    if (on) loop_->emergency_stop();
    else loop_->clear_emergency_stop();
  }
  emit statusMessage(on ? tr("Emergency stop: no force until released (Space)") : tr("Emergency stop released"));
}

void HapticSession::stopServo() {
  if (loop_) loop_->stop();
  loop_.reset();
}

// --- export ----------------------------------------------------------------------------

bool HapticSession::startReport(const QString& dir, const QString& errorFieldImage, std::size_t samples,
                                QString* error) {
  if (!boxes_) {
    if (error) *error = tr("Bake or open boxes first");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = mesh_;
  auto boxes = boxes_;
  const auto refsFuture = references_;
  // The request `hapticbox report BOX MESH` builds (report/report_request.h), so the window
  // and the command line give the same report for the same input.
  hb::ReportRequest request;
  request.mesh_path = QFile::encodeName(meshPath_).toStdString();
  request.mesh_hash = meshHash_;
  request.box_path = QFile::encodeName(boxPath_).toStdString();
  request.bake_seconds = bakeSeconds_;  // 0 for boxes loaded from a file or the cache
  request.options.samples = samples;
  request.options.law = law_;
  request.options.cache_dir = bake_.useCache ? cache_.dir() : std::string();
  request.product_version = HB_VERSION;
  request.command_line = "hapticbox-gui: File > Export Report";
  request.error_field_image = QFile::encodeName(errorFieldImage).toStdString();
  request.no_image_note = "no error field in the window to picture (Compute Error Field first)";
  const std::string out = QFile::encodeName(dir).toStdString();
  // A report measures fewer configurations than a sweep: it fills the charts only when no
  // sweep has (exporting a report never replaces the window's sweep chart).
  const bool haveSweep = !sweepRows_.empty();
  return job_->start(tr("Report"), [=](const auto& progress) mutable {
    const std::shared_ptr<const vtkHapticBoxReferenceQueries> refs = refsFuture.get();
    request.mesh = mesh.get();
    request.scene = boxes.get();
    request.references = refs->References();
    request.options.progress = progress;
    hb::ReportData d = hb::compute_report(request);
    if (!haveSweep) {
      pendingRows_ = d.rows;
      pendingCompression_ = d.compression_curve;
      pendingRowsReady_ = true;
    }
    hb::write_report(request, d, out);
  });
}

bool HapticSession::startSweep(const std::vector<int>& ms, const std::vector<int>& ns, std::size_t samples,
                               QString* error) {
  if (!mesh_) {
    if (error) *error = tr("Open a model first");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = mesh_;
  const auto refsFuture = references_;
  const hb::SourceInfo source = sourceInfo();
  const std::string cache = bake_.useCache ? cache_.dir() : std::string();
  return job_->start(tr("Sweep"), [=](const auto& progress) {
    const std::shared_ptr<const vtkHapticBoxReferenceQueries> references = refsFuture.get();
    const std::vector<hb::SweepReference> refs = references->References();
    hb::SweepOptions o;
    o.configs = hb::sweep_grid(ms, ns);
    o.samples = samples;
    o.timing_rounds = 3;
    o.law = law_;
    o.cache_dir = cache;
    o.progress = progress;
    pendingRows_ = hb::run_sweep(*mesh, source, refs, o);
    pendingCompression_.clear();
    pendingRowsReady_ = true;
  });
}

void HapticSession::aimProbe(const hb::Vec3& view, const hb::Vec3& right) {
  const float a = static_cast<float>(tiltDegrees_ * 3.14159265358979 / 180.0);
  setProbeDirection(Eigen::AngleAxisf(a, right.normalized()) * view.normalized());
}

double HapticSession::forceDisplayScale() const {
  const double f = law_.stiffness_n_per_m * 0.01 * diagonal_ * law_.metres_per_unit;
  return f > 0.0 ? 0.08 * diagonal_ / f : 1.0;
}

const hb::ExactQuery* HapticSession::readyExact() const {
  if (!references_.valid() || references_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return nullptr;
  try {
    return &references_.get()->Exact();
  } catch (const std::exception&) {
    return nullptr;  // Embree failed: reported when a job needs it
  }
}
