// hapticbox.Scene (a box file, baked or loaded), hapticbox.bake and hapticbox.Exact: the
// core's box-file load/save, the default bake through the box cache (hb::choose_recipe and
// hb::bake_cached, as `hapticbox bake` makes it) or one sampling, and both answerers'
// query_many over an (N, 6) numpy array of segments (arrays.h).
#include "arrays.h"
#include "bindings.h"
#include "store/box_file.h"
#include "perception/budget_report.h"
#include "model_options_key.h"
#include "recipe/box_cache.h"
#include "recipe/recipe_choice.h"
#include "scene_access.h"
#include <pybind11/stl.h>
#include <optional>

namespace hb::python {

namespace {

constexpr const char* kQueryDoc = R"doc(Answers probe segments in one call (the GIL released while it runs).

segments: (N, 6) float array, one probe a row: handle sx, sy, sz then tip ex, ey, ez, in model
          units (mm). A C-contiguous float32 array is read in place (no copy); float64 is
          converted once. ValueError for another shape or dtype, or a NaN, infinite or too
          large value (the message names the row and column).
workspace: None for the default (the model's diagonal fitted to 80 mm at the device, 1500 N/m,
          forces up to 8 N), or the command line's --workspace spec
          "mm=D|real-size|metres-per-unit=S,stiffness=K,max-force=F".
Returns a dict of numpy arrays: "contact" (N,) bool; "depth" (N,) float32, penetration along
the segment, model units; "point" (N, 3) float32, the surface point met, model units; "normal"
(N, 3) float32, unit outward normal there; "force" (N, 3) float32, newtons at the workspace
(unclamped). The same answers as `hapticbox query --out` gives for the same rows.)doc";

std::optional<BoxCache> cache_of(const py::object& cache) {
  if (cache.is_none() || (py::isinstance<py::bool_>(cache) && !py::cast<bool>(cache))) return std::nullopt;
  if (py::isinstance<py::bool_>(cache)) return BoxCache();
  return BoxCache(py::cast<std::string>(py::str(cache)));
}

Scene bake(const Model& model, const py::object& m, const py::object& n, const py::object& refine,
           const py::object& budget, const py::object& cache) {
  SamplingGiven given;
  given.m = !m.is_none();
  given.n = !n.is_none();
  given.refine = !refine.is_none();
  BakeRecipe sampling;  // one raw box of exactly this sampling, as `bake -m M -n N [--refine]`
  if (given.m) sampling.options.params.m = py::cast<int>(m);
  if (given.n) sampling.options.params.n = py::cast<int>(n);
  if (given.refine) sampling.options.refine = py::cast<bool>(refine);
  if (given.m && (sampling.options.params.m < 2 || sampling.options.params.m > 1024))
    throw py::value_error("m: " + std::to_string(sampling.options.params.m) + " is outside [2, 1024] (position points per box face edge)");
  if (given.n && (sampling.options.params.n < 2 || sampling.options.params.n > 256))
    throw py::value_error("n: " + std::to_string(sampling.options.params.n) + " is outside [2, 256] (directions per sub-block face edge)");
  BakeRecipe recipe = choose_recipe(given, std::move(sampling));
  if (!budget.is_none()) {
    if (!bakes_default_recipe(given))
      throw py::value_error("budget: the error budget belongs to the default bake; drop m, n and refine, or budget");
    recipe.budget.budget = parse_budget(py::cast<std::string>(budget));
  }
  const std::optional<BoxCache> box_cache = cache_of(cache);
  const TriangleMesh& mesh = model.mesh();
  const SourceInfo source{model.path, vtk::model_hash(model.path, model.options), mesh.triangle_count(),
                          mesh.bounds().diagonal()};
  py::gil_scoped_release release;
  CachedBake baked = bake_cached(mesh, recipe, source, box_cache ? &*box_cache : nullptr);
  return Scene{std::make_shared<const BoxScene>(std::move(baked.result.scene)), {}};
}

Scene load_scene(const std::string& path, bool verify) {
  LoadOptions options;
  options.verify = verify;
  py::gil_scoped_release release;
  return Scene{std::make_shared<const BoxScene>(load_box_file(path, options)), path};
}

Exact exact_of(const Model& model) {
  Exact e;
  e.model = model.loaded;
  py::gil_scoped_release release;
  e.query = std::make_unique<ExactQuery>(e.model->mesh);
  return e;
}

} // namespace

