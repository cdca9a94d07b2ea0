// Point shells of tools.
//  1. Sphere: a Fibonacci lattice (points at equal area, golden-angle longitudes), every
//     handle the centre.
//  2. Capsule: the points shared between the cylinder and the two hemispheres by area; the
//     cylinder's on a helix of golden-angle steps, each hemisphere's a half Fibonacci lattice;
//     a handle is the nearest point of the axis segment (the segment handle -> point is then
//     normal to the surface and a radius long).
//  3. Mesh: area-weighted candidates (8 a point, a fixed seed), thinned to one a cell of a
//     grid whose cell is sized so that about `points` cells are occupied (the candidate nearest
//     the cell's centre), then cut or topped up to exactly `points`; each handle is moved
//     inward along the normal by the margin, no farther than half the thickness a ray from the
//     point finds inside the tool.
#include "tool/tool_shape.h"
#include "errors.h"
#include "exact/embree_scene.h"
#include "math/constants.h"
#include "mesh/surface_sampler.h"
#include "mesh/triangle_mesh.h"
#include "spec_parse.h"
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <unordered_map>

namespace hb {
namespace {

constexpr double kGoldenAngle = 2.39996322972865332;  // pi (3 - sqrt 5)
constexpr std::size_t kMaxPoints = 1000000;

void check_points(std::size_t points, const char* what) {
  if (points < 1 || points > kMaxPoints)
    throw InvalidInput(std::string(what) + ": points " + std::to_string(points) + " is not in [1, 1000000]");
}

void check_size(double metres, const char* what, const char* name) {
  if (!(metres > 0.0 && metres <= 1.0))
    throw InvalidInput(std::string(what) + ": " + name + " " + spec_format(metres * 1e3) +
                       " mm is not in (0, 1000] mm");
}

// Unit direction k of n on a Fibonacci lattice over the sphere (z from 1 to -1) or, with
// `half`, over the hemisphere z >= 0.
Vec3 fibonacci_direction(std::size_t k, std::size_t n, bool half) {
  const double f = (double(k) + 0.5) / double(n);
  const double z = half ? 1.0 - f : 1.0 - 2.0 * f;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = kGoldenAngle * double(k);
  return Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
}

double bounding_radius(const std::vector<Vec3>& points) {
  double r = 0.0;
  for (const Vec3& p : points) r = std::max(r, double(p.norm()));
  return r;
}

// The sag (ToolShape::sag_m): the largest shortfall of the points' projection against the
// true support, over directions spread evenly (fewer for large shells), a quarter added for
// the directions between them.
double shell_sag(const ToolShape& t) {
  const std::size_t directions = std::max<std::size_t>(64, std::min<std::size_t>(2000, 20000000 / std::max<std::size_t>(1, t.size())));
  double sag = 0.0;
  for (std::size_t k = 0; k < directions; ++k) {
    const Vec3 u = fibonacci_direction(k, directions, false);
    // A direction between the lattice's own: turn it by a fixed irrational angle.
    const Vec3 v = Eigen::AngleAxisf(0.7f, Vec3(0.3f, 0.5f, 0.8f).normalized()) * u;
    float best = -1e30f;
    for (const Vec3& p : t.points) best = std::max(best, v.dot(p));
    sag = std::max(sag, tool_support(t, v) - double(best));
  }
  return 1.25 * sag;
}

} // namespace

double tool_support(const ToolShape& tool, const Vec3& u) {
  switch (tool.kind) {
  case ToolKind::sphere: return tool.size_m;
  case ToolKind::capsule: return tool.size_m + (tool.radius_m - tool.size_m) * std::fabs(double(u.z()));
  default: break;
  }
  double best = -1e30;
  for (const Vec3& p : tool.points) best = std::max(best, double(u.dot(p)));
  return best;
}

ToolShape make_point_tool(double stylus_m) {
  check_size(stylus_m, "point tool", "stylus");
  ToolShape t;
  t.kind = ToolKind::point;
  t.points = {Vec3::Zero()};
  t.normals = {Vec3(0.f, 0.f, -1.f)};
  t.handles = {Vec3(0.f, 0.f, float(stylus_m))};
  t.radius_m = 0.0;
  t.size_m = stylus_m;
  t.spec = "point";
  return t;
}

ToolShape make_sphere_tool(double radius_m, std::size_t points) {
  check_size(radius_m, "sphere tool", "radius");
  check_points(points, "sphere tool");
  ToolShape t;
  t.kind = ToolKind::sphere;
  t.points.reserve(points);
  for (std::size_t k = 0; k < points; ++k) {
    const Vec3 d = fibonacci_direction(k, points, false);
    t.normals.push_back(d);
    t.points.push_back(d * float(radius_m));
    t.handles.push_back(Vec3::Zero());
  }
  t.radius_m = radius_m;
  t.size_m = radius_m;
  t.spec = "sphere,radius-mm=" + spec_format(radius_m * 1e3) + ",points=" + std::to_string(points);
  t.sag_m = shell_sag(t);
  return t;
}

ToolShape make_capsule_tool(double radius_m, double length_m, std::size_t points) {
  check_size(radius_m, "capsule tool", "radius");
  check_size(length_m, "capsule tool", "length");
  check_points(points, "capsule tool");
  if (length_m < 2.0 * radius_m)
    throw InvalidInput("capsule tool: length " + spec_format(length_m * 1e3) + " mm is shorter than its diameter " +
                       spec_format(2e3 * radius_m) + " mm");
  const double half = 0.5 * length_m - radius_m;  // half the cylinder's length
  const double cap_area = 4.0 * kPi * radius_m * radius_m, side_area = 2.0 * kPi * radius_m * (2.0 * half);
  std::size_t side = std::size_t(std::llround(double(points) * side_area / (cap_area + side_area)));
  std::size_t caps = points - side;
  if (caps < 2 && points >= 2) {
    caps = 2;
    side = points - 2;
  }
  const std::size_t top = (caps + 1) / 2, bottom = caps - top;
  ToolShape t;
  t.kind = ToolKind::capsule;
  const auto add = [&](const Vec3& point, const Vec3& normal, float axis_z) {
    t.points.push_back(point);
    t.normals.push_back(normal);
    t.handles.push_back(Vec3(0.f, 0.f, axis_z));
  };
  for (std::size_t k = 0; k < top; ++k) {
    const Vec3 d = fibonacci_direction(k, top, true);
    add(Vec3(0.f, 0.f, float(half)) + d * float(radius_m), d, float(half));
  }
  for (std::size_t k = 0; k < side; ++k) {
    const double z = half - 2.0 * half * (double(k) + 0.5) / double(side);
    const double phi = kGoldenAngle * double(k);
    const Vec3 n(float(std::cos(phi)), float(std::sin(phi)), 0.f);
    add(n * float(radius_m) + Vec3(0.f, 0.f, float(z)), n, float(z));
  }
  for (std::size_t k = 0; k < bottom; ++k) {
    Vec3 d = fibonacci_direction(k, bottom, true);
    d.z() = -d.z();
    add(Vec3(0.f, 0.f, float(-half)) + d * float(radius_m), d, float(-half));
  }
  t.radius_m = 0.5 * length_m;
  t.size_m = radius_m;
  t.spec = "capsule,radius-mm=" + spec_format(radius_m * 1e3) + ",length-mm=" + spec_format(length_m * 1e3) +
           ",points=" + std::to_string(points);
  t.sag_m = shell_sag(t);
  return t;
}

ToolShape make_mesh_tool(const TriangleMesh& mesh_mm, std::size_t points, double margin_m, bool centre_on_bounds) {
  check_points(points, "mesh tool");
  if (margin_m < 0.0 || !std::isfinite(margin_m)) throw InvalidInput("mesh tool: margin must be >= 0 mm");
  const SurfaceSampler sampler(mesh_mm, "mesh tool");
  const Bounds bounds = mesh_mm.bounds();
  const Vec3 centre = centre_on_bounds ? Vec3(0.5f * (bounds.min + bounds.max)) : Vec3::Zero();
  const Vec3 extent = bounds.max - bounds.min;
  if (!(extent.maxCoeff() * 1e-3 <= 1.0)) throw InvalidInput("mesh tool: the tool is larger than 1 m");

  // 1. Candidates.
  std::mt19937_64 rng(0x7001);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::size_t candidates = std::min<std::size_t>(8 * points, 4 * kMaxPoints);
  std::vector<Vec3> cand_p(candidates), cand_n(candidates);
  for (std::size_t i = 0; i < candidates; ++i) {
    const double r = uniform(rng), u = uniform(rng), v = uniform(rng);
    sampler.sample(r, u, v, cand_p[i], cand_n[i]);
  }
  // 2. One candidate a cell: bisect the cell size until about `points` cells are occupied.
  const auto thin = [&](double cell, std::vector<std::size_t>& kept) {
    std::unordered_map<std::uint64_t, std::pair<std::size_t, float>> best;
    best.reserve(points * 2);
    for (std::size_t i = 0; i < candidates; ++i) {
      const Vec3 f = (cand_p[i] - bounds.min) / float(cell);
      const std::uint64_t x = std::uint64_t(f.x()), y = std::uint64_t(f.y()), z = std::uint64_t(f.z());
      const std::uint64_t key = (x << 42) ^ (y << 21) ^ z;
      const Vec3 mid((float(x) + 0.5f) * float(cell), (float(y) + 0.5f) * float(cell), (float(z) + 0.5f) * float(cell));
      const float d = (cand_p[i] - bounds.min - mid).squaredNorm();
      auto it = best.find(key);
      if (it == best.end()) best.emplace(key, std::make_pair(i, d));
      else if (d < it->second.second) it->second = {i, d};
    }
    kept.clear();
    for (const auto& kv : best) kept.push_back(kv.second.first);
    std::sort(kept.begin(), kept.end());
  };
  std::vector<std::size_t> kept;
  double lo = 1e-9, hi = std::max(double(extent.maxCoeff()), 1e-6);
  for (int it = 0; it < 40; ++it) {
    const double mid = std::sqrt(lo * hi);
    thin(mid, kept);
    if (kept.size() > points) lo = mid;
    else hi = mid;
  }
  thin(lo, kept);  // at least `points` occupied cells (or every candidate)
  // 3. Exactly `points`: an even stride through the kept ones, then candidates not yet taken.
  std::vector<std::size_t> chosen;
  if (kept.size() >= points) {
    for (std::size_t k = 0; k < points; ++k) chosen.push_back(kept[k * kept.size() / points]);
  } else {
    chosen = kept;
    for (std::size_t i = 0; chosen.size() < points && i < candidates; ++i)
      if (!std::binary_search(kept.begin(), kept.end(), i)) chosen.push_back(i);
  }
  // 4. Handles: inward by the margin, at most half the thickness along -n.
  TriangleMesh tool = mesh_mm;
  if (tool.normals.size() != tool.positions.size()) tool.compute_vertex_normals();
  const EmbreeScene inside(tool);
  const double margin_mm = margin_m > 0.0 ? margin_m * 1e3 : 0.25 * double(extent.minCoeff());
  if (!(margin_mm > 0.0)) throw InvalidInput("mesh tool: the tool is flat (no thickness for its handles)");
  ToolShape t;
  t.kind = ToolKind::mesh;
  for (std::size_t i : chosen) {
    const Vec3 p = cand_p[i], n = cand_n[i];
    const float offset = 1e-4f * float(extent.maxCoeff());
    const RayHit hit = inside.intersect(p - offset * n, -n, 0.f, float(4.0 * margin_mm));
    const double thickness = hit.hit ? double(hit.t + offset) : 4.0 * margin_mm;
    const double m = std::min(margin_mm, 0.5 * thickness);
    t.points.push_back((p - centre) * 1e-3f);
    t.normals.push_back(n);
    t.handles.push_back((p - float(m) * n - centre) * 1e-3f);
  }
  t.radius_m = bounding_radius(t.points);
  t.size_m = margin_mm * 1e-3;
  std::ostringstream spec;
  spec << "mesh,points=" << points;
  t.spec = spec.str();
  return t;
}

std::string describe_tool(const ToolShape& tool) {
  std::ostringstream os;
  switch (tool.kind) {
  case ToolKind::point: os << "point (stylus " << spec_format(tool.size_m * 1e3) << " mm)"; break;
  case ToolKind::sphere: os << "sphere, radius " << spec_format(tool.size_m * 1e3) << " mm"; break;
  case ToolKind::capsule:
    os << "capsule, radius " << spec_format(tool.size_m * 1e3) << " mm, length " << spec_format(tool.radius_m * 2e3)
       << " mm";
    break;
  case ToolKind::mesh:
    os << "mesh tool, " << spec_format(tool.radius_m * 1e3) << " mm bounding radius, margin "
       << spec_format(tool.size_m * 1e3) << " mm";
    break;
  }
  os << ", " << tool.size() << (tool.size() == 1 ? " point" : " points");
  return os.str();
}

} // namespace hb
