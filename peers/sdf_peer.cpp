// The signed distance field peer (sdf_peer.h).
//  1. Check the mesh and the options; copy the mesh into OpenVDB's arrays.
//  2. The voxel: given, or sized to the memory target. A narrow band's memory is its leaf
//     nodes (8^3 voxels each), about c A / v^2 for surface area A and voxel v once the voxel
//     is small against the shape: estimate v from A with a measured c, build, measure
//     memUsage, correct v by the measured exponent (-2 first, then the secant through the
//     last two builds), at most three builds, keep the closest.
//  3. A query reads the grid through an accessor of its own (one per batch for query_many;
//     not registered with the tree: the grid is never written after the build), each leaf
//     node around a point found once and read directly: the trilinear field at the tip, at
//     the handle only when the tip is inside, then the gradient at the tip from 32 voxels
//     around it (the voxels' central differences, interpolated trilinearly with the value's
//     own weights, so the normal is continuous across voxels).
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

/// The band's half widths in voxels, outside and inside the surface.
struct Band {
  int outside = 3;
  int inside = 3;
};

/// The band at `voxel`: inside, wide enough that a tip `inside_depth` deep still has two
/// voxels of field beyond it (its gradient reads one; one more keeps it off the band's edge).
Band band_at(const SdfPeerOptions& o, double voxel) {
  const double needed = std::ceil(o.inside_depth / voxel) + 2;
  return Band{o.band_voxels, int(std::min(1e6, std::max(double(o.band_voxels), needed)))};
}

/// Bytes of a band per unit of area at `voxel`: leaf nodes of some 2.2 KB (8^3 voxels), 1.25
/// times the area's share of them, over L layers of leaves for a band T = outside + inside
/// voxels thick, L = 1 + 0.7 (T / 6)^0.6 fitted on a sphere, a slab and the armadillo for
/// T from 6 to 25 (within 15%: a thin part fills less than the band inside). Only the first
/// guess of the search depends on it.
double bytes_per_area(const SdfPeerOptions& o, double voxel) {
  const Band b = band_at(o, voxel);
  const double layers = 1.0 + 0.7 * std::pow((b.outside + b.inside) / 6.0, 0.6);
  return 2200.0 / 64.0 * 1.25 * layers / (voxel * voxel);
}

/// Largest grid the options may ask for (an explicit voxel far too small for the mesh).
constexpr double kMaxEstimatedBytes = 64.0 * 1024 * 1024 * 1024;
/// Index coordinates stay well inside OpenVDB's int32 Coord.
constexpr float kMaxIndex = 1 << 29;

struct MeshArrays {
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  double area = 0;
  double diagonal = 0;
  Vec3 lowest{Vec3::Zero()};  // the bounds' minimum corner
};

/// A grid and where its index space lies: index = (world - origin) / voxel.
struct Built {
  openvdb::FloatGrid::Ptr grid;
  double voxel = 0;
  Vec3 origin{Vec3::Zero()};
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
  const Bounds bounds = mesh.bounds();
  a.diagonal = bounds.diagonal();
  a.lowest = bounds.min;
  return a;
}

void check_options(const SdfPeerOptions& o, const MeshArrays& mesh) {
  if (!std::isfinite(o.voxel) || o.voxel < 0)
    throw InvalidInput("SdfPeer: voxel " + std::to_string(o.voxel) + " is negative or not finite");
  if (o.voxel == 0 && o.memory_bytes == 0)
    throw InvalidInput("SdfPeer: neither a voxel nor memory_bytes given: one of them sizes the field");
  if (o.band_voxels < 1 || o.band_voxels > 64)
    throw InvalidInput("SdfPeer: band_voxels " + std::to_string(o.band_voxels) + " outside [1, 64]");
  if (!std::isfinite(o.inside_depth) || o.inside_depth < 0)
    throw InvalidInput("SdfPeer: inside_depth " + std::to_string(o.inside_depth) + " is negative or not finite");
  if (!(mesh.area > 0) || !(mesh.diagonal > 0))
    throw InvalidInput("SdfPeer: the mesh has no area (all its triangles degenerate)");
  if (o.voxel > 0) {
    const double estimate = bytes_per_area(o, o.voxel) * mesh.area;
    if (estimate > kMaxEstimatedBytes || mesh.diagonal / o.voxel > kMaxIndex)
      throw InvalidInput("SdfPeer: voxel " + std::to_string(o.voxel) + " is too small for a mesh of area " +
                         std::to_string(mesh.area) + ": the grid would take about " +
                         std::to_string(estimate / (1024.0 * 1024 * 1024)) + " GiB");
  }
}

