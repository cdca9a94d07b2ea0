// hapticbox.Tool: a tool with volume (src/tool/: ToolSpec, ToolShape, ToolProbe) answered at
// poses by a scene or the exact reference, as `hapticbox query BOX --tool SPEC --poses CSV`.
#include "arrays.h"
#include "bindings.h"
#include "evaluation/tool_poses_csv.h"
#include "model_spec.h"
#include "scene_access.h"
#include "tool/tool_contact.h"
#include "tool/tool_spec.h"
#include <pybind11/numpy.h>
#include <cstring>
#include <vector>

namespace hb::python {

namespace {

struct Tool {
  ToolSpec spec;
  ToolShape shape;
};

Tool make(const std::string& text) {
  Tool t;
  t.spec = parse_tool_spec(text);
  py::gil_scoped_release release;
  // A mesh tool is read as every model is (any format the product reads).
  t.shape = make_tool(t.spec, [](const std::string& path) { return vtk::load_model_guarded(path).mesh; });
  return t;
}

std::vector<ToolPose> poses_of(py::handle poses) {
  const FloatRows rows = float_rows(poses, "poses", {3, 7}, "x, y, z[, qw, qx, qy, qz]");
  std::vector<ToolPose> out(rows.count);
  for (std::size_t i = 0; i < rows.count; ++i) {
    float v[7] = {0, 0, 0, 1, 0, 0, 0};
    std::memcpy(v, rows.values + i * rows.width, rows.width * sizeof(float));
    try {
      out[i] = tool_pose(v, "poses[" + std::to_string(i) + "]: ");
    } catch (const InvalidInput& e) {
      throw py::value_error(e.what());
    }
  }
  return out;
}

py::dict answer(const Tool& tool, const ContactQuery& query, py::handle poses, const Workspace& ws) {
  const std::vector<ToolPose> p = poses_of(poses);
  const py::ssize_t n = py::ssize_t(p.size());
  py::array_t<float> force({n, py::ssize_t(3)}), torque({n, py::ssize_t(3)});
  py::array_t<std::uint32_t> contacts(n);
  float *f = force.mutable_data(), *t = torque.mutable_data();
  std::uint32_t* c = contacts.mutable_data();
  {
    py::gil_scoped_release release;
    ToolProbe probe(tool.shape, ws.metres_per_unit);  // each pose on its own, as `query --tool`
    const ForceLaw law = ws.law();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const ToolAnswer a = probe.answer(query, p[i], law);
      std::memcpy(f + 3 * i, a.force.data(), 3 * sizeof(float));
      std::memcpy(t + 3 * i, a.torque.data(), 3 * sizeof(float));
      c[i] = a.contacts;
    }
  }
  py::dict d;
  d["force"] = force;
  d["torque"] = torque;
  d["contacts"] = contacts;
  return d;
}

constexpr const char* kAnswerDoc = R"doc(The tool's net force and torque at each pose, each pose on its own (no coupling), as
`hapticbox query BOX --tool SPEC --poses CSV` answers them.

answerer: a Scene or an Exact. poses: (N, 3) x, y, z (the tool's centre, model units) or (N, 7)
with its orientation qw, qx, qy, qz (normalised), float. workspace: as Scene.query.
Returns "force" (N, 3) float32 N on the tool, "torque" (N, 3) float32 N m about its centre,
"contacts" (N,) uint32 points of the shell in contact.)doc";

} // namespace

void bind_tool(py::module_& m) {
  py::class_<Tool>(m, "Tool", R"doc(A tool with volume: a point shell whose every point is the product's probe segment.

Tool(spec): "sphere,radius-mm=R,points=N", "capsule,radius-mm=R,length-mm=L,points=N" or
"mesh=FILE,points=N" (sizes in device mm at the workspace; `hapticbox query --tool`).)doc")
      .def(py::init(&make), py::arg("spec"))
      .def_property_readonly("spec", [](const Tool& t) { return t.spec.text(); }, "The spec, every key.")
      .def_property_readonly("points", [](const Tool& t) { return t.shape.points.size(); }, "Points of the shell.")
      .def(
          "answer",
          [](const Tool& t, const Scene& s, py::handle poses, const py::object& workspace) {
            return answer(t, *s.scene, poses, workspace_of(scene_facts(*s.scene).diagonal, workspace));
          },
          py::arg("answerer"), py::arg("poses"), py::kw_only(), py::arg("workspace") = py::none(), kAnswerDoc)
      .def(
          "answer",
          [](const Tool& t, const Exact& e, py::handle poses, const py::object& workspace) {
            return answer(t, *e.query, poses, workspace_of(e.model->mesh.bounds().diagonal(), workspace));
          },
          py::arg("answerer"), py::arg("poses"), py::kw_only(), py::arg("workspace") = py::none(), kAnswerDoc);
}

} // namespace hb::python
