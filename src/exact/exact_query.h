#pragma once
#include "exact/embree_scene.h"
#include "contact/contact.h"

namespace hb {

/// The exact reference: the segment against the original mesh with Embree. The first hit
/// within the segment is the contact when the segment meets the outside of the surface
/// there; a first hit on a back side means the handle is inside the object: no contact
/// (the same definition as the haptic box, see hb::Contact). Depth = L - t_hit, the shaded
/// normal, the same force law.
class ExactQuery final : public ContactQuery {
public:
  /// The mesh must outlive this object and have vertex normals.
  explicit ExactQuery(const TriangleMesh& mesh) : scene_(mesh) {}
  /// With the tree built as `build` says (the budgeted bake's own reference, queried some
  /// 40,000 times, takes the quick build; `bench` and `eval` the best).
  ExactQuery(const TriangleMesh& mesh, BvhBuild build) : scene_(mesh, {}, build) {}
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;
  /// The same answers as query() one by one, the rays traced as one stream
  /// (EmbreeScene::intersect_many).
  void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                  Contact* out) const noexcept override;
  /// Whether a triangle lies within `radius` of `centre` (an Embree point query).
  bool within_reach(const Vec3& centre, float radius) const noexcept override {
    return scene_.any_within(centre, radius);
  }
  /// The mesh the scene was built over (it must outlive this query).
  const TriangleMesh& mesh() const { return scene_.mesh(); }
  /// Its Embree scene of the whole mesh (the budgeted bake's decomposition casts its lines
  /// against it rather than building a second BVH of the same triangles).
  const EmbreeScene& scene() const { return scene_; }

private:
  EmbreeScene scene_;
};

} // namespace hb