/// The level set at `voxel`. Its index space starts just below the mesh's bounds: a tree's
/// top internal nodes (4096 voxels a side, some 270 KB each whatever they hold) would
/// otherwise split a mesh around the world's origin eight ways, a floor of 2 MB.
Built build_grid(const MeshArrays& mesh, double voxel, const Band& band) {
  Built b;
  b.voxel = voxel;
  b.origin = mesh.lowest - Vec3::Constant(float((band.outside + 2) * voxel));
  const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(voxel);
  xform->postTranslate(openvdb::Vec3d(b.origin.x(), b.origin.y(), b.origin.z()));
  try {
    b.grid = band.inside == band.outside
                 ? openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, mesh.points, mesh.triangles,
                                                                      float(band.outside))
                 : openvdb::tools::meshToSignedDistanceField<openvdb::FloatGrid>(
                       *xform, mesh.points, mesh.triangles, {}, float(band.outside), float(band.inside));
    return b;
  } catch (const std::exception& e) {
    throw LibraryError(std::string("SdfPeer: OpenVDB's meshToLevelSet failed at voxel ") + std::to_string(voxel) +
                       ": " + e.what());
  }
}

double log_error(std::size_t bytes, std::size_t target) { return std::abs(std::log(double(bytes) / double(target))); }

