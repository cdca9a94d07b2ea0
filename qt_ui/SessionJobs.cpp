// SessionJobs: the window's long jobs.
//  1. startBake runs hb::bake_cached (hb::bake through the shared box cache) on the worker with
//     the recipe of the bake settings: hb::default_recipe() unless advanced, so the window's
//     Bake is `hapticbox bake MESH -o BOX`'s.
//  2. startErrorField runs the pipeline's vtkHapticBoxErrorFieldFilter on the model's surface
//     and boxes (its output's arrays go to the view); startSweep and startReport run
//     hb::run_sweep and the report request of `hapticbox report` (report/report_request.h)
//     against the model's references.
//  3. When the job ends, its result is installed into the model on the GUI thread.
#include "SessionJobs.h"
#include "BackgroundJob.h"
#include "errors.h"
#include "report_request.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxReferenceQueries.h"
#include "vtkHapticBoxSet.h"
#include <QFile>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <functional>
#include <optional>

// --- bake settings ---------------------------------------------------------------------

hb::BakeRecipe BakeSettings::recipe() const {
  if (!advanced) return hb::default_recipe();  // what `hapticbox bake MESH -o BOX` bakes
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
    model_->installBoxes(std::move(pendingBoxes_), pendingSeconds_, pendingFromCache_);
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
  pendingCacheWarning_.clear();
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
  if (!model_->hasMesh() || !bake_.useCache) return false;
  try {
    const hb::BakeRecipe recipe = bake_.recipe();
    std::optional<hb::BoxScene> scene = cache_.load(model_->meshHash(), recipe);
    if (!scene) return false;
    model_->installBoxes(std::make_shared<hb::BoxScene>(std::move(*scene)), 0.0, true);
    emit statusMessage(tr("Loaded cached boxes %1")
                           .arg(QString::fromStdString(cache_.path_for(model_->meshHash(), recipe))));
    return true;
  } catch (const std::exception& e) {
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
  auto mesh = model_->sharedMesh();
  const hb::SourceInfo source = model_->sourceInfo();
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

// --- error field, sweep, report --------------------------------------------------------

bool SessionJobs::startErrorField(int probesPerPoint, QString* error) {
  if (!model_->hasBoxes()) {
    if (error) *error = tr("Bake or open boxes first");
    return false;
  }
  if (busy(error)) return false;
  // The pipeline's error-field filter (a thin adapter over hb::compute_error_field) on the
  // model's surface (a shallow copy: the view keeps drawing the original) and boxes; the
  // view's arrays are its output's.
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->ShallowCopy(model_->surface());
  auto boxes = vtkSmartPointer<vtkHapticBoxSet>::New();
  boxes->SetScene(model_->sharedBoxes());
  const hb::ForceLaw law = model_->law();
  return job_->start(tr("Error field"), [this, surface, boxes, law, probesPerPoint](const auto& progress) {
    auto filter = vtkSmartPointer<vtkHapticBoxErrorFieldFilter>::New();
    filter->SetInputData(0, surface);
    filter->SetBoxSetData(boxes);
    filter->SetSampleModeToVertices();
    filter->SetProbesPerPoint(probesPerPoint);
    filter->SetStiffness(law.stiffness_n_per_m);
    filter->SetMetresPerUnit(law.metres_per_unit);
    // The job's progress bar and cancel: a cancel aborts the filter at its next progress call.
    bool cancelled = false;
    auto onProgress = vtkSmartPointer<vtkCallbackCommand>::New();
    onProgress->SetCallback([](vtkObject* caller, unsigned long, void* client, void* data) {
      auto* state = static_cast<std::pair<const std::function<bool(double)>*, bool*>*>(client);
      if (!(*state->first)(*static_cast<double*>(data))) {
        *state->second = true;
        static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
      }
    });
    const std::function<bool(double)> forward = progress;
    std::pair<const std::function<bool(double)>*, bool*> state{&forward, &cancelled};
    onProgress->SetClientData(&state);
    filter->AddObserver(vtkCommand::ProgressEvent, onProgress);
    filter->AddObserver(vtkCommand::ErrorEvent, vtkSmartPointer<vtkCallbackCommand>::New());  // shown by the window
    filter->Update();
    if (cancelled) throw hb::Cancelled("error field cancelled");
    if (!filter->GetErrorField()) throw hb::Error(filter->GetLastError().empty() ? "error field failed" : filter->GetLastError());
    pendingFieldSurface_ = filter->GetOutput();
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
  request.options.law = model_->law();
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
    o.progress = progress;
    pendingRows_ = hb::run_sweep(*mesh, source, refs, o);
    pendingCompression_.clear();
    pendingRowsReady_ = true;
  });
}
