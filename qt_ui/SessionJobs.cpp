// SessionJobs: the window's long jobs.
//  1. startBake runs the model's pipeline (SessionPipeline: reader -> decomposition filter ->
//     vtkHapticBoxBakeFilter, which calls hb::bake_cached: hb::bake through the shared box
//     cache) on the worker with the recipe of the bake settings: hb::default_recipe() unless
//     advanced, so the window's Bake is `hapticbox bake MESH -o BOX`'s, and its cache entry is
//     the one `sweep`, `report` and `cache` see. loadCachedBoxes runs the same bake filter,
//     cache only (no decomposition, no bake on the GUI thread).
//  2. startErrorField runs the pipeline's vtkHapticBoxErrorFieldFilter on the reader's surface
//     and the bake filter's boxes against the model's shared exact reference (its output's
//     arrays go to the view); startSweep and startReport run hb::run_sweep and the report
//     request of `hapticbox report` (report/report_request.h) against the model's references.
//  3. When the job ends, its result is installed into the model on the GUI thread: the
//     boxes with the bake filter's outlines and piece ids, the field with its arrays.
#include "SessionJobs.h"
#include "BackgroundJob.h"
#include "SessionPipeline.h"
#include "vtkHapticBoxBakeFilter.h"
#include "errors.h"
#include "recipe/recipe_choice.h"
#include "report_request.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxReferenceQueries.h"
#include "vtkHapticBoxSet.h"
#include <QFile>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <chrono>
#include <functional>
#include <optional>

// --- bake settings ---------------------------------------------------------------------

