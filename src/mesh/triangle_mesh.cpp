#include "mesh/triangle_mesh.h"
#include <cmath>

namespace hb {

Bounds TriangleMesh::bounds() const {
  Bounds b;
  if (positions.empty()) return b;
  b.min = b.max = positions.front();
  for (const Vec3& p : positions) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

void TriangleMesh::compute_vertex_normals() {
  normals.assign(positions.size(), Vec3::Zero());
  for (const Triangle& t : triangles) {
    const Vec3& a = positions[t[0]];
    const Vec3& b = positions[t[1]];
    const Vec3& c = positions[t[2]];
    const Vec3 n = (b - a).cross(c - a);  // length = twice the area: area weighting
    for (auto v : t) normals[v] += n;
  }
  for (Vec3& n : normals) {
    const float len = n.norm();
    if (len > 1e-18f && len < 1e18f) {
      n /= len;
      continue;
    }
    // Tiny (squares underflow: a denormal length, a normal far from unit) or huge
    // (squares overflow): scale by the largest component first (found by fuzzing).
    const float largest = n.cwiseAbs().maxCoeff();
    if (!(largest > 0.f) || !std::isfinite(largest)) {
      n = Vec3(0.f, 0.f, 1.f);
      continue;
    }
    n /= largest;
    n /= n.norm();
  }
}

double TriangleMesh::area() const {
  double sum = 0.0;
  for (const Triangle& t : triangles) {
    const Vec3& a = positions[t[0]];
    sum += 0.5 * double((positions[t[1]] - a).cross(positions[t[2]] - a).norm());
  }
  return sum;
}

TriangleMesh select_triangles(const TriangleMesh& mesh, const std::vector<std::uint32_t>& keep) {
  TriangleMesh out;
  out.positions = mesh.positions;
  out.normals = mesh.normals;
  out.triangles.reserve(keep.size());
  for (auto id : keep) out.triangles.push_back(mesh.triangles.at(id));
  return out;
}

} // namespace hb
