// SessionModel: the window's model.
//  1. openMesh runs the pipeline's reader (vtkHapticBoxMeshReader: every format, volumes, CAD
//     and scenes through hb::vtk::load_model, as the command line), hashes the input with
//     hb::vtk::model_hash, starts the references (exact Embree, VTK locator) on their own thread,
//     and takes the reader's output as the surface the views draw.
//     The reader stays the head of the model's pipeline (SessionPipeline).
//  2. installBoxes takes the boxes a job baked (or the cache or a file held); the piece ids
//     and the PBB outlines the views show are the bake filter's outputs (made from the scene
//     the same way for a box file opened by hand).
//  3. setErrorField adds the error-field filter's output arrays to the surface.
#include "SessionModel.h"
#include "SessionPipeline.h"
#include "errors.h"
#include "store/box_file.h"
#include "model_load_text.h"
#include "model_loader.h"
#include "model_options_key.h"
#include "vtkHapticBoxMeshReader.h"
#include "vtkHapticBoxReferenceQueries.h"
#include "vtkHapticBoxUtilities.h"
#include <QFile>
#include <QFileInfo>
#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkFloatArray.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <chrono>

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

double msBetween(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

SessionModel::SessionModel(QObject* parent) : QObject(parent) { outlines_ = vtkSmartPointer<vtkPolyData>::New(); }

SessionModel::~SessionModel() = default;

QString SessionModel::meshFileFilter() {
  // Every format the pipeline's reader takes (meshes, volumes, CAD, scenes), as the CLI.
  return tr("Models (%1);;All files (*)").arg(QString::fromStdString(hb::vtk::model_file_patterns()));
}

bool SessionModel::openMesh(const QString& path, QString* error, OpenTiming* timing, const hb::vtk::ModelOptions& options) {
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string p = QFile::encodeName(path).toStdString();
    auto reader = vtkSmartPointer<vtkHapticBoxMeshReader>::New();
    // The window shows the reader's error and warnings itself (no console output window).
    auto quiet = vtkSmartPointer<vtkCallbackCommand>::New();
    reader->AddObserver(vtkCommand::ErrorEvent, quiet);
    reader->AddObserver(vtkCommand::WarningEvent, quiet);
    reader->SetFileName(p.c_str());
    reader->SetModelOptions(options);
    reader->Update();
    if (!reader->GetLastError().empty()) throw hb::InvalidInput(reader->GetLastError());
    vtkPolyData* out = reader->GetOutput();
    if (!out || out->GetNumberOfCells() == 0) throw hb::InvalidInput(p + ": no triangles could be read");
    const hb::vtk::LoadedModel& model = reader->GetLoadedModel();
    auto mesh = std::make_shared<hb::TriangleMesh>(model.mesh);
    // The line `hapticbox` prints on reading the same model.
    const QString modelNote = QString::fromStdString(
        hb::vtk::model_load_text(model, options, "; set another in the Surface panel"));
    const auto tRead = std::chrono::steady_clock::now();
    // A volume's histogram and Otsu threshold, for choosing another iso-value.
    hb::vtk::VolumeHistogram histogram;
    double otsu = 0.0;
    std::shared_ptr<const hb::vtk::Volume> volume;
    if (model.kind == hb::vtk::ModelKind::Volume) {
      // Kept for the Surface panel's preview of other iso-values (SurfacePanel, volume_preview.h).
      volume = std::make_shared<const hb::vtk::Volume>(hb::vtk::read_volume(p));
      histogram = hb::vtk::volume_histogram(*volume);
      otsu = hb::vtk::otsu_threshold(histogram);
    }
    // As the command line with the same options (hb::cli::hash_model).
    const std::uint64_t hash = hb::vtk::model_hash(p, options);
    const auto tHash = std::chrono::steady_clock::now();
    References references = std::async(std::launch::async, [mesh] { return buildReferences(mesh); }).share();
    const auto tExact = std::chrono::steady_clock::now();
    hb::SourceInfo source;
    source.mesh_path = QFile::encodeName(QFileInfo(path).absoluteFilePath()).toStdString();
    source.mesh_hash = hash;
    source.triangles = mesh->triangle_count();
    source.diagonal = mesh->bounds().diagonal();
    auto pipeline = std::make_unique<SessionPipeline>(reader, source);

    // Commit: nothing below throws on a valid mesh.
    boxes_.reset();
    errorField_.reset();
    boxPath_.clear();
    references_ = std::move(references);
    pipeline_ = std::move(pipeline);
    mesh_ = std::move(mesh);
    meshHash_ = hash;
    meshPath_ = QFileInfo(path).absoluteFilePath();
    diagonal_ = mesh_->bounds().diagonal();
    workspace_ = hb::make_workspace(mesh_->bounds());
    law_ = workspace_.law();
    options_ = options;
    facts_ = model.facts;
    kind_ = model.kind;
    histogram_ = std::move(histogram);
    otsu_ = otsu;
    volume_ = std::move(volume);
    warnings_.clear();
    for (const auto& w : model.report.warnings) warnings_ << QString::fromStdString(w);
    surface_ = vtkSmartPointer<vtkPolyData>::New();
    surface_->ShallowCopy(out);
    updatePieceArray({});
    outlines_ = vtkSmartPointer<vtkPolyData>::New();
    const auto tSurface = std::chrono::steady_clock::now();
    emit meshChanged();
    if (!modelNote.isEmpty()) emit statusMessage(tr("Opened %1: %2").arg(QFileInfo(path).fileName(), modelNote));
    if (timing) {
      const auto tView = std::chrono::steady_clock::now();
      *timing = OpenTiming{msBetween(t0, tRead), msBetween(tRead, tHash), msBetween(tHash, tExact),
                           msBetween(tExact, tSurface), msBetween(tSurface, tView)};
    }
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

void SessionModel::updatePieceArray(const std::vector<std::uint32_t>& pieces) {
  auto ids = vtkSmartPointer<vtkIntArray>::New();
  ids->SetName("PieceId");
  ids->SetNumberOfTuples(static_cast<vtkIdType>(mesh_->triangle_count()));
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i)
    ids->SetValue(i, pieces.empty() ? 0 : static_cast<int>(pieces[static_cast<std::size_t>(i)]));
  surface_->GetCellData()->AddArray(ids);
  surface_->Modified();
}

hb::SourceInfo SessionModel::sourceInfo() const {
  hb::SourceInfo s;
  s.mesh_path = QFile::encodeName(meshPath_).toStdString();
  s.mesh_hash = meshHash_;
  s.triangles = mesh_->triangle_count();
  s.diagonal = diagonal_;
  return s;
}

std::shared_ptr<const hb::ExactQuery> SessionModel::exactOf(const References& references) {
  if (!references.valid()) return nullptr;
  const std::shared_ptr<const vtkHapticBoxReferenceQueries> refs = references.get();
  return std::shared_ptr<const hb::ExactQuery>(refs, &refs->Exact());
}

const hb::ExactQuery* SessionModel::readyExact() const {
  if (!references_.valid() || references_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return nullptr;
  try {
    return &references_.get()->Exact();
  } catch (const std::exception&) {
    return nullptr;  // Embree failed: reported when a job needs it
  }
}

// --- boxes -----------------------------------------------------------------------------

void SessionModel::setPieceArray(vtkDataArray* ids) {
  surface_->GetCellData()->AddArray(ids);
  surface_->Modified();
}

void SessionModel::installBoxes(std::shared_ptr<const hb::BoxScene> boxes, double seconds, bool fromCache,
                                vtkPolyData* outlines, vtkDataArray* pieceIds) {
  boxes_ = std::move(boxes);
  bakeSeconds_ = seconds;
  boxesFromCache_ = fromCache;
  boxPath_.clear();
  errorField_.reset();
  vtkPointData* pd = surface_->GetPointData();
  for (ErrorMetric m : kErrorMetrics)
    pd->RemoveArray(errorArrayName(m));
  if (pieceIds && pieceIds->GetNumberOfTuples() == surface_->GetNumberOfCells()) setPieceArray(pieceIds);
  else updatePieceArray(boxes_->parts().piece_of_triangle);
  if (outlines) {
    outlines_ = vtkSmartPointer<vtkPolyData>::New();
    outlines_->ShallowCopy(outlines);
  } else {
    outlines_ = vtkHapticBoxUtilities::BoxOutlines(*boxes_);
  }
  emit boxesChanged();
  emit errorFieldChanged();
}

bool SessionModel::openBoxFile(const QString& path, QString* error) {
  if (!mesh_) {
    if (error) *error = tr("Open the model the boxes were baked from first");
    return false;
  }
  try {
    auto scene = std::make_shared<hb::BoxScene>(hb::load_box_file(QFile::encodeName(path).toStdString()));
    if (scene->parts().source.mesh_hash != 0 && scene->parts().source.mesh_hash != meshHash_)
      throw hb::InvalidInput(QFile::encodeName(path).toStdString() + ": baked from another mesh (" +
                             scene->parts().source.mesh_path + ")");
    installBoxes(std::move(scene), 0.0, true);
    boxPath_ = QFileInfo(path).absoluteFilePath();
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

bool SessionModel::saveBoxFile(const QString& path, QString* error) const {
  try {
    if (!boxes_) throw hb::InvalidInput("no boxes: bake first");
    hb::save_box_file(*boxes_, QFile::encodeName(path).toStdString());
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}

// --- error field -----------------------------------------------------------------------

void SessionModel::setErrorField(std::unique_ptr<hb::ErrorField> field, vtkPolyData* fieldSurface) {
  errorField_ = std::move(field);
  vtkPointData* pd = surface_->GetPointData();
  for (ErrorMetric m : kErrorMetrics) {
    vtkDataArray* a = fieldSurface ? fieldSurface->GetPointData()->GetArray(errorArrayName(m)) : nullptr;
    if (a && a->GetNumberOfTuples() == surface_->GetNumberOfPoints()) pd->AddArray(a);
    else pd->RemoveArray(errorArrayName(m));
  }
  surface_->Modified();
  emit errorFieldChanged();
}

const char* SessionModel::errorArrayName(ErrorMetric metric) {
  switch (metric) {
  case ErrorMetric::RelativeForce: return "RelativeForceError";
  case ErrorMetric::Direction: return "DirectionError";
  case ErrorMetric::ContactDisagreement: return "ContactDisagreement";
  case ErrorMetric::Perceptible: return "PerceptibleRatio";
  }
  return "RelativeForceError";
}

QString SessionModel::errorMetricTitle(ErrorMetric metric) {
  switch (metric) {
  case ErrorMetric::RelativeForce: return tr("Relative force error");
  case ErrorMetric::Direction: return tr("Direction error (deg)");
  case ErrorMetric::ContactDisagreement: return tr("Contact disagreement");
  case ErrorMetric::Perceptible: return tr("Perceptible difference (x what a hand feels)");
  }
  return {};
}
