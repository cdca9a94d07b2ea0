// SessionPipeline: the window's reader -> decomposition -> bake -> error-field pipeline.
//  1. The filters are made once per model and connected as the design names them; their
//     errors are read back (GetLastError) instead of going to VTK's output window.
//  2. A run attaches a progress observer to each filter it updates (the decomposition takes
//     the first third of the bar when it runs); a cancel aborts the filter at its next
//     progress call, and the filter that failed is marked modified so the next run redoes it.
//  3. The error field reads the reader's surface and the bake filter's boxes (or given boxes)
//     with the session's exact reference.
#include "SessionPipeline.h"
#include "errors.h"
#include "contact/contact.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxDecompositionFilter.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxMeshReader.h"
#include "vtkHapticBoxSet.h"
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <utility>
#include <vector>

namespace {

// Forwards a filter's progress events into [begin, end] of `progress`; a false answer aborts
// the filter. Removes its observer when it goes.
class ProgressForward {
public:
  ProgressForward(vtkAlgorithm* filter, const std::function<bool(double)>& progress, double begin, double end)
      : filter_(filter), progress_(progress), begin_(begin), end_(end) {
    auto command = vtkSmartPointer<vtkCallbackCommand>::New();
    command->SetClientData(this);
    command->SetCallback([](vtkObject* caller, unsigned long, void* client, void* data) {
      auto* self = static_cast<ProgressForward*>(client);
      const double f = *static_cast<double*>(data);
      if (self->progress_ && !self->progress_(self->begin_ + (self->end_ - self->begin_) * f)) {
        self->cancelled_ = true;
        static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
      }
    });
    tag_ = filter_->AddObserver(vtkCommand::ProgressEvent, command);
  }
  ~ProgressForward() { filter_->RemoveObserver(tag_); }
  ProgressForward(const ProgressForward&) = delete;
  ProgressForward& operator=(const ProgressForward&) = delete;
  bool cancelled() const { return cancelled_; }

private:
  vtkAlgorithm* filter_;
  std::function<bool(double)> progress_;
  double begin_, end_;
  bool cancelled_ = false;
  unsigned long tag_ = 0;
};

// The filters report their errors through GetLastError: keep VTK's output window closed.
void quiet(vtkAlgorithm* filter) {
  auto silent = vtkSmartPointer<vtkCallbackCommand>::New();
  filter->AddObserver(vtkCommand::ErrorEvent, silent);
  filter->AddObserver(vtkCommand::WarningEvent, silent);
}

}  // namespace

SessionPipeline::SessionPipeline(vtkSmartPointer<vtkHapticBoxMeshReader> reader, const hb::SourceInfo& source)
    : reader_(std::move(reader)),
      decomposition_(vtkSmartPointer<vtkHapticBoxDecompositionFilter>::New()),
      bake_(vtkSmartPointer<vtkHapticBoxBakeFilter>::New()),
      errorField_(vtkSmartPointer<vtkHapticBoxErrorFieldFilter>::New()) {
  for (vtkAlgorithm* f : std::vector<vtkAlgorithm*>{decomposition_, bake_, errorField_}) quiet(f);
  decomposition_->SetInputConnection(reader_->GetOutputPort());
  bake_->SetInputConnection(reader_->GetOutputPort());
  bake_->SetSource(source);
  errorField_->SetInputConnection(0, reader_->GetOutputPort());
  errorField_->SetSampleModeToVertices();
}

SessionPipeline::~SessionPipeline() = default;

bool SessionPipeline::prepareBake(const hb::BakeRecipe& recipe, const std::string& cacheDir) {
  bake_->SetRecipe(recipe);
  bake_->SetCacheDirectory(cacheDir.empty() ? nullptr : cacheDir.c_str());
  const bool automatic = recipe.pieces.kind == hb::PiecesRecipe::Kind::automatic && recipe.pieces.resolved.empty();
  decomposes_ = automatic && !bake_->HasCachedScene();
  if (decomposes_) {
    decomposition_->SetOptions(recipe.pieces.automatic);
    bake_->SetInputConnection(decomposition_->GetOutputPort());
  } else {
    bake_->SetInputConnection(reader_->GetOutputPort());
  }
  bakeCurrent_ = false;
  return decomposes_;
}

bool SessionPipeline::hasCachedScene() const { return bake_->HasCachedScene(); }

void SessionPipeline::runBake(const std::function<bool(double)>& progress, bool cacheOnly) {
  bakeCurrent_ = false;
  bake_->SetCacheOnly(cacheOnly);
  bake_->SetAbortExecute(0);
  decomposition_->SetAbortExecute(0);
  bool cancelled = false;
  {
    ProgressForward onDecomposition(decomposition_, progress, 0.0, 1.0 / 3.0);
    ProgressForward onBake(bake_, progress, decomposes_ ? 1.0 / 3.0 : 0.0, 1.0);
    bake_->Update();
    cancelled = onDecomposition.cancelled() || onBake.cancelled();
  }
  // A failed or cancelled filter runs again next time (its output is not the result).
  const std::string decompositionError = decomposes_ ? decomposition_->GetLastError() : std::string();
  if (cancelled || !decompositionError.empty()) decomposition_->Modified();
  if (cancelled || !bake_->GetLastError().empty()) bake_->Modified();
  if (cancelled) throw hb::Cancelled("bake cancelled");
  if (!decompositionError.empty()) throw hb::Error("decomposition: " + decompositionError);
  if (!bake_->GetLastError().empty()) throw hb::Error(bake_->GetLastError());
  vtkHapticBoxSet* set = bake_->GetBoxSet();
  if (!set || !set->GetScene()) throw hb::Error("the bake filter gave no boxes");
  bakeCurrent_ = true;
}

void SessionPipeline::runErrorField(std::shared_ptr<const hb::BoxScene> boxes,
                                    std::shared_ptr<const hb::ExactQuery> exact, const hb::Workspace& workspace,
                                    int probesPerPoint, const std::function<bool(double)>& progress) {
  if (boxes) {
    auto set = vtkSmartPointer<vtkHapticBoxSet>::New();
    set->SetScene(std::move(boxes));
    errorField_->SetBoxSetData(set);
  } else {
    if (!bakeCurrent_) throw hb::InvalidInput("the bake filter holds no current boxes");
    errorField_->SetBoxSetConnection(bake_->GetOutputPort(0));
  }
  errorField_->SetExactQuery(std::move(exact));
  errorField_->SetProbesPerPoint(probesPerPoint);
  errorField_->SetWorkspace(workspace);
  errorField_->SetAbortExecute(0);
  bool cancelled = false;
  {
    ProgressForward onField(errorField_, progress, 0.0, 1.0);
    errorField_->Update();
    cancelled = onField.cancelled();
  }
  if (cancelled || !errorField_->GetErrorField()) errorField_->Modified();
  if (cancelled) throw hb::Cancelled("error field cancelled");
  if (!errorField_->GetErrorField())
    throw hb::Error(errorField_->GetLastError().empty() ? "error field failed" : errorField_->GetLastError());
}
