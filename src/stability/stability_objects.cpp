// The stability suite's generated objects (stability_suite.h, stability_harness.h): flat
// shaded prisms in mm (a wall, plates, V-grooves), built from quads of their own vertices.
#include "stability/stability_harness.h"
#include "errors.h"
#include "math/constants.h"
#include <algorithm>
#include <cmath>

namespace hb {
namespace {

// Adds a grid of `div` x `div` quads over the planar quad a, b, c, d (in order around it)
// with its own vertices and `normal` (flat shading); winding made outward.
void add_quad(TriangleMesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& normal,
              int div) {
  const std::uint32_t base = std::uint32_t(m.positions.size());
  for (int i = 0; i <= div; ++i)
    for (int j = 0; j <= div; ++j) {
      const float u = float(i) / div, v = float(j) / div;
      m.positions.push_back((1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d);
      m.normals.push_back(normal);
    }
  const bool flip = (b - a).cross(d - a).dot(normal) < 0;
  const auto id = [&](int i, int j) { return base + std::uint32_t(i * (div + 1) + j); };
  for (int i = 0; i < div; ++i)
    for (int j = 0; j < div; ++j) {
      Triangle t1{id(i, j), id(i + 1, j), id(i + 1, j + 1)}, t2{id(i, j), id(i + 1, j + 1), id(i, j + 1)};
      if (flip) std::swap(t1[1], t1[2]), std::swap(t2[1], t2[2]);
      m.triangles.push_back(t1);
      m.triangles.push_back(t2);
    }
}

} // namespace

namespace stability {

// A prism: the polygon (x, z) (star-shaped from its first vertex) extruded over y in
// [-half_y, half_y], flat shaded.
TriangleMesh extrude(std::vector<Eigen::Vector2f> poly, float half_y, int div) {
  double area = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % poly.size()];
    area += double(p.x()) * q.y() - double(q.x()) * p.y();
  }
  if (area < 0) std::reverse(poly.begin() + 1, poly.end());
  TriangleMesh m;
  const auto at = [&](const Eigen::Vector2f& p, float y) { return Vec3(p.x(), y, p.y()); };
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& p = poly[i];
    const auto& q = poly[(i + 1) % poly.size()];
    const Eigen::Vector2f e = q - p;
    const Vec3 normal = Vec3(e.y(), 0, -e.x()).normalized();
    add_quad(m, at(p, -half_y), at(q, -half_y), at(q, half_y), at(p, half_y), normal, div);
  }
  for (float side : {-1.f, 1.f}) {
    const Vec3 normal(0, side, 0);
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
      const std::uint32_t base = std::uint32_t(m.positions.size());
      for (const auto* p : {&poly[0], &poly[i], &poly[i + 1]}) {
        m.positions.push_back(at(*p, side * half_y));
        m.normals.push_back(normal);
      }
      Triangle t{base, base + 1, base + 2};
      if ((m.positions[base + 1] - m.positions[base]).cross(m.positions[base + 2] - m.positions[base]).dot(normal) < 0)
        std::swap(t[1], t[2]);
      m.triangles.push_back(t);
    }
  }
  return m;
}

} // namespace stability

using stability::extrude;

TriangleMesh make_plate(float thickness_mm) {
  if (!(thickness_mm > 0)) throw InvalidInput("make_plate: thickness must be > 0");
  const float h = 0.5f * thickness_mm;
  return extrude({{-15, -h}, {15, -h}, {15, h}, {-15, h}}, 15.f, 8);
}

TriangleMesh make_v_groove(float degrees, bool welded, int divisions) {
  if (!(degrees > 10 && degrees < 170)) throw InvalidInput("make_v_groove: angle must be in (10, 170) degrees");
  const float a = float(degrees * kPi / 360.0), wall = 15.f;
  const float s = std::sin(a), c = std::cos(a);
  const float top = wall * c, x = wall * s + 5.f;
  TriangleMesh m = extrude({{0, 0}, {wall * s, top}, {x, top}, {x, -10}, {-x, -10}, {-x, top}, {-wall * s, top}},
                           15.f, divisions);
  if (welded) {
    // The two walls' vertices on the crease (x = 0, z = 0) share the averaged normal.
    const Vec3 n = Vec3(0, 0, 1);
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      const Vec3& p = m.positions[i];
      if (std::fabs(p.x()) < 1e-5f && std::fabs(p.z()) < 1e-5f && std::fabs(m.normals[i].y()) < 0.5f) m.normals[i] = n;
    }
  }
  return m;
}

} // namespace hb