/// The voxel search of step 2: the grid closest to `target` bytes in at most three builds.
Built build_at_memory(const MeshArrays& mesh, const SdfPeerOptions& o, int& builds) {
  constexpr double kTolerance = 0.1;
  const std::size_t target = o.memory_bytes;
  const double largest = mesh.diagonal / 8;  // coarser than this the field is no longer the shape
  // The estimate's voxel for `bytes`: the fixed point of v = sqrt(c(v) A / bytes) (c grows
  // as v shrinks when inside_depth widens the band), from above.
  auto estimate = [&](double bytes) {
    double v = largest;
    for (int i = 0; i < 30; ++i) v = std::min(largest, std::sqrt(bytes_per_area(o, v) * v * v * mesh.area / bytes));
    return v;
  };
  const double smallest = std::max(double(mesh.diagonal) / kMaxIndex, estimate(kMaxEstimatedBytes));
  auto clamp_voxel = [&](double v) { return std::min(largest, std::max(smallest, v)); };
  double v = clamp_voxel(estimate(double(target)));
  Built best;
  double previous_voxel = 0, previous_bytes = 0;
  std::size_t best_bytes = 0;
  for (builds = 1; builds <= 3; ++builds) {
    Built built = build_grid(mesh, v, band_at(o, v));
    const std::size_t bytes = built.grid->memUsage();
    if (!best.grid || log_error(bytes, target) < log_error(best_bytes, target)) {
      best = std::move(built);
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
  return best;
}

/// The field around one index-space point: the trilinear weights and the 2 x 2 x 2 voxels of
/// its cell.
struct Cell {
  openvdb::Coord origin;  // the cell's lowest voxel
  float fx = 0, fy = 0, fz = 0;
  float v[2][2][2];  // [x][y][z] offsets from origin
};

/// The cell of `q` (index space) and its weights; false when `q` is not finite or beyond the
/// grid's coordinates.
bool locate(const Vec3& q, Cell& c) noexcept {
  if (!q.allFinite() || q.cwiseAbs().maxCoeff() > kMaxIndex) return false;
  const float x0 = std::floor(q.x()), y0 = std::floor(q.y()), z0 = std::floor(q.z());
  c.origin = openvdb::Coord(int(x0), int(y0), int(z0));
  c.fx = q.x() - x0;
  c.fy = q.y() - y0;
  c.fz = q.z() - z0;
  return true;
}

/// Reads the voxels within one voxel of a cell (the 4 x 4 x 4 around it) straight from their
/// leaf nodes, each leaf (at most 3 a side) found once through the accessor, or the tile
/// that stands where there is no leaf (beyond the band). Read one by one through the accessor,
/// a cell across a leaf's face makes it climb the tree at every other voxel.
class StencilReader {
public:
  StencilReader(const Accessor& acc, const openvdb::Coord& origin) noexcept
      : acc_(acc), base_(origin.x() & ~7, origin.y() & ~7, origin.z() & ~7) {}
  float operator()(const openvdb::Coord& c) noexcept {
    // Offsets from the cell's leaf are in [-1, 10]: leaf -1, 0 or +1 along each axis.
    const int k = ((c.x() - base_.x() + 8) >> 3) * 9 + ((c.y() - base_.y() + 8) >> 3) * 3 +
                  ((c.z() - base_.z() + 8) >> 3);
    if (!(probed_ & (1u << k))) {
      leaves_[k] = acc_.probeConstLeaf(c);
      // No leaf: a tile of an upper node covers the leaf's whole place with one value.
      if (!leaves_[k]) tiles_[k] = acc_.getValue(c);
      probed_ |= 1u << k;
    }
    return leaves_[k] ? leaves_[k]->getValue(c) : tiles_[k];
  }

private:
  using Leaf = openvdb::FloatGrid::TreeType::LeafNodeType;
  const Accessor& acc_;
  openvdb::Coord base_;
  const Leaf* leaves_[27];
  float tiles_[27];
  std::uint32_t probed_ = 0;  // bit k: leaves_[k] looked up
};

/// Reads the cell's corners.
void read_corners(StencilReader& read, Cell& c) noexcept {
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c.v[a][b][d] = read(c.origin.offsetBy(a, b, d));
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
Vec3 gradient(StencilReader& read, const Cell& c) noexcept {
  float gx[2][2][2], gy[2][2][2], gz[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) {
        // Along each axis, the corner's neighbour inside the cell is known; the other lies
        // one voxel outside it (offset -1 for the low corner, +2 for the high one).
        const float outside_x = read(c.origin.offsetBy(a == 0 ? -1 : 2, b, d));
        const float outside_y = read(c.origin.offsetBy(a, b == 0 ? -1 : 2, d));
        const float outside_z = read(c.origin.offsetBy(a, b, d == 0 ? -1 : 2));
        gx[a][b][d] = a == 0 ? c.v[1][b][d] - outside_x : outside_x - c.v[0][b][d];
        gy[a][b][d] = b == 0 ? c.v[a][1][d] - outside_y : outside_y - c.v[a][0][d];
        gz[a][b][d] = d == 0 ? c.v[a][b][1] - outside_z : outside_z - c.v[a][b][0];
      }
  return Vec3(trilinear(c, gx), trilinear(c, gy), trilinear(c, gz)) * 0.5f;
}

/// The contact of step 3 (sdf_peer.h): the field read through `acc`, index = (world -
/// origin) * inverse_voxel.
Contact answer(const Accessor& acc, const Vec3& origin, float inverse_voxel, const Segment& segment,
               const ForceLaw& law) noexcept {
  Contact contact;
  const Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f) || !std::isfinite(length)) return contact;
  Cell tip;
  if (!locate((segment.end - origin) * inverse_voxel, tip)) return contact;
  StencilReader read_tip(acc, tip.origin);
  read_corners(read_tip, tip);
  const float p = -trilinear(tip, tip.v);
  if (!(p > 0.f)) return contact;  // the tip outside (or on) the surface
  Cell handle;
  if (locate((segment.start - origin) * inverse_voxel, handle)) {
    StencilReader read_handle(acc, handle.origin);
    read_corners(read_handle, handle);
    if (trilinear(handle, handle.v) < 0.f) return contact;  // the handle inside: no contact by definition
  }
  const Vec3 g = gradient(read_tip, tip);
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

} // namespace

SdfPeer::SdfPeer(const TriangleMesh& mesh, const SdfPeerOptions& options) : band_voxels_(options.band_voxels) {
  const auto t0 = std::chrono::steady_clock::now();
  const MeshArrays arrays = mesh_arrays(mesh);
  check_options(options, arrays);
  openvdb::initialize();  // idempotent and thread-safe; registers the grid types
  builds_ = 1;
  Built built = options.voxel > 0 ? build_grid(arrays, options.voxel, band_at(options, options.voxel))
                                  : build_at_memory(arrays, options, builds_);
  grid_ = std::make_unique<Grid>();
  grid_->grid = std::move(built.grid);
  voxel_ = built.voxel;
  inside_voxels_ = band_at(options, voxel_).inside;
  origin_ = built.origin;
  inverse_voxel_ = float(1.0 / voxel_);
  grid_->background = grid_->grid->background();
  memory_bytes_ = grid_->grid->memUsage();
  build_seconds_ = seconds_since(t0);
}

SdfPeer::~SdfPeer() = default;

float SdfPeer::distance(const Vec3& p) const noexcept {
  const Accessor acc = grid_->grid->getConstUnsafeAccessor();
  Cell c;
  if (!locate((p - origin_) * inverse_voxel_, c)) return grid_->background;
  StencilReader read(acc, c.origin);
  read_corners(read, c);
  return trilinear(c, c.v);
}

bool SdfPeer::within_reach(const Vec3& centre, float radius) const noexcept {
  if (!centre.allFinite()) return true;  // cannot tell
  return !(distance(centre) > radius + float(voxel_));
}

Contact SdfPeer::query(const Segment& segment, const ForceLaw& law) const noexcept {
  const Accessor acc = grid_->grid->getConstUnsafeAccessor();
  return answer(acc, origin_, inverse_voxel_, segment, law);
}

void SdfPeer::query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                         Contact* out) const noexcept {
  // One accessor for the batch: a tool's neighbouring points find their leaf cached.
  const Accessor acc = grid_->grid->getConstUnsafeAccessor();
  for (std::size_t i = 0; i < count; ++i) out[i] = answer(acc, origin_, inverse_voxel_, segments[i], law);
}

std::string SdfPeer::describe() const {
  std::ostringstream s;
  s << "sdf peer: OpenVDB level set, voxel " << voxel_ << " model units, band " << band_voxels_ << " voxels outside, "
    << inside_voxels_ << " inside, " << double(memory_bytes_) / (1024.0 * 1024.0) << " MiB, "
    << grid_->grid->activeVoxelCount() << " active voxels, " << builds_ << (builds_ == 1 ? " build, " : " builds, ")
    << build_seconds_ << " s";
  return s.str();
}

} // namespace hb
