// The signed distance field peer (sdf_peer.h).
//  1. Check the mesh and the options; copy the mesh into OpenVDB's arrays.
//  2. The voxel: given, or sized to the memory target. A narrow band's memory is its leaf
//     nodes (8^3 voxels each), about c A / v^2 for surface area A and voxel v once the voxel
//     is small against the shape: estimate v from A with a measured c, build, measure
//     memUsage, correct v by the measured exponent (-2 first, then the secant through the
//     last two builds), at most three builds, keep the closest.
//  3. A query reads the grid through a per-call accessor (not registered with the tree: the
//     grid is never written after the build): the trilinear field at the tip, then at the
//     handle, then the gradient at the tip from 32 voxels around it (the voxels' central
//     differences, interpolated trilinearly with the value's own weights, so the normal is
//     continuous across voxels).
#include "peers/sdf_peer.h"
#include "errors.h"
#include "stopwatch.h"
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

namespace hb {

struct SdfPeer::Grid {
  openvdb::FloatGrid::Ptr grid;
  float background = 0.f;  // the clamped field beyond the band, model units
};

namespace {

using Accessor = openvdb::FloatGrid::ConstUnsafeAccessor;

/// Bytes of a narrow band of half width `band` voxels per unit of area at voxel 1, measured
/// on spheres and the armadillo (leaf nodes of 2 KB over roughly 1 + 2 band / 8 layers of
/// 8-voxel leaves). Only the first guess of the search depends on it.
double bytes_per_area(int band) { return 2200.0 / 64.0 * (1.0 + 2.0 * band / 8.0) * 1.25; }

/// Largest grid the options may ask for (an explicit voxel far too small for the mesh).
constexpr double kMaxEstimatedBytes = 64.0 * 1024 * 1024 * 1024;
/// Index coordinates stay well inside OpenVDB's int32 Coord.
constexpr float kMaxIndex = 1 << 29;

struct MeshArrays {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  double area = 0;
  double diagonal = 0;
};

MeshArrays mesh_arrays(const TriangleMesh& mesh) {
  if (mesh.triangles.empty())
    throw InvalidInput("SdfPeer: the mesh has no triangles (" + std::to_string(mesh.vertex_count()) +
                       " vertices): a distance field needs a closed surface");
  MeshArrays a;
  a.points.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3& p = mesh.positions[i];
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InvalidInput("SdfPeer: vertex " + std::to_string(i) + " is not finite or beyond 1e15: (" +
                         std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")");
    a.points.emplace_back(p.x(), p.y(), p.z());
  }
  a.triangles.reserve(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    for (std::uint32_t v : t)
      if (v >= mesh.positions.size())
        throw InvalidInput("SdfPeer: triangle " + std::to_string(i) + " refers to vertex " + std::to_string(v) +
                           " of " + std::to_string(mesh.positions.size()));
    a.triangles.emplace_back(t[0], t[1], t[2]);
  }
  a.area = mesh.area();
  a.diagonal = mesh.bounds().diagonal();
  return a;
}

void check_options(const SdfPeerOptions& o, const MeshArrays& mesh) {
  if (!std::isfinite(o.voxel) || o.voxel < 0)
    throw InvalidInput("SdfPeer: voxel " + std::to_string(o.voxel) + " is negative or not finite");
  if (o.voxel == 0 && o.memory_bytes == 0)
    throw InvalidInput("SdfPeer: neither a voxel nor memory_bytes given: one of them sizes the field");
  if (o.band_voxels < 1 || o.band_voxels > 64)
    throw InvalidInput("SdfPeer: band_voxels " + std::to_string(o.band_voxels) + " outside [1, 64]");
  if (!(mesh.area > 0) || !(mesh.diagonal > 0))
    throw InvalidInput("SdfPeer: the mesh has no area (all its triangles degenerate)");
  if (o.voxel > 0) {
    const double estimate = bytes_per_area(o.band_voxels) * mesh.area / (o.voxel * o.voxel);
    if (estimate > kMaxEstimatedBytes || mesh.diagonal / o.voxel > kMaxIndex)
      throw InvalidInput("SdfPeer: voxel " + std::to_string(o.voxel) + " is too small for a mesh of area " +
                         std::to_string(mesh.area) + ": the grid would take about " +
                         std::to_string(estimate / (1024.0 * 1024 * 1024)) + " GiB");
  }
}

openvdb::FloatGrid::Ptr build_grid(const MeshArrays& mesh, double voxel, int band) {
  const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(voxel);
  try {
    return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, mesh.points, mesh.triangles, float(band));
  } catch (const std::exception& e) {
    throw LibraryError(std::string("SdfPeer: OpenVDB's meshToLevelSet failed at voxel ") + std::to_string(voxel) +
                       ": " + e.what());
  }
}

