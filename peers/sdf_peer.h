#pragma once
// The benchmark's peer for tools: the standard multi-point method, each tool point against a
// signed distance field (VPS, McNeely, Puterbaugh and Troy 1999; Barbic and James 2008, the
// point shell against a distance field), the field an OpenVDB narrow-band level set of the
// mesh built at a chosen memory (the box file's, so the two are compared at equal memory).
// OpenVDB stays inside sdf_peer.cpp: this header includes only the core.
#include "contact/contact.h"
#include "mesh/triangle_mesh.h"
#include <cstddef>
#include <memory>
#include <string>

namespace hb {

/// How the distance field is sized.
struct SdfPeerOptions {
  /// Edge of a voxel, model units, >= 0. 0: chosen so that the grid takes `memory_bytes`.
  /// When both are given, `voxel` is used and `memory_bytes` ignored.
  double voxel = 0;
  /// Target memory of the grid in bytes (e.g. the box file's size), used when voxel is 0:
  /// the voxel is estimated from the surface area, the grid built and measured, and the
  /// voxel corrected (at most two more builds) until the grid is within 10% of the target
  /// (or the closest of the builds is kept).
  std::size_t memory_bytes = 0;
  /// Half width of the narrow band, in voxels, in [1, 64]: the field is the surface's distance
  /// within band_voxels * voxel outside (and inside, unless inside_depth asks for more) and
  /// clamped beyond. Memory grows with it.
  int band_voxels = 3;
  /// Deepest penetration the field must render, model units, >= 0: the band inside the surface
  /// is widened to inside_depth / voxel + 2 voxels when that is more than band_voxels. A tool
  /// point deeper than the band inside finds the field flat there: no normal, no contact.
  /// The normal is reliable to about a voxel short of the band's inner edge.
  double inside_depth = 0;
};

/// The signed distance field peer: answers a probe segment (handle S -> tip E) by the field
/// at E, as the point-shell methods do, not by where the segment crosses the surface:
///  - contact when the field is negative at E (the tip inside) and not negative at S (the
///    handle outside, the product's contact definition);
///  - normal n: the field's gradient at E, normalised (central differences of the voxels,
///    trilinearly interpolated: continuous across voxels); no contact where it vanishes
///    (a tip deeper than the band, where the field is flat);
///  - p = -sdf(E), the penetration along the normal (model units); point = E + p n, the
///    nearest surface point (not on the segment in general);
///  - depth (along the segment, as Contact says) = min(|SE|, p / max(1e-3, -l . n)), l the
///    segment's unit direction, so that apply_force_law with DepthLaw::normal gives back the
///    force below wherever -l . n >= 1e-3;
///  - force: k p metres_per_unit n for DepthLaw::normal (the normal depth law exactly, as the
///    point-shell methods render), k depth metres_per_unit n along the segment;
///  - face_normal: zero (the field knows no triangle).
/// The mesh should be closed (OpenVDB signs the field by flood fill from outside).
/// Built once; const, noexcept and safe from many threads after (each query reads the grid
/// through its own accessor on the stack; nothing is allocated).
class SdfPeer final : public ContactQuery {
public:
  /// Builds the field of `mesh` (model units; not kept). Throws hb::InvalidInput naming the
  /// value when the mesh has no triangles, no area, a non-finite vertex or an index out of
  /// range, or an option is out of range (negative or non-finite voxel or inside_depth,
  /// neither voxel nor memory_bytes given, band_voxels outside [1, 64], a voxel so small the
  /// grid would take over 64 GiB); hb::LibraryError when OpenVDB fails.
  SdfPeer(const TriangleMesh& mesh, const SdfPeerOptions& options);
  ~SdfPeer() override;
  SdfPeer(const SdfPeer&) = delete;
  SdfPeer& operator=(const SdfPeer&) = delete;

  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;
  /// The same answers as query() one by one, read through one accessor (a tool's points,
  /// close together, find the grid's nodes cached).
  void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                  Contact* out) const noexcept override;
  /// False when the field at `centre` exceeds radius + voxel (no surface within `radius`,
  /// with a voxel's margin for the interpolation). Beyond the band the field is clamped to
  /// band_voxels * voxel, so a radius of that or more always answers true (the field cannot
  /// tell), as do a centre inside the object and a non-finite one.
  bool within_reach(const Vec3& centre, float radius) const noexcept override;

  /// The field's trilinear value at `p`, model units: negative inside, clamped beyond the band
  /// to band_voxels * voxel outside and -inside_voxels * voxel inside.
  float distance(const Vec3& p) const noexcept;
  /// The grid's memory (OpenVDB's memUsage), bytes.
  std::size_t memory_bytes() const noexcept { return memory_bytes_; }
  /// The voxel edge, model units.
  double voxel() const noexcept { return voxel_; }
  int band_voxels() const noexcept { return band_voxels_; }
  /// The band's half width inside the surface, voxels (>= band_voxels).
  int inside_voxels() const noexcept { return inside_voxels_; }
  /// Builds of the grid it took to meet the memory target (1 when the voxel was given).
  int builds() const noexcept { return builds_; }
  /// Wall-clock seconds the constructor took (every build of the search included).
  double build_seconds() const noexcept { return build_seconds_; }
  /// One line: voxel, band, memory, active voxels, builds.
  std::string describe() const;

private:
  struct Grid;  // the OpenVDB grid, known to sdf_peer.cpp only
  std::unique_ptr<Grid> grid_;
  double voxel_ = 0;
  Vec3 origin_{Vec3::Zero()};  // world position of the grid's index (0, 0, 0), model units
  float inverse_voxel_ = 0;
  int band_voxels_ = 3;
  int inside_voxels_ = 3;
  std::size_t memory_bytes_ = 0;
  int builds_ = 0;
  double build_seconds_ = 0;
};

} // namespace hb