hb::BakeRecipe BakeSettings::recipe() const {
  // The rule `hapticbox bake` follows: Advanced gives the sampling options -m, -n and --refine.
  const hb::SamplingGiven given = hb::SamplingGiven::advanced(advanced);
  if (hb::bakes_default_recipe(given)) return hb::default_recipe();  // `hapticbox bake MESH -o BOX`
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

// --- jobs ------------------------------------------------------------------------------

SessionJobs::SessionJobs(SessionModel* model, QObject* parent)
    : QObject(parent), model_(model), job_(new BackgroundJob(this)) {
  connect(job_, &BackgroundJob::finished, this, [this](bool ok, bool, const QString& message) {
    const QString name = job_->name();
    finished(ok);
    emit jobFinished(name, ok, ok ? tr("%1 done").arg(name) : message);
  });
}

SessionJobs::~SessionJobs() {
  job_->cancel();
  job_->wait();
}

void SessionJobs::finished(bool ok) {
  if (ok && pendingBoxes_) {
    model_->installBoxes(std::move(pendingBoxes_), pendingSeconds_, pendingFromCache_, pendingOutlines_,
                         pendingPieceIds_);
    if (!pendingCacheWarning_.isEmpty()) emit statusMessage(pendingCacheWarning_);
    emit cacheChanged();
  }
  if (ok && pendingField_) model_->setErrorField(std::move(pendingField_), pendingFieldSurface_);
  if (ok && pendingRowsReady_) {
    sweepRows_ = std::move(pendingRows_);
    compression_ = std::move(pendingCompression_);
    emit sweepChanged();
  }
  pendingRowsReady_ = false;
  pendingBoxes_.reset();
  pendingField_.reset();
  pendingFieldSurface_ = nullptr;
  pendingOutlines_ = nullptr;
  pendingPieceIds_ = nullptr;
  pendingCacheWarning_.clear();
}

void SessionJobs::takeBakeOutputs() {
  vtkHapticBoxBakeFilter* bake = model_->pipeline()->bake();
  pendingBoxes_ = bake->GetBoxSet()->GetScene();
  pendingSeconds_ = bake->GetBakeSeconds();
  pendingFromCache_ = bake->GetFromCache();
  if (!bake->GetCacheWarning().empty()) pendingCacheWarning_ = QString::fromStdString(bake->GetCacheWarning());
  pendingOutlines_ = vtkSmartPointer<vtkPolyData>::New();
  pendingOutlines_->ShallowCopy(bake->GetOutput(1));
  pendingPieceIds_ = bake->GetOutput(3)->GetCellData()->GetArray("PieceId");
}

bool SessionJobs::busy(QString* error) const {
  if (!job_->isRunning()) return false;
  if (error) *error = tr("%1 is running: wait for it or cancel it first").arg(job_->name());
  return true;
}

// --- bake ------------------------------------------------------------------------------

bool SessionJobs::clearCache(QString* error) {
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

bool SessionJobs::loadCachedBoxes() {
  if (!model_->hasMesh() || !bake_.useCache || job_->isRunning()) return false;
  try {
    const hb::BakeRecipe recipe = bake_.recipe();
    SessionPipeline* pipeline = model_->pipeline();
    pipeline->prepareBake(recipe, cache_.dir());
    if (!pipeline->hasCachedScene()) return false;
    pipeline->runBake({}, /*cacheOnly=*/true);  // reads the entry: never decomposes or bakes here
    takeBakeOutputs();
    const QString path = QString::fromStdString(pipeline->bake()->GetCachePath());
    finished(true);
    emit statusMessage(tr("Loaded cached boxes %1").arg(path));
    return true;
  } catch (const std::exception& e) {
    finished(false);
    emit statusMessage(tr("Ignoring the cached boxes: %1").arg(QString::fromStdString(e.what())));
    return false;
  }
}

bool SessionJobs::startBake(QString* error) {
  if (!model_->hasMesh()) {
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
  // The pipeline: reader -> decomposition filter (automatic pieces not in the cache) ->
  // bake filter (hb::bake_cached in the box cache), updated on the worker.
  SessionPipeline* pipeline = model_->pipeline();
  pipeline->prepareBake(recipe, bake_.useCache ? cache_.dir() : std::string());
  return job_->start(tr("Bake"), [this, pipeline](const auto& progress) {
    const auto start = std::chrono::steady_clock::now();
    pipeline->runBake(progress);
    takeBakeOutputs();
    // The bake's whole time (decomposition, budget search, tables, codec, checks), as
    // `hapticbox report` times the default bake; not one stage of it.
    if (!pendingFromCache_) pendingSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  });
}

// --- error field, sweep, report --------------------------------------------------------

bool SessionJobs::startErrorField(int probesPerPoint, QString* error) {
  if (!model_->hasBoxes()) {
    if (error) *error = tr("Bake or open boxes first");
    return false;
  }
  if (busy(error)) return false;
  // The pipeline's error-field filter (a thin adapter over hb::compute_error_field) on the
  // reader's surface and the bake filter's boxes (or, for a box file opened by hand, the
  // model's), against the model's exact reference (not built again); the view's arrays are
  // its output's.
  SessionPipeline* pipeline = model_->pipeline();
  const bool fromBake =
      pipeline->bakeCurrent() && pipeline->bake()->GetBoxSet()->GetScene() == model_->sharedBoxes();
  const std::shared_ptr<const hb::BoxScene> boxes = fromBake ? nullptr : model_->sharedBoxes();
  const hb::Workspace workspace = model_->workspace();
  const SessionModel::References refsFuture = model_->references();
  return job_->start(tr("Error field"), [this, pipeline, boxes, workspace, probesPerPoint, refsFuture](const auto& progress) {
    pipeline->runErrorField(boxes, SessionModel::exactOf(refsFuture), workspace, probesPerPoint, progress);
    vtkHapticBoxErrorFieldFilter* filter = pipeline->errorField();
    pendingFieldSurface_ = vtkSmartPointer<vtkPolyData>::New();
    pendingFieldSurface_->ShallowCopy(filter->GetOutput());
    pendingField_ = std::make_unique<hb::ErrorField>(*filter->GetErrorField());
  });
}

bool SessionJobs::startReport(const QString& dir, const QString& errorFieldImage, std::size_t samples, QString* error) {
  if (!model_->hasBoxes()) {
    if (error) *error = tr("Bake or open boxes first");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = model_->sharedMesh();
  auto boxes = model_->sharedBoxes();
  const SessionModel::References refsFuture = model_->references();
  // The request `hapticbox report BOX MESH` builds (report/report_request.h), so the window
  // and the command line give the same report for the same input.
  hb::ReportRequest request;
  request.mesh_path = QFile::encodeName(model_->meshPath()).toStdString();
  request.mesh_hash = model_->meshHash();
  request.box_path = QFile::encodeName(model_->boxPath()).toStdString();
  request.bake_seconds = model_->bakeSeconds();  // 0 for boxes loaded from a file or the cache
  request.options.samples = samples;
  // The workspace follows from the mesh's diagonal (the default fit, as model_->law()).
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

bool SessionJobs::startSweep(const std::vector<int>& ms, const std::vector<int>& ns, std::size_t samples,
                             QString* error) {
  if (!model_->hasMesh()) {
    if (error) *error = tr("Open a model first");
    return false;
  }
  if (busy(error)) return false;
  auto mesh = model_->sharedMesh();
  const SessionModel::References refsFuture = model_->references();
  const hb::SourceInfo source = model_->sourceInfo();
  const hb::ForceLaw law = model_->law();
  const std::string cache = bake_.useCache ? cache_.dir() : std::string();
  return job_->start(tr("Sweep"), [=](const auto& progress) {
    const std::shared_ptr<const vtkHapticBoxReferenceQueries> references = refsFuture.get();
    const std::vector<hb::SweepReference> refs = references->References();
    hb::SweepOptions o;
    o.configs = hb::sweep_grid(ms, ns);
    o.samples = samples;
    o.timing_rounds = 3;
    o.law = law;
    o.cache_dir = cache;
    o.default_bake = true;  // the product's bake beside the samplings, as `hapticbox sweep` (cached after a default bake)
    o.progress = progress;
    pendingRows_ = hb::run_sweep(*mesh, source, refs, o);
    pendingCompression_.clear();
    pendingRowsReady_ = true;
  });
}
