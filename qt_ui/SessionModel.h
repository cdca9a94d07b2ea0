#pragma once
// The window's model (the "model" third of HapticSession): the mesh read through the
// pipeline's reader (vtkHapticBoxMeshReader), its hash (hb::hash_model, as the command line),
// the pipeline downstream of the reader (SessionPipeline: decomposition, bake, error field),
// the surface the views draw, the exact and VTK references, the boxes in use and their error
// field. It runs nothing long and holds no widget: the jobs fill it, the device reads it.
#include "contact/workspace.h"
#include "evaluation/error_field.h"
#include "exact/exact_query.h"
#include "scene/box_scene.h"
#include "contact/contact.h"
#include "mesh/triangle_mesh.h"
#include "model_loader.h"
#include "volume_histogram.h"
#include <QObject>
#include <QString>
#include <QStringList>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <cstdint>
#include <future>
#include <memory>
#include <vector>

class SessionPipeline;
class vtkDataArray;
class vtkHapticBoxReferenceQueries;

/// The surface metric the error-field view colours by. Perceptible (the default): per vertex
/// the largest box-vs-exact force difference over what a hand feels (hb::perceive's ratio,
/// array "PerceptibleRatio"; 1 = just feelable); the others are the relative metrics.
enum class ErrorMetric { RelativeForce = 0, Direction = 1, ContactDisagreement = 2, Perceptible = 3 };
/// Every metric, in the order the panel lists them (the default first).
inline constexpr ErrorMetric kErrorMetrics[] = {ErrorMetric::Perceptible, ErrorMetric::RelativeForce,
                                                ErrorMetric::Direction, ErrorMetric::ContactDisagreement};

class SessionModel : public QObject {
  Q_OBJECT
public:
  explicit SessionModel(QObject* parent = nullptr);
  ~SessionModel() override;

  /// Where opening a model spent its time, ms (hapticbox-gui --timing).
  struct OpenTiming {
    double readMs = 0, hashMs = 0, exactMs = 0, surfaceMs = 0, viewMs = 0;
  };
  /// Reads a model (any format vtkHapticBoxMeshReader takes, at its default options: the
  /// same surface and hash as the command line), starts building the references and emits
  /// meshChanged. On failure the previous model stays and `error` names the file and the cause.
  /// `options`: how a volume or CAD solid becomes triangles (iso-value, label, smoothing,
  /// target triangles, as the command line's --iso, --label, --smooth, --target-triangles); its
  /// key is mixed into the hash as the command line does, so cached bakes never mix surfaces.
  bool openMesh(const QString& path, QString* error = nullptr, OpenTiming* timing = nullptr,
                const hb::vtk::ModelOptions& options = {});
  /// The options the open model was read with, what the loader found (format, volume facts:
  /// dimensions, spacing, value range, iso-value or label used) and whether it is a volume.
  const hb::vtk::ModelOptions& modelOptions() const { return options_; }
  const nlohmann::json& modelFacts() const { return facts_; }
  bool isVolume() const { return kind_ == hb::vtk::ModelKind::Volume; }
  /// A volume's histogram of calibrated values and its Otsu threshold (the automatic iso-value).
  const hb::vtk::VolumeHistogram& histogram() const { return histogram_; }
  double otsu() const { return otsu_; }
  /// The open volume as read (null for a mesh): what the Surface panel previews other options
  /// on (shared, so a preview running on a worker keeps it alive after another model opens).
  std::shared_ptr<const hb::vtk::Volume> volume() const { return volume_; }
  bool hasMesh() const { return mesh_ != nullptr; }
  QString meshPath() const { return meshPath_; }
  const hb::TriangleMesh& mesh() const { return *mesh_; }
  std::shared_ptr<const hb::TriangleMesh> sharedMesh() const { return mesh_; }
  /// hb::hash_model of the file (or DICOM folder) opened: what box files and the cache record.
  std::uint64_t meshHash() const { return meshHash_; }
  float diagonal() const { return diagonal_; }
  QStringList meshWarnings() const { return warnings_; }
  /// The source a bake records (path, hash, triangles, diagonal).
  hb::SourceInfo sourceInfo() const;
  /// The surface (the reader's output): cell i = triangle i, cell "PieceId", point "Normals"
  /// and, after an error field, the point arrays named by errorArrayName().
  vtkPolyData* surface() const { return surface_; }
  /// PBB outlines of the current boxes (12 lines per box, cell "BoxId"); empty when none.
  vtkPolyData* outlines() const { return outlines_; }
  /// File filter of every format the reader takes (hb::vtk::model_file_patterns).
  static QString meshFileFilter();
  /// The force law of the session (probe, servo, error field, report, sweep): the workspace's
  /// (the model fitted to the device, k 1500 N/m), the same newtons as `hapticbox eval`.
  const hb::ForceLaw& law() const { return law_; }
  /// The scale of every force the window shows (set when a model opens).
  const hb::Workspace& workspace() const { return workspace_; }

