#include "tool/tool_spec.h"
#include "errors.h"
#include "mesh/mesh_io.h"
#include "mesh/triangle_mesh.h"
#include "spec_parse.h"

namespace hb {

std::string ToolSpec::text() const {
  const std::string n = ",points=" + std::to_string(points);
  switch (kind) {
  case ToolKind::point: return "point,stylus-mm=" + spec_format(stylus_mm);
  case ToolKind::sphere: return "sphere,radius-mm=" + spec_format(radius_mm) + n;
  case ToolKind::capsule: return "capsule,radius-mm=" + spec_format(radius_mm) + ",length-mm=" + spec_format(length_mm) + n;
  case ToolKind::mesh:
    return "mesh=" + mesh_path + n + (margin_mm > 0.0 ? ",margin-mm=" + spec_format(margin_mm) : std::string());
  }
  return {};
}

ToolSpec parse_tool_spec(const std::string& spec) {
  const std::string option = "--tool";
  ToolSpec t;
  std::string head;
  bool has_mesh = false;
  const auto points = [&](const std::string& v, const std::string& what) {
    t.points = std::size_t(spec_number(v, what, 1, 1000000));
    if (double(t.points) != spec_number(v, what, 1, 1000000))
      throw InvalidInput(what + ": '" + v + "' is not a whole number of points");
  };
  parse_spec_keys(option, spec,
                  {{"radius-mm", [&](const std::string& v, const std::string& w) { t.radius_mm = spec_number(v, w, 1e-3, 1000); }},
                   {"length-mm", [&](const std::string& v, const std::string& w) { t.length_mm = spec_number(v, w, 1e-3, 1000); }},
                   {"points", points},
                   {"margin-mm", [&](const std::string& v, const std::string& w) { t.margin_mm = spec_number(v, w, 1e-3, 1000); }},
                   {"stylus-mm", [&](const std::string& v, const std::string& w) { t.stylus_mm = spec_number(v, w, 1e-3, 1000); }},
                   {"mesh", [&](const std::string& v, const std::string& w) {
                      if (spec_trim(v).empty()) throw InvalidInput(w + ": give the tool's mesh file (mesh=FILE)");
                      t.mesh_path = spec_trim(v);
                      has_mesh = true;
                    }}},
                  &head);
  head = spec_trim(head);
  if (has_mesh) {
    if (!head.empty() && head != "mesh")
      throw InvalidInput(option + ": '" + head + "' and mesh= name two tools (give one)");
    t.kind = ToolKind::mesh;
  } else if (head == "sphere" || head.empty()) {
    if (head.empty()) throw InvalidInput(option + ": name the tool first: sphere, capsule, point or mesh=FILE");
    t.kind = ToolKind::sphere;
  } else if (head == "capsule") {
    t.kind = ToolKind::capsule;
    if (t.length_mm < 2.0 * t.radius_mm)
      throw InvalidInput(option + " length-mm: " + spec_format(t.length_mm) + " is shorter than the diameter " +
                         spec_format(2.0 * t.radius_mm) + " mm");
  } else if (head == "point") {
    t.kind = ToolKind::point;
    t.points = 1;
  } else {
    throw InvalidInput(option + ": unknown tool '" + head + "' (sphere, capsule, point or mesh=FILE)");
  }
  return t;
}

ToolShape make_tool(const ToolSpec& spec, const std::function<TriangleMesh(const std::string&)>& load_mesh) {
  ToolShape shape;
  switch (spec.kind) {
  case ToolKind::point: shape = make_point_tool(spec.stylus_mm * 1e-3); break;
  case ToolKind::sphere: shape = make_sphere_tool(spec.radius_mm * 1e-3, spec.points); break;
  case ToolKind::capsule: shape = make_capsule_tool(spec.radius_mm * 1e-3, spec.length_mm * 1e-3, spec.points); break;
  case ToolKind::mesh: {
    const TriangleMesh mesh = load_mesh ? load_mesh(spec.mesh_path) : read_mesh(spec.mesh_path);
    try {
      shape = make_mesh_tool(mesh, spec.points, spec.margin_mm * 1e-3);
    } catch (const InvalidInput& e) {
      throw InvalidInput(spec.mesh_path + ": " + e.what());
    }
    break;
  }
  }
  shape.spec = spec.text();
  return shape;
}

} // namespace hb
