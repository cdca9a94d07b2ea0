// Procedural meshes. All are closed, watertight and oriented outward (counter-clockwise seen
// from outside); vertex normals are set (analytic where the shape has a simple one).
//  1. Icosphere: the regular icosahedron, midpoint-subdivided level by level with the new
//     vertices pushed back onto the unit sphere; ellipsoid and bumpy sphere deform it radially
//     or axis-wise.
//  2. Bumpy sphere: r(d) = R (1 + a b(d)) on unit directions d, with b the normalised sum of
//     three smooth degree-f harmonics Re((x+iy)^f), Re((y+iz)^f), Re((z+ix)^f) (polynomials in
//     d, hence smooth everywhere, also at the poles); small a keeps it star-shaped and
//     quasi-convex.
//  3. Cube: six (n x n) grids whose shared border vertices are welded through integer lattice
//     coordinates.
//  4. Torus: a (major x minor) periodic grid.
//  5. Chess piece: a profile curve r(z) (base, moulding, body bulge, collar, neck, ball head)
//     resampled uniformly in arc length and revolved about +Z; a flat cap closes the bottom
//     and the top ends on the axis at a pole vertex.
#include "mesh/generators.h"
#include "math/constants.h"

#include "errors.h"
#include "mesh/subdivision.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <unordered_map>

namespace hb {
namespace {


void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidInput(what);
}

/// Regular icosahedron inscribed in the unit sphere, faces counter-clockwise from outside.
TriangleMesh icosahedron() {
  const float t = (1.f + std::sqrt(5.f)) / 2.f;
  TriangleMesh m;
  m.positions = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : m.positions) p.normalize();
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  return m;
}

/// Unit icosphere; normals equal positions.
TriangleMesh unit_icosphere(int subdivisions) {
  require(subdivisions >= 0 && subdivisions <= 12,
          "icosphere: subdivisions must be in [0, 12], got " + std::to_string(subdivisions));
  TriangleMesh m = icosahedron();
  for (int s = 0; s < subdivisions; ++s) {
    m.normals.clear();  // flat midpoints, projected below
    m = subdivide_midpoint(m, 1);
    for (Vec3& p : m.positions) p.normalize();
  }
  m.normals = m.positions;
  return m;
}

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.f, 1.f);
  return t * t * (3.f - 2.f * t);
}

float bump(float z, float centre, float width) {
  const float u = (z - centre) / width;
  return std::exp(-u * u);
}

/// Chess piece profile for a unit-ish piece: radius at height z in [0, kChessTop].
constexpr float kChessHeadCentre = 0.84f;
constexpr float kChessHeadRadius = 0.13f;
constexpr float kChessTop = kChessHeadCentre + kChessHeadRadius;

float chess_radius(float z) {
  // Shaft that narrows towards the neck, with rings and bulges on it.
  const float shaft = 0.10f - 0.04f * smoothstep(0.45f, 0.70f, z);
  float body = shaft + 0.20f * bump(z, 0.00f, 0.07f)  // wide foot
               + 0.06f * bump(z, 0.12f, 0.025f)        // base moulding ring
               + 0.07f * bump(z, 0.38f, 0.12f)         // body bulge
               + 0.10f * bump(z, 0.64f, 0.018f);       // collar
  body *= 1.f - smoothstep(0.80f, 0.90f, z);           // hidden inside the head by then
  const float dz = z - kChessHeadCentre;
  const float head = std::sqrt(std::max(0.f, kChessHeadRadius * kChessHeadRadius - dz * dz));
  return std::max(body, head);
}

} // namespace

TriangleMesh make_sphere(float radius, int subdivisions) {
  require(radius > 0.f && std::isfinite(radius), "make_sphere: radius must be > 0");
  TriangleMesh m = unit_icosphere(subdivisions);
  for (Vec3& p : m.positions) p *= radius;
  return m;
}