  /// The reference methods over the mesh (exact Embree, VTK's cell locator, with their memory
  /// and build times, as the command line measures them), built beside the window's own setup.
  using References = std::shared_future<std::shared_ptr<const vtkHapticBoxReferenceQueries>>;
  References references() const { return references_; }
  /// The exact query when it is built, else nullptr (never blocks).
  const hb::ExactQuery* readyExact() const;
  /// The exact query of `references`, shared (waits until it is built; throws what building
  /// it threw): the one the error field, the sweep and the report compare with. Call it with
  /// the job's own copy of references().
  static std::shared_ptr<const hb::ExactQuery> exactOf(const References& references);

  /// The VTK pipeline over the model (null before a model is open).
  SessionPipeline* pipeline() const { return pipeline_.get(); }

  // --- boxes ---------------------------------------------------------------------------
  /// Installs boxes baked or loaded for the mesh; drops the error field; emits boxesChanged
  /// and errorFieldChanged. `outlines` and `pieceIds` (a cell array, one id per triangle) are
  /// what the views show: the bake filter's outputs 1 and 3; null: made from the scene (a
  /// box file opened by hand).
  void installBoxes(std::shared_ptr<const hb::BoxScene> boxes, double seconds, bool fromCache,
                    vtkPolyData* outlines = nullptr, vtkDataArray* pieceIds = nullptr);
  bool hasBoxes() const { return boxes_ != nullptr; }
  const hb::BoxScene* boxes() const { return boxes_.get(); }
  std::shared_ptr<const hb::BoxScene> sharedBoxes() const { return boxes_; }
  double bakeSeconds() const { return bakeSeconds_; }
  bool boxesFromCache() const { return boxesFromCache_; }
  /// The box file the boxes were opened from (empty: baked or cached).
  QString boxPath() const { return boxPath_; }
  /// Installs a loaded .hbox file (checked against the mesh hash when it records one).
  bool openBoxFile(const QString& path, QString* error = nullptr);
  bool saveBoxFile(const QString& path, QString* error = nullptr) const;

  // --- error field ---------------------------------------------------------------------
  /// Installs a computed field and, on the surface, the arrays errorArrayName() names of
  /// `fieldSurface` (vtkHapticBoxErrorFieldFilter's output over this surface, same vertices);
  /// emits errorFieldChanged.
  void setErrorField(std::unique_ptr<hb::ErrorField> field, vtkPolyData* fieldSurface);
  bool hasErrorField() const { return errorField_ != nullptr; }
  const hb::ErrorField* errorField() const { return errorField_.get(); }
  static const char* errorArrayName(ErrorMetric metric);
  static QString errorMetricTitle(ErrorMetric metric);

signals:
  void meshChanged();
  void boxesChanged();
  void errorFieldChanged();
  void statusMessage(const QString& message);

private:
  void updatePieceArray(const std::vector<std::uint32_t>& pieces);
  void setPieceArray(vtkDataArray* ids);

  QString meshPath_;
  QStringList warnings_;
  hb::vtk::ModelOptions options_;
  nlohmann::json facts_;
  hb::vtk::ModelKind kind_ = hb::vtk::ModelKind::Mesh;
  hb::vtk::VolumeHistogram histogram_;
  double otsu_ = 0.0;
  std::shared_ptr<const hb::vtk::Volume> volume_;
  std::shared_ptr<hb::TriangleMesh> mesh_;
  std::uint64_t meshHash_ = 0;
  float diagonal_ = 0.f;
  hb::ForceLaw law_;
  hb::Workspace workspace_;
  References references_;
  std::unique_ptr<SessionPipeline> pipeline_;
  vtkSmartPointer<vtkPolyData> surface_;
  vtkSmartPointer<vtkPolyData> outlines_;
  std::shared_ptr<const hb::BoxScene> boxes_;
  double bakeSeconds_ = 0.0;
  bool boxesFromCache_ = false;
  QString boxPath_;
  std::unique_ptr<hb::ErrorField> errorField_;
};
