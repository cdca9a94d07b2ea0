// The `hapticbox._core` extension (the `hapticbox` package re-exports it with the VTK glue):
// the errors the core throws as Python exceptions carrying its messages, then the model, the
// scene and the exact reference, the verdict and eval's figures, the error field.
#include "bindings.h"
#include "errors.h"
#include "spec_parse.h"

namespace hb::python {

Workspace workspace_of(double model_diagonal, const py::object& workspace) {
  WorkspaceOptions options;
  if (!workspace.is_none()) parse_workspace_spec(py::cast<std::string>(workspace), options);
  return make_workspace(model_diagonal, options);
}

PerceptualJudge judge_of(const py::object& workspace, const std::string& perceptual) {
  WorkspaceOptions options;
  if (!workspace.is_none()) parse_workspace_spec(py::cast<std::string>(workspace), options);
  PerceptualJudge judge;
  judge.thresholds = parse_thresholds(perceptual);
  judge.max_force_n = options.max_force_n;
  return judge;
}

void bind_errors(py::module_& m) {
  // OSError and ValueError bases: `except OSError` / `except ValueError` catch them as a
  // Python user expects of a missing file or a bad value; hapticbox.Error catches all.
  static py::exception<Error> base(m, "Error", PyExc_RuntimeError);
  static py::handle io = PyErr_NewExceptionWithDoc("hapticbox.IoError",
                                                   "A file could not be opened, read or written (the message names it and why).",
                                                   py::make_tuple(base, py::handle(PyExc_OSError)).release().ptr(), nullptr);
  static py::handle invalid = PyErr_NewExceptionWithDoc(
      "hapticbox.InvalidInput", "A file's content or a value is invalid (the message names the file or value and the cause).",
      py::make_tuple(base, py::handle(PyExc_ValueError)).release().ptr(), nullptr);
  m.attr("IoError") = io;
  m.attr("InvalidInput") = invalid;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IoError& e) {
      PyErr_SetString(io.ptr(), e.what());
    } catch (const InvalidInput& e) {
      PyErr_SetString(invalid.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(base.ptr(), e.what());
    }
  });
}

} // namespace hb::python

PYBIND11_MODULE(_core, m) {
  m.doc() = "HapticBox: bake a model into haptic boxes, answer probe segments, judge them against exact Embree";
  m.attr("__version__") = HB_VERSION;
  hb::python::bind_errors(m);
  hb::python::bind_model(m);
  hb::python::bind_scene(m);
  hb::python::bind_evaluation(m);
  hb::python::bind_field(m);
  hb::python::bind_tool(m);
}