void bind_scene(py::module_& m) {
  py::class_<Scene>(m, "Scene", R"doc(A scene of haptic boxes: what `hapticbox bake` writes to a .hbox file. Made by
hapticbox.bake(model) or Scene.load(path); immutable, safe to query from several threads.)doc")
      .def_static("load", &load_scene, py::arg("path"), py::kw_only(), py::arg("verify") = false,
                  "Opens a .hbox file (memory-mapped). verify=True hashes every table (`hapticbox info --verify`). "
                  "Raises hapticbox.IoError or hapticbox.InvalidInput naming the file and the cause.")
      .def(
          "save",
          [](Scene& s, const std::string& path) {
            {
              py::gil_scoped_release release;
              save_box_file(*s.scene, path);
            }
            s.path = path;
          },
          py::arg("path"), "Writes the scene to a .hbox file (hapticbox.IoError when it cannot).")
      .def(
          "query",
          [](const Scene& s, py::handle segments, const py::object& workspace) {
            const Workspace ws = workspace_of(scene_facts(*s.scene).diagonal, workspace);
            return answer_segments(*s.scene, segments, ws.law());
          },
          py::arg("segments"), py::kw_only(), py::arg("workspace") = py::none(), kQueryDoc)
      .def_property_readonly("path", [](const Scene& s) { return s.path; }, "The .hbox file it came from or went to.")
      .def("info", [](const Scene& s) { return scene_info(*s.scene, s.path); },
           "What the scene holds: boxes, the route that answers, its source model (path, hash, triangles, "
           "diagonal) and the workspace a query uses by default.")
      .def("__repr__", [](const Scene& s) { return scene_repr(*s.scene, s.path); });

  m.def("bake", &bake, py::arg("model"), py::kw_only(), py::arg("m") = py::none(), py::arg("n") = py::none(),
        py::arg("refine") = py::none(), py::arg("budget") = py::none(), py::arg("cache") = true,
        R"doc(Bakes a model into a Scene, as `hapticbox bake MODEL -o BOX` does.

Without m, n or refine: the default bake (automatic pieces, the error budget: at most 0.1% of
probes perceptibly different from exact; `budget="felt=0.1,raw=on,memory=48"` changes it).
With any of them: exactly one raw box of that sampling (`bake -m M -n N [--refine]`):
m position points per box face edge (2-1024, default 32), n directions per sub-block face edge
(2-256, default 16), refine=True for exact refinement on the triangles.
cache: True (the box cache shared with the command line and the window), a directory, or
False/None (bake, store nothing). The GIL is released while it bakes.)doc");

  py::class_<Exact>(m, "Exact", R"doc(The exact reference: Embree on the model's full mesh, with the same contact rule and
force law as the scene (what every HapticBox figure compares against).

Exact(model))doc")
      .def(py::init(&exact_of), py::arg("model"))
      .def(
          "query",
          [](const Exact& e, py::handle segments, const py::object& workspace) {
            const Workspace ws = workspace_of(e.model->mesh.bounds().diagonal(), workspace);
            return answer_segments(*e.query, segments, ws.law());
          },
          py::arg("segments"), py::kw_only(), py::arg("workspace") = py::none(), kQueryDoc);

  // The batch's measurement (bench/python_query.py): C++ query_many alone on the same array.
  m.def("_time_query_many", [](const Scene& s, py::handle segments) {
    return time_query_many(*s.scene, segments, workspace_of(scene_facts(*s.scene).diagonal, py::none()).law());
  });
  m.def("_time_query_many", [](const Exact& e, py::handle segments) {
    return time_query_many(*e.query, segments, workspace_of(e.model->mesh.bounds().diagonal(), py::none()).law());
  });
}

} // namespace hb::python
