#pragma once
// The window's VTK pipeline over the open model, as the product's design names it:
//   vtkHapticBoxMeshReader -> vtkHapticBoxDecompositionFilter -> vtkHapticBoxBakeFilter
//   -> vtkHapticBoxErrorFieldFilter
// each a thin adapter over the core (hb::decompose_auto, hb::bake_cached with the recipe and
// the box cache `hapticbox bake`, sweep and report use, hb::compute_error_field against the
// session's shared exact reference). The session's views draw these filters' outputs: the
// bake filter's outlines and piece ids, the error-field filter's arrays.
// Updates run on whatever thread calls them (the job's worker), one at a time; nothing here
// touches a widget.
#include "recipe/bake_recipe.h"
#include "scene/box_scene.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxDecompositionFilter.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxMeshReader.h"
#include <vtkSmartPointer.h>
#include <functional>
#include <memory>
#include <string>

namespace hb {
class ExactQuery;
struct ForceLaw;
}

class SessionPipeline {
public:
  /// The pipeline downstream of `reader` (already updated on the model), which records
  /// `source` (path and hb::hash_model hash) in what it bakes.
  SessionPipeline(vtkSmartPointer<vtkHapticBoxMeshReader> reader, const hb::SourceInfo& source);
  ~SessionPipeline();

  vtkHapticBoxMeshReader* reader() const { return reader_; }
  vtkHapticBoxDecompositionFilter* decomposition() const { return decomposition_; }
  vtkHapticBoxBakeFilter* bake() const { return bake_; }
  vtkHapticBoxErrorFieldFilter* errorField() const { return errorField_; }

  /// Sets the bake for `recipe` and the cache directory (empty: no cache) and connects it:
  /// through the decomposition filter (with the recipe's automatic options) when the recipe's
  /// pieces are automatic and the cache holds no scene for it, straight from the reader
  /// otherwise (a cached automatic bake opens without decomposing: the .hbox file holds the
  /// piece ids). Returns whether the decomposition filter is in the chain.
  bool prepareBake(const hb::BakeRecipe& recipe, const std::string& cacheDir);
  /// True when the cache holds the scene prepareBake asks for.
  bool hasCachedScene() const;
  /// Updates the bake filter (and the decomposition filter upstream when in the chain).
  /// `progress` (may be empty) takes [0, 1] and returns false to cancel. `cacheOnly`: load the
  /// cached scene or fail, never bake. Throws hb::Cancelled or hb::Error naming the filter's cause.
  void runBake(const std::function<bool(double)>& progress, bool cacheOnly = false);
  /// True when the bake filter's output holds the result of the last runBake (not failed or
  /// cancelled since).
  bool bakeCurrent() const { return bakeCurrent_; }

  /// Updates the error-field filter: the reader's surface against the bake filter's boxes when
  /// `boxes` is null (they must be current), else against `boxes` (e.g. a loaded .hbox file);
  /// `exact` is the session's exact reference over the same mesh (not built again).
  void runErrorField(std::shared_ptr<const hb::BoxScene> boxes, std::shared_ptr<const hb::ExactQuery> exact,
                     const hb::Workspace& workspace, int probesPerPoint, const std::function<bool(double)>& progress);

private:
  vtkSmartPointer<vtkHapticBoxMeshReader> reader_;
  vtkSmartPointer<vtkHapticBoxDecompositionFilter> decomposition_;
  vtkSmartPointer<vtkHapticBoxBakeFilter> bake_;
  vtkSmartPointer<vtkHapticBoxErrorFieldFilter> errorField_;
  bool decomposes_ = false;
  bool bakeCurrent_ = false;
};
