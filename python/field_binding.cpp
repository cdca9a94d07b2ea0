// hapticbox.error_field: the error field through the VTK pipeline `hapticbox field` runs (the
// model as polydata -> vtkHapticBoxErrorFieldFilter with the scene as its box set), so the
// arrays are the command's. The output vtkPolyData crosses to VTK's own Python (python3-vtk9,
// the same VTK libraries) by its address; hapticbox/__init__.py wraps it and takes a shallow
// copy, so the C++ handle may go at once.
#include "bindings.h"
#include "errors.h"
#include "polydata_files.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <cstdio>

namespace hb::python {

namespace {

/// A vtkPolyData made here, held until VTK's Python has wrapped it.
struct PolyDataHandle {
  vtkSmartPointer<vtkPolyData> data;
  /// VTK's Python pointer text, "_<hex>_p_vtkPolyData" (vtkPolyData(text) wraps the object).
  std::string pointer_text() const {
    char text[64];
    std::snprintf(text, sizeof text, "_%016llx_p_vtkPolyData",
                  static_cast<unsigned long long>(reinterpret_cast<std::uintptr_t>(data.GetPointer())));
    return text;
  }
};

PolyDataHandle error_field(const Scene& scene, const Model& model, int probes, std::uint64_t seed, long long even,
                           const py::object& workspace, const std::string& perceptual) {
  if (probes < 1 || probes > 100000) throw py::value_error("probes: " + std::to_string(probes) + " is outside [1, 100000] (probes per point)");
  if (even < 0 || even > 100000000) throw py::value_error("even: " + std::to_string(even) + " is outside [0, 1e8] (0: the vertices)");
  const TriangleMesh& mesh = model.mesh();
  const Workspace ws = workspace_of(mesh.bounds().diagonal(), workspace);  // as field and eval
  const PerceptualJudge judge = judge_of(workspace, perceptual);
  PolyDataHandle out;
  {
    py::gil_scoped_release release;
    vtkNew<vtkHapticBoxErrorFieldFilter> field;
    field->SetInputData(vtkHapticBoxUtilities::ToPolyData(mesh));
    vtkNew<vtkHapticBoxSet> boxes;
    boxes->SetScene(scene.scene);
    field->SetBoxSetData(boxes);
    field->SetProbesPerPoint(probes);
    field->SetSeed(seed);
    field->SetWorkspace(ws, judge);
    if (even > 0) {
      field->SetSampleModeToEven();
      field->SetNumberOfSamples(vtkIdType(even));
    }
    field->Update();
    if (!field->GetLastError().empty()) throw Error("error field: " + field->GetLastError());
    out.data = vtkSmartPointer<vtkPolyData>::New();
    out.data->ShallowCopy(field->GetOutput());
    vtk::add_provenance(out.data->GetFieldData(), {{{"HapticBoxVersion", HB_VERSION},
                                                    {"Mesh", model.path},
                                                    {"BoxFile", scene.path},
                                                    {"Workspace", ws.describe()},
                                                    {"Perceptual", thresholds_spec(judge.thresholds)}},
                                                   {}});
  }
  return out;
}

} // namespace

void bind_field(py::module_& m) {
  py::class_<PolyDataHandle>(m, "_PolyDataHandle")
      .def_property_readonly("pointer_text", &PolyDataHandle::pointer_text)
      .def_property_readonly("points", [](const PolyDataHandle& h) { return h.data->GetNumberOfPoints(); });
  m.def("_model_polydata", [](const Model& model) {
    PolyDataHandle h;
    h.data = vtkHapticBoxUtilities::ToPolyData(model.mesh());
    return h;
  });
  m.def("_error_field", &error_field, py::arg("scene"), py::arg("model"), py::kw_only(), py::arg("probes") = 1,
        py::arg("seed") = 1, py::arg("even") = 0, py::arg("workspace") = py::none(), py::arg("perceptual") = "nominal");
}

} // namespace hb::python