TriangleMesh make_ellipsoid(const Vec3& radii, int subdivisions) {
  require(radii.allFinite() && radii.minCoeff() > 0.f, "make_ellipsoid: radii must be > 0");
  TriangleMesh m = unit_icosphere(subdivisions);
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    // Gradient of the implicit function: the exact ellipsoid normal.
    m.normals[i] = m.positions[i].cwiseQuotient(radii).normalized();
    m.positions[i] = m.positions[i].cwiseProduct(radii);
  }
  return m;
}

TriangleMesh make_bumpy_sphere(const BumpySphereOptions& o) {
  require(o.radius > 0.f && std::isfinite(o.radius), "make_bumpy_sphere: radius must be > 0");
  require(o.bump_amplitude >= 0.f && o.bump_amplitude <= 0.3f, "make_bumpy_sphere: bump_amplitude must be in [0, 0.3]");
  require(o.bump_frequency >= 1, "make_bumpy_sphere: bump_frequency must be >= 1");
  TriangleMesh m = unit_icosphere(o.subdivisions);

  const auto harmonic = [f = o.bump_frequency](double a, double b) {
    return std::real(std::pow(std::complex<double>(a, b), f));
  };
  std::vector<double> field(m.positions.size());
  double peak = 0.0;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Eigen::Vector3d d = m.positions[i].cast<double>();
    field[i] = harmonic(d.x(), d.y()) + harmonic(d.y(), d.z()) + harmonic(d.z(), d.x());
    peak = std::max(peak, std::abs(field[i]));
  }
  const double scale = peak > 0.0 ? double(o.bump_amplitude) / peak : 0.0;
  for (std::size_t i = 0; i < m.positions.size(); ++i)
    m.positions[i] *= float(double(o.radius) * (1.0 + scale * field[i]));
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_cube(const Vec3& half, int divisions) {
  require(half.allFinite() && half.minCoeff() > 0.f, "make_cube: half extents must be > 0");
  require(divisions >= 1 && divisions <= 4096, "make_cube: divisions must be in [1, 4096]");
  const int n = divisions;
  TriangleMesh m;
  std::unordered_map<std::uint64_t, std::uint32_t> lattice;  // welds shared border vertices
  const auto vertex = [&](int i, int j, int k) {
    const std::uint64_t key = (std::uint64_t(i) * (n + 1) + std::uint64_t(j)) * (n + 1) + std::uint64_t(k);
    auto [it, inserted] = lattice.emplace(key, std::uint32_t(m.positions.size()));
    if (inserted)
      m.positions.emplace_back(half.x() * (2.f * i / n - 1.f), half.y() * (2.f * j / n - 1.f),
                               half.z() * (2.f * k / n - 1.f));
    return it->second;
  };
  // For each face: the fixed axis and its side, and tangent axes u, v with u x v = outward.
  struct Face { int axis, side, u, v; };
  const Face faces[6] = {{0, 1, 1, 2}, {0, 0, 2, 1}, {1, 1, 2, 0}, {1, 0, 0, 2}, {2, 1, 0, 1}, {2, 0, 1, 0}};
  for (const Face& f : faces) {
    const auto at = [&](int a, int b) {
      int c[3];
      c[f.axis] = f.side * n;
      c[f.u] = a;
      c[f.v] = b;
      return vertex(c[0], c[1], c[2]);
    };
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const std::uint32_t p00 = at(a, b), p10 = at(a + 1, b), p11 = at(a + 1, b + 1), p01 = at(a, b + 1);
        m.triangles.push_back({p00, p10, p11});
        m.triangles.push_back({p00, p11, p01});
      }
  }
  m.compute_vertex_normals();
  return m;
}

