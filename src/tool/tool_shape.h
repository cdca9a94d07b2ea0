#pragma once
// A tool with volume as a point shell (McNeely et al.'s VPS, Barbic and James): points on the
// tool's surface with outward normals, in the tool's own frame and in device metres, each with
// a handle inside the tool. A point of the shell is answered as the product's probe segment,
// handle -> point (hb::Contact), so every route of a scene and exact Embree answer tool points
// unchanged. docs/tools.md.
#include "math/vec3.h"
#include <cstddef>
#include <string>
#include <vector>

namespace hb {

struct TriangleMesh;

enum class ToolKind { point, sphere, capsule, mesh };

/// The shell of a rigid tool, in the tool's frame (origin at the tool's centre, the point about
/// which torque is taken), metres at the device.
struct ToolShape {
  ToolKind kind = ToolKind::point;
  std::vector<Vec3> points;   ///< on the tool's surface, m.
  std::vector<Vec3> normals;  ///< unit, outward.
  /// Per point, the handle of its probe segment, m: inside the tool, so that the segment
  /// handle -> point lies in the tool (the sphere's centre, the capsule's axis, a mesh tool's
  /// point moved inward along its normal by the margin).
  std::vector<Vec3> handles;
  double radius_m = 0.0;      ///< bounding radius about the origin, m.
  double size_m = 0.0;        ///< the tool's own radius (sphere, capsule) or margin (mesh), m.
  std::string spec;           ///< the spec it was made from (ToolSpec::text()).
  /// How far the shell's points fall short of the tool's surface at worst, along any direction
  /// (the support of the true shape minus the points' largest projection), m: the sampling's
  /// sag. 0 for a point tool and a mesh tool (whose shell is its own support).
  double sag_m = 0.0;

  std::size_t size() const noexcept { return points.size(); }
};

/// The tool of today's single-point probe: one point at the origin, its handle `stylus_m`
/// behind it along +z (the tip points along -z). Answers exactly as the probe segment.
ToolShape make_point_tool(double stylus_m);

/// A sphere of radius `radius_m` (a burr), `points` points spread evenly (a Fibonacci
/// lattice), every handle at the centre. Throws hb::InvalidInput when radius_m is not in
/// (0, 1] or points not in [1, 1,000,000].
ToolShape make_sphere_tool(double radius_m, std::size_t points);

/// A capsule along the tool's z axis, `length_m` tip to tip (>= 2 radius_m), radius
/// `radius_m`, `points` points spread evenly by area over the cylinder and its two
/// hemispherical ends; each handle is the nearest point of the axis segment. Throws
/// hb::InvalidInput on sizes out of range.
ToolShape make_capsule_tool(double radius_m, double length_m, std::size_t points);

/// A tool from a closed mesh in millimetres at the device (its origin is the tool's centre
/// unless `centre_on_bounds`: then the centre of its bounding box is), `points` points spread
/// evenly by area, each with its face's outward normal; a handle is its point moved inward by
/// `margin_m` (default, 0: a quarter of the smallest extent of the bounding box), never past
/// half the tool's thickness measured along the normal. Throws hb::InvalidInput when the mesh
/// has no area, or the sizes are out of range.
ToolShape make_mesh_tool(const TriangleMesh& mesh_mm, std::size_t points, double margin_m = 0.0,
                         bool centre_on_bounds = true);

/// The support of the tool's true shape along unit `u` (tool frame): max over the surface of
/// u . x, m. Sphere and capsule analytic; for a point or mesh tool, the points' largest
/// projection.
double tool_support(const ToolShape& tool, const Vec3& u);

/// One line: "sphere, radius 2 mm, 1000 points".
std::string describe_tool(const ToolShape& tool);

} // namespace hb
