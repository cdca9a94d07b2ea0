#pragma once
// The window's long jobs (the "jobs" third of HapticSession): bake (the model's pipeline:
// decomposition and bake filters, hb::bake through the box cache, with the default recipe of
// `hapticbox bake` unless the panel's advanced sampling is chosen), error field (the
// error-field filter), sweep and report, one at a time on the BackgroundJob worker. Their
// results are installed into the model on the GUI thread when the job ends.
#include "SessionModel.h"
#include "recipe/sweep.h"
#include "recipe/bake_recipe.h"
#include "recipe/box_cache.h"
#include "contact/god_object.h"
#include <QObject>
#include <QString>
#include <memory>
#include <utility>
#include <vector>

class BackgroundJob;
namespace hb {
struct StabilityReport;
}

/// What the bake panel sets. By default the bake is the product's default, the one
/// `hapticbox bake MESH -o BOX` runs (hb::default_recipe(): automatic pieces, an error budget
/// choosing n, the cell and refinement per piece, the block codec). `advanced` bakes the given
/// sampling instead: densities, padding, pieces (none: one box, a piece file, or automatic:
/// hb::decompose_auto) and the table codec ("none", "block", "haar"; compressed at the codec's
/// default error bound), as `hapticbox bake -m M -n N ...`.
struct BakeSettings {
  enum class Pieces { None, File, Automatic };
  bool advanced = false;          ///< false: hb::default_recipe(); true: the fields below.
  int m = 16;                     ///< position points per PBB face edge.
  int n = 8;                      ///< directional points per sub-block face edge.
  float padding = 0.01f;          ///< PBB padding, fraction of its diagonal.
  Pieces pieces = Pieces::None;
  QString piecesFile;             ///< text: one integer piece id per triangle.
  QString codec = QStringLiteral("none");
  bool refine = false;            ///< store triangle ids: queries refine exactly (hb::BakeOptions::refine).
  bool useCache = true;           ///< load/save baked boxes in the box cache (hb::BoxCache).
  /// The bake these settings ask for: hb::default_recipe(), or with `advanced` the given
  /// sampling (seams and decomposition at their defaults, the codec at its default error
  /// bound). Throws hb::InvalidInput for an unknown codec.
  hb::BakeRecipe recipe() const;
};

class SessionJobs : public QObject {
  Q_OBJECT
public:
  /// Jobs over `model` (which outlives this object).
  explicit SessionJobs(SessionModel* model, QObject* parent = nullptr);
  ~SessionJobs() override;  ///< cancels and waits for the running job.

  /// The one worker: bake, error field, sweep, report. One job at a time.
  BackgroundJob* job() const { return job_; }
  /// True (and `error` says which job) while a job runs.
  bool busy(QString* error) const;

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

  // --- error field, sweep, report ------------------------------------------------------
  bool startErrorField(int probesPerPoint = 1, QString* error = nullptr);
  /// Runs a small sweep (m x n grid, codec none) with the exact and VTK-locator references.
  bool startSweep(const std::vector<int>& ms, const std::vector<int>& ns, std::size_t samples = 5000,
                  QString* error = nullptr);
  /// Computes and writes the error report (the files of `hapticbox report`) into `dir` on the
  /// worker. `errorFieldImage`: a PNG of the rendered field to embed, or empty.
  bool startReport(const QString& dir, const QString& errorFieldImage, std::size_t samples = 20000,
                   QString* error = nullptr);
  /// Runs the trajectory stability suite on the model's boxes and mesh on the worker
  /// (`hapticbox stability`'s defaults: hb::default_stability_options), `sites` trajectories
  /// per test, one test at a time (progress and cancel between tests); `generated` false: the
  /// model alone (as `--no-generated`). Implemented in SessionStability.cpp.
  bool startStability(std::size_t sites = 12, bool generated = true, QString* error = nullptr,
                      hb::ContactLaw law = hb::ContactLaw::penalty);
  /// The last suite's report (null before one finished).
  const hb::StabilityReport* stabilityReport() const { return stability_.get(); }
  /// Sweep rows of the last report or sweep (the charts).
  const std::vector<hb::SweepRow>& sweepRows() const { return sweepRows_; }
  const std::vector<std::pair<double, double>>& compressionCurve() const { return compression_; }

signals:
  void stabilityChanged();
  void cacheChanged();
  void sweepChanged();
  void jobFinished(const QString& name, bool ok, const QString& message);
  void statusMessage(const QString& message);

private:
  void finished(bool ok);
  /// The bake filter's result (scene, seconds, cache hit, outlines, piece ids) as pending.
  void takeBakeOutputs();

  SessionModel* model_;
  BakeSettings bake_;
  hb::BoxCache cache_;
  std::vector<hb::SweepRow> sweepRows_;
  std::vector<std::pair<double, double>> compression_;

  // Results handed from the worker to the GUI thread on finished().
  std::shared_ptr<const hb::BoxScene> pendingBoxes_;
  std::unique_ptr<hb::ErrorField> pendingField_;
  vtkSmartPointer<vtkPolyData> pendingFieldSurface_;  ///< the error-field filter's output.
  vtkSmartPointer<vtkPolyData> pendingOutlines_;      ///< the bake filter's output 1.
  vtkSmartPointer<vtkDataArray> pendingPieceIds_;     ///< the bake filter's output 3 "PieceId".
  double pendingSeconds_ = 0.0;
  bool pendingFromCache_ = false;
  QString pendingCacheWarning_;
  std::vector<hb::SweepRow> pendingRows_;
  std::vector<std::pair<double, double>> pendingCompression_;
  bool pendingRowsReady_ = false;

  std::shared_ptr<const hb::StabilityReport> stability_;

  BackgroundJob* job_ = nullptr;
};
