#pragma once
// Points spread over a mesh's surface in proportion to area (a tool's shell, the slides' start
// points): a triangle by its share of the area, a point in it uniformly.
#include "errors.h"
#include "mesh/triangle_mesh.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace hb {

class SurfaceSampler {
public:
  /// Throws hb::InvalidInput, naming `what`, when the mesh has no surface area.
  SurfaceSampler(const TriangleMesh& mesh, const std::string& what) : mesh_(mesh) {
    cumulative_.reserve(mesh.triangle_count());
    for (const Triangle& t : mesh.triangles) {
      const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
      const double area = 0.5 * double((b - a).cross(c - a).norm());
      total_ += std::isfinite(area) ? area : 0.0;
      cumulative_.push_back(total_);
    }
    if (!(total_ > 0.0)) throw InvalidInput(what + ": the mesh has no surface area");
  }
  /// The point of uniform numbers r, u, v in [0, 1) (r picks the triangle), its triangle's unit
  /// geometric normal (+z for a degenerate one) and id.
  std::uint32_t sample(double r, double u, double v, Vec3& point, Vec3& normal) const {
    const std::size_t k = std::min(cumulative_.size() - 1,
                                   std::size_t(std::lower_bound(cumulative_.begin(), cumulative_.end(), r * total_) -
                                               cumulative_.begin()));
    const Triangle& tri = mesh_.triangles[k];
    const Vec3 &a = mesh_.positions[tri[0]], &b = mesh_.positions[tri[1]], &c = mesh_.positions[tri[2]];
    if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
    point = a + float(u) * (b - a) + float(v) * (c - a);
    const Vec3 g = (b - a).cross(c - a);
    normal = g.norm() > 0.f ? Vec3(g.normalized()) : Vec3::UnitZ();
    return std::uint32_t(k);
  }

private:
  const TriangleMesh& mesh_;
  std::vector<double> cumulative_;
  double total_ = 0.0;
};

} // namespace hb