double log_error(std::size_t bytes, std::size_t target) { return std::abs(std::log(double(bytes) / double(target))); }

/// The voxel search of step 2: the grid closest to `target` bytes in at most three builds.
openvdb::FloatGrid::Ptr build_at_memory(const MeshArrays& mesh, std::size_t target, int band, double& voxel,
                                        int& builds) {
  constexpr double kTolerance = 0.1;
  const double largest = mesh.diagonal / 8;  // coarser than this the field is no longer the shape
  const double smallest = std::max(mesh.diagonal / kMaxIndex, std::sqrt(bytes_per_area(band) * mesh.area / kMaxEstimatedBytes));
  auto clamp_voxel = [&](double v) { return std::min(largest, std::max(smallest, v)); };
  double v = clamp_voxel(std::sqrt(bytes_per_area(band) * mesh.area / double(target)));
  openvdb::FloatGrid::Ptr best;
  double best_voxel = v, previous_voxel = 0, previous_bytes = 0;
  std::size_t best_bytes = 0;
  for (builds = 1; builds <= 3; ++builds) {
    openvdb::FloatGrid::Ptr grid = build_grid(mesh, v, band);
    const std::size_t bytes = grid->memUsage();
    if (!best || log_error(bytes, target) < log_error(best_bytes, target)) {
      best = std::move(grid);
      best_voxel = v;
      best_bytes = bytes;
    }
    if (std::abs(double(bytes) / double(target) - 1) <= kTolerance || builds == 3) break;
    // Memory ~ v^e: e = -2 for a surface, else measured through the last two builds.
    double exponent = -2;
    if (previous_voxel > 0 && std::abs(std::log(v / previous_voxel)) > 1e-3)
      exponent = std::clamp(std::log(double(bytes) / previous_bytes) / std::log(v / previous_voxel), -3.0, -1.0);
    previous_voxel = v;
    previous_bytes = double(bytes);
    const double next = clamp_voxel(v * std::pow(double(target) / double(bytes), 1.0 / exponent));
    if (std::abs(next / v - 1) < 1e-3) break;  // clamped: another build gives the same grid
    v = next;
  }
  builds = std::min(builds, 3);
  voxel = best_voxel;
  return best;
}

/// The field around one index-space point: the trilinear weights and the 2 x 2 x 2 voxels of
/// its cell.
struct Cell {
  openvdb::Coord origin;  // the cell's lowest voxel
  float fx = 0, fy = 0, fz = 0;
  float v[2][2][2];  // [x][y][z] offsets from origin
};

/// False when `q` (index space) is not finite or beyond the grid's coordinates.
bool cell_at(const Accessor& acc, const Vec3& q, Cell& c) noexcept {
  if (!q.allFinite() || q.cwiseAbs().maxCoeff() > kMaxIndex) return false;
  const float x0 = std::floor(q.x()), y0 = std::floor(q.y()), z0 = std::floor(q.z());
  c.origin = openvdb::Coord(int(x0), int(y0), int(z0));
  c.fx = q.x() - x0;
  c.fy = q.y() - y0;
  c.fz = q.z() - z0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c.v[a][b][d] = acc.getValue(c.origin.offsetBy(a, b, d));
  return true;
}

/// Trilinear interpolation of corner values u[x][y][z] with the cell's weights.
float trilinear(const Cell& c, const float (&u)[2][2][2]) noexcept {
  float yz[2];
  for (int a = 0; a < 2; ++a) {
    const float z0 = u[a][0][0] + c.fz * (u[a][0][1] - u[a][0][0]);
    const float z1 = u[a][1][0] + c.fz * (u[a][1][1] - u[a][1][0]);
    yz[a] = z0 + c.fy * (z1 - z0);
  }
  return yz[0] + c.fx * (yz[1] - yz[0]);
}