TriangleMesh make_torus(float major_radius, float minor_radius, int major_segments, int minor_segments) {
  require(minor_radius > 0.f && major_radius > minor_radius, "make_torus: need major_radius > minor_radius > 0");
  require(major_segments >= 3 && minor_segments >= 3, "make_torus: segments must be >= 3");
  TriangleMesh m;
  const int M = major_segments, N = minor_segments;
  for (int i = 0; i < M; ++i) {
    const double u = 2.0 * kPi * i / M;
    for (int j = 0; j < N; ++j) {
      const double v = 2.0 * kPi * j / N;
      const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
      const Eigen::Vector3d c(major_radius * std::cos(u), major_radius * std::sin(u), 0.0);
      m.positions.push_back((c + double(minor_radius) * n).cast<float>());
      m.normals.push_back(n.cast<float>());
    }
  }
  const auto id = [&](int i, int j) { return std::uint32_t((i % M) * N + (j % N)); };
  // d/du x d/dv points outward, so (i,j) -> (i+1,j) -> (i+1,j+1) is counter-clockwise.
  for (int i = 0; i < M; ++i)
    for (int j = 0; j < N; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

TriangleMesh make_chess_piece(const ChessPieceOptions& o) {
  require(o.height > 0.f && std::isfinite(o.height), "make_chess_piece: height must be > 0");
  require(o.profile_samples >= 8, "make_chess_piece: profile_samples must be >= 8");
  require(o.segments >= 8, "make_chess_piece: segments must be >= 8");

  // Dense polyline of the profile, then uniform resampling in arc length so the steep parts
  // (the foot's edge, the collar, the head) get as many rings as their length needs.
  const int dense = 64 * o.profile_samples;
  std::vector<Eigen::Vector2f> poly(dense + 1);  // (r, z)
  std::vector<double> arc(dense + 1, 0.0);
  for (int i = 0; i <= dense; ++i) {
    const float z = kChessTop * float(i) / float(dense);
    poly[i] = Eigen::Vector2f(i == dense ? 0.f : chess_radius(z), z);
    if (i > 0) arc[i] = arc[i - 1] + double((poly[i] - poly[i - 1]).norm());
  }
  const int P = o.profile_samples;  // rings 0..P-2, pole P-1
  std::vector<Eigen::Vector2f> profile(P);
  for (int k = 0, seg = 0; k < P; ++k) {
    const double s = arc.back() * k / (P - 1);
    while (seg < dense - 1 && arc[seg + 1] < s) ++seg;
    const double t = std::clamp((s - arc[seg]) / std::max(1e-12, arc[seg + 1] - arc[seg]), 0.0, 1.0);
    profile[k] = poly[seg] + float(t) * (poly[seg + 1] - poly[seg]);
  }
  profile.front() = poly.front();
  profile.back() = poly.back();
  const float scale = o.height / kChessTop;

  TriangleMesh m;
  const int S = o.segments;
  const int rings = P - 1;
  m.positions.reserve(std::size_t(rings) * S + 2);
  for (int k = 0; k < rings; ++k)
    for (int j = 0; j < S; ++j) {
      const double phi = 2.0 * kPi * j / S;
      m.positions.emplace_back(scale * profile[k].x() * float(std::cos(phi)),
                               scale * profile[k].x() * float(std::sin(phi)), scale * profile[k].y());
    }
  const auto top = std::uint32_t(m.positions.size());
  m.positions.emplace_back(0.f, 0.f, scale * profile.back().y());
  const auto bottom = std::uint32_t(m.positions.size());
  m.positions.emplace_back(0.f, 0.f, 0.f);

  const auto id = [&](int k, int j) { return std::uint32_t(k * S + (j % S)); };
  m.triangles.reserve(std::size_t(2 * rings) * S);
  // Side bands: d/dphi x d/dprofile points outward, so (k,j) -> (k,j+1) -> (k+1,j+1).
  for (int k = 0; k + 1 < rings; ++k)
    for (int j = 0; j < S; ++j) {
      m.triangles.push_back({id(k, j), id(k, j + 1), id(k + 1, j + 1)});
      m.triangles.push_back({id(k, j), id(k + 1, j + 1), id(k + 1, j)});
    }
  for (int j = 0; j < S; ++j) {
    m.triangles.push_back({id(rings - 1, j), id(rings - 1, j + 1), top});  // head, ends on the axis
    m.triangles.push_back({bottom, id(0, j + 1), id(0, j)});               // flat foot, facing -Z
  }
  m.compute_vertex_normals();
  return m;
}

} // namespace hb
