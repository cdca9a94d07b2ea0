// hapticbox.Model: any model the product reads (meshes, volumes, CAD solids, scenes) through
// the one loader the command line and the window use (hb::vtk::load_model_guarded), with the
// command line's model options as keywords (unit=, volume=, cad=: hb::vtk::model_options_from_specs).
#include "bindings.h"
#include "model_options_key.h"
#include "model_spec.h"
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <cstring>

namespace hb::python {

namespace {

std::string spec_or_empty(const py::object& o, const char* name) {
  if (o.is_none()) return {};
  if (!py::isinstance<py::str>(o)) throw py::type_error(std::string(name) + ": expected a string spec or None");
  return py::cast<std::string>(o);
}

Model load_model(const std::string& path, const py::object& unit, const py::object& volume, const py::object& cad) {
  Model m;
  m.path = path;
  m.options = vtk::model_options_from_specs(spec_or_empty(unit, "unit"), spec_or_empty(volume, "volume"),
                                            spec_or_empty(cad, "cad"));
  py::gil_scoped_release release;
  m.loaded = std::make_shared<const vtk::LoadedModel>(vtk::load_model_guarded(path, m.options));
  return m;
}

const char* kind_name(vtk::ModelKind kind) {
  switch (kind) {
  case vtk::ModelKind::Volume: return "volume";
  case vtk::ModelKind::Cad: return "cad";
  case vtk::ModelKind::Scene: return "scene";
  default: return "mesh";
  }
}

py::dict info(const Model& m) {
  const TriangleMesh& mesh = m.mesh();
  const vtk::LoadedModel& l = *m.loaded;
  const Bounds b = mesh.bounds();
  py::dict d;
  d["path"] = m.path;
  d["format"] = l.format;
  d["kind"] = kind_name(l.kind);
  d["vertices"] = mesh.vertex_count();
  d["triangles"] = mesh.triangle_count();
  d["bounds_min"] = py::make_tuple(b.min.x(), b.min.y(), b.min.z());
  d["bounds_max"] = py::make_tuple(b.max.x(), b.max.y(), b.max.z());
  d["diagonal"] = b.diagonal();
  d["unit"] = l.unit;
  d["unit_source"] = l.unit_source;
  d["mm_per_unit"] = l.mm_per_unit;
  d["open"] = l.report.open;
  d["non_manifold"] = l.report.non_manifold;
  d["inconsistent_orientation"] = l.report.inconsistent_orientation;
  d["degenerate_dropped"] = l.report.degenerate_dropped;
  d["warnings"] = l.report.warnings;
  d["facts"] = py::module_::import("json").attr("loads")(l.facts.dump());
  return d;
}

} // namespace

void bind_model(py::module_& m) {
  py::class_<Model>(m, "Model", R"doc(A model read as HapticBox reads it: a mesh (.off .obj .ply .stl .om .vtp .vtk), a medical
volume (NIfTI, MetaImage, NRRD, DICOM series), a CAD solid (STEP, IGES) or a scene (glTF, GLB,
3MF, FBX, Collada), as triangles in millimetres.

Model(path, unit=None, volume=None, cad=None)
  unit:   length of one unit of the file: "mm", "cm", "m", "um", "in", "ft" (default: the file's
          own unit, else mm); the model is scaled to mm (`hapticbox --unit`).
  volume: a volume's surface, "iso=V|label=L,smooth=N,triangles=N" (`--volume`).
  cad:    a CAD solid's tessellation, "chordal-mm=D,force-tolerance=N,accept-lost-faces" (`--cad`).
Raises hapticbox.IoError (an OSError) for a missing or unreadable file, hapticbox.InvalidInput
(a ValueError) for a damaged one or a bad option; the message names the file and the cause.)doc")
      .def(py::init(&load_model), py::arg("path"), py::kw_only(), py::arg("unit") = py::none(),
           py::arg("volume") = py::none(), py::arg("cad") = py::none())
      .def_property_readonly("path", [](const Model& m) { return m.path; }, "The file it was read from.")
      .def_property_readonly("triangle_count", [](const Model& m) { return m.mesh().triangle_count(); })
      .def_property_readonly("vertex_count", [](const Model& m) { return m.mesh().vertex_count(); })
      .def_property_readonly("diagonal", [](const Model& m) { return m.mesh().bounds().diagonal(); },
                             "Bounding-box diagonal, mm (the default workspace fits it to 80 mm at the device).")
      .def_property_readonly("hash", [](const Model& m) { return vtk::model_hash(m.path, m.options); },
                             "The hash a box file baked from this model records (file bytes and options).")
      .def_property_readonly(
          "vertices",
          [](const Model& m) {
            const auto& p = m.mesh().positions;
            py::array_t<float> a({py::ssize_t(p.size()), py::ssize_t(3)});
            float* out = a.mutable_data();
            for (std::size_t i = 0; i < p.size(); ++i) std::memcpy(out + 3 * i, p[i].data(), 3 * sizeof(float));
            return a;
          },
          "(V, 3) float32 vertex positions, mm (a copy).")
      .def_property_readonly(
          "triangles",
          [](const Model& m) {
            const auto& t = m.mesh().triangles;
            py::array_t<std::uint32_t> a({py::ssize_t(t.size()), py::ssize_t(3)});
            std::memcpy(a.mutable_data(), t.data(), t.size() * sizeof(Triangle));
            return a;
          },
          "(T, 3) uint32 vertex indices of each triangle (a copy).")
      .def("info", &info, "What `hapticbox info MODEL` reports: format, counts, bounds (mm), unit, defects, warnings, "
                          "and the volume's or CAD solid's facts.")
      .def("__repr__", [](const Model& m) {
        return "<hapticbox.Model '" + m.path + "': " + std::to_string(m.mesh().triangle_count()) + " triangles>";
      });
}

} // namespace hb::python
