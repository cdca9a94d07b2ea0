#pragma once
// RAII wrapper of an Embree 3 device and scene over (a subset of) a triangle mesh.
#include "mesh/triangle_mesh.h"
#include <cstdint>
#include <memory>
#include <vector>

namespace hb {

/// First hit of a ray, with the shaded normal (vertex normals interpolated at the hit,
/// oriented like the triangle's outward geometric normal) and whether the ray met the
/// triangle's back side (the ray started inside a closed object or passed an opening).
struct RayHit {
  bool hit = false;
  float t = 0.f;
  std::uint32_t triangle = 0;   ///< id in the mesh given to the scene.
  Vec3 normal{Vec3::Zero()};    ///< unit shaded normal, outward.
  Vec3 face_normal{Vec3::Zero()};  ///< unit geometric normal (the triangle's winding), zero for a degenerate one.
  bool back_face = false;       ///< geometric normal points along the ray.
};

/// An Embree BVH over the chosen triangles of a mesh. Built once; intersect() is const,
/// noexcept and thread-safe. The mesh must outlive the scene (normals are read from it).
/// Errors reported by Embree are recorded by the device's error callback and thrown
/// after the call as hb::LibraryError.
/// How an EmbreeScene's tree is built: `best` (Embree's high quality: the fastest queries, the
/// slowest build) or `quick` (medium: about half the build time, slightly slower queries). The
/// nearest hit is the same either way.
enum class BvhBuild { best, quick };

class EmbreeScene {
public:
  /// `triangles` selects triangle ids of `mesh` (empty: all). `build`: the whole mesh defaults
  /// to the best tree, a selection (a piece's scene, cast once) to the quick one.
  explicit EmbreeScene(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles = {});
  EmbreeScene(const TriangleMesh& mesh, const std::vector<std::uint32_t>& triangles, BvhBuild build);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// First hit along origin + t * dir (unit dir) for t in [t_near, t_far].
  RayHit intersect(const Vec3& origin, const Vec3& dir, float t_near, float t_far) const noexcept;
  /// The first hits of `count` rays origins[i] + t dirs[i] (unit), t in [0, t_far[i]], as
  /// intersect() one by one, traced as one coherent stream (rtcIntersect1M): a tool's rays,
  /// which share a centre.
  void intersect_many(const Vec3* origins, const Vec3* dirs, const float* t_far, std::size_t count,
                      RayHit* out) const noexcept;
  /// Whether a triangle lies within `radius` of `centre` (a point query; true for a query
  /// out of Embree's range, which it cannot answer).
  bool any_within(const Vec3& centre, float radius) const noexcept;

  const TriangleMesh& mesh() const { return mesh_; }

private:
  struct Impl;
  const TriangleMesh& mesh_;
  std::unique_ptr<Impl> impl_;
};

} // namespace hb
