#pragma once
// The objects the `hapticbox` module hands to Python, and the function that binds each group
// (module.cpp calls them in order). Bindings only: every figure comes from a core or VTK
// pipeline function the command line calls too.
#include "contact/workspace.h"
#include "evaluation/comparison.h"
#include "exact/exact_query.h"
#include "scene/box_scene.h"
#include "model_loader.h"
#include <pybind11/pybind11.h>
#include <memory>
#include <string>

namespace hb::python {

namespace py = pybind11;

/// A model as hb::vtk::load_model_guarded read it (millimetres), with the options that shaped
/// it (they are part of its hash, which a bake records).
struct Model {
  std::string path;
  vtk::ModelOptions options;
  std::shared_ptr<const vtk::LoadedModel> loaded;
  const TriangleMesh& mesh() const { return loaded->mesh; }
};

/// A baked or loaded scene (immutable: shared by Python objects and running queries).
struct Scene {
  std::shared_ptr<const BoxScene> scene;
  std::string path;  ///< the file it was loaded from or last saved to, else empty.
};

/// The exact reference (Embree over the model's full mesh), which keeps its model alive.
struct Exact {
  std::shared_ptr<const vtk::LoadedModel> model;
  std::unique_ptr<ExactQuery> query;
};

/// The workspace of a model of this diagonal under the `workspace=` spec (empty or None: the
/// default, an 80 mm diagonal at 1500 N/m; hb::parse_workspace_spec), and the judge of the
/// `perceptual=` spec (hb::parse_thresholds) with the workspace's force limit.
Workspace workspace_of(double model_diagonal, const py::object& workspace);
PerceptualJudge judge_of(const py::object& workspace, const std::string& perceptual);

void bind_errors(py::module_& m);
void bind_model(py::module_& m);
void bind_scene(py::module_& m);
void bind_evaluation(py::module_& m);
void bind_field(py::module_& m);
void bind_tool(py::module_& m);

} // namespace hb::python
