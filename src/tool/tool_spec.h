#pragma once
// A tool as the user names it: "sphere,radius-mm=2,points=1000",
// "capsule,radius-mm=1,length-mm=20,points=2000", "mesh=FILE,points=5000[,margin-mm=0.5]" or
// "point". Sizes are millimetres at the device (the one workspace scale).
#include "tool/tool_shape.h"
#include <cstddef>
#include <functional>
#include <string>

namespace hb {

struct TriangleMesh;

struct ToolSpec {
  ToolKind kind = ToolKind::sphere;
  double radius_mm = 2.0;      ///< sphere, capsule.
  double length_mm = 10.0;     ///< capsule, tip to tip.
  std::size_t points = 1000;   ///< 1 to 1,000,000 (the point tool has one).
  std::string mesh_path;       ///< mesh: the tool's surface, in millimetres.
  double margin_mm = 0.0;      ///< mesh: how far inside a handle lies (0: automatic).
  double stylus_mm = 8.0;      ///< point: the stylus behind the tip.

  /// The spec parse_tool_spec reads back.
  std::string text() const;
};

/// Parses a tool spec (above). Throws hb::InvalidInput naming the key and the bad value.
ToolSpec parse_tool_spec(const std::string& spec);

/// The tool's point shell. `load_mesh` reads a mesh tool's file (a front end passes its own
/// reader of every format; the default reads the core's formats). Throws hb::InvalidInput or
/// hb::IoError naming the file or value.
ToolShape make_tool(const ToolSpec& spec,
                    const std::function<TriangleMesh(const std::string&)>& load_mesh = nullptr);

} // namespace hb