/// The gradient at the cell's point (index units): each corner's central difference, the
/// neighbours one voxel outside the cell read on demand, interpolated trilinearly.
Vec3 gradient(const Accessor& acc, const Cell& c) noexcept {
  float gx[2][2][2], gy[2][2][2], gz[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) {
        // Along each axis, the corner's neighbour inside the cell is known; the other lies
        // one voxel outside it (offset -1 for the low corner, +2 for the high one).
        const float outside_x = acc.getValue(c.origin.offsetBy(a == 0 ? -1 : 2, b, d));
        const float outside_y = acc.getValue(c.origin.offsetBy(a, b == 0 ? -1 : 2, d));
        const float outside_z = acc.getValue(c.origin.offsetBy(a, b, d == 0 ? -1 : 2));
        gx[a][b][d] = a == 0 ? c.v[1][b][d] - outside_x : outside_x - c.v[0][b][d];
        gy[a][b][d] = b == 0 ? c.v[a][1][d] - outside_y : outside_y - c.v[a][0][d];
        gz[a][b][d] = d == 0 ? c.v[a][b][1] - outside_z : outside_z - c.v[a][b][0];
      }
  return Vec3(trilinear(c, gx), trilinear(c, gy), trilinear(c, gz)) * 0.5f;
}

} // namespace

SdfPeer::SdfPeer(const TriangleMesh& mesh, const SdfPeerOptions& options) : band_voxels_(options.band_voxels) {
  const auto t0 = std::chrono::steady_clock::now();
  const MeshArrays arrays = mesh_arrays(mesh);
  check_options(options, arrays);
  openvdb::initialize();  // idempotent and thread-safe; registers the grid types
  grid_ = std::make_unique<Grid>();
  if (options.voxel > 0) {
    voxel_ = options.voxel;
    grid_->grid = build_grid(arrays, voxel_, band_voxels_);
    builds_ = 1;
  } else {
    grid_->grid = build_at_memory(arrays, options.memory_bytes, band_voxels_, voxel_, builds_);
  }
  inverse_voxel_ = float(1.0 / voxel_);
  grid_->background = grid_->grid->background();
  memory_bytes_ = grid_->grid->memUsage();
  build_seconds_ = seconds_since(t0);
}

SdfPeer::~SdfPeer() = default;

float SdfPeer::distance(const Vec3& p) const noexcept {
  const Accessor acc = grid_->grid->getConstUnsafeAccessor();
  Cell c;
  return cell_at(acc, p * inverse_voxel_, c) ? trilinear(c, c.v) : grid_->background;
}

bool SdfPeer::within_reach(const Vec3& centre, float radius) const noexcept {
  return !(distance(centre) > radius + float(voxel_));
}

Contact SdfPeer::query(const Segment& segment, const ForceLaw& law) const noexcept {
  Contact contact;
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f) || !std::isfinite(length)) return contact;
  const Accessor acc = grid_->grid->getConstUnsafeAccessor();
  Cell tip;
  if (!cell_at(acc, segment.end * inverse_voxel_, tip)) return contact;
  const float p = -trilinear(tip, tip.v);
  if (!(p > 0.f)) return contact;  // the tip outside (or on) the surface
  Cell handle;
  if (cell_at(acc, segment.start * inverse_voxel_, handle) && trilinear(handle, handle.v) < 0.f)
    return contact;  // the handle inside: not a contact by the product's definition
  const Vec3 g = gradient(acc, tip);
  const float g_norm = g.norm();
  if (!(g_norm > 1e-6f) || !std::isfinite(g_norm)) return contact;  // deeper than the band: flat
  const Vec3 n = g / g_norm;
  const Vec3 l = delta / length;
  contact.contact = true;
  contact.normal = n;
  contact.point = segment.end + p * n;
  contact.depth = std::min(length, p / std::max(1e-3f, -l.dot(n)));
  if (law.depth == DepthLaw::normal)
    contact.force = n * (law.stiffness_n_per_m * p * law.metres_per_unit);
  else
    apply_force_law(contact, law);
  return contact;
}

std::string SdfPeer::describe() const {
  std::ostringstream s;
  s << "sdf peer: OpenVDB level set, voxel " << voxel_ << " model units, band " << band_voxels_ << " voxels, "
    << double(memory_bytes_) / (1024.0 * 1024.0) << " MiB, " << grid_->grid->activeVoxelCount() << " active voxels, "
    << builds_ << (builds_ == 1 ? " build, " : " builds, ") << build_seconds_ << " s";
  return s.str();
}

} // namespace hb
