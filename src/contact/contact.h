#pragma once
// The answer to a probe query, shared by the exact reference and the haptic box so that a
// comparison isolates the approximation.
#include "contact/workspace_options.h"
#include "geometry/segment.h"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace hb {

/// Which depth the spring of the force law compresses.
enum class DepthLaw : std::uint8_t {
  /// The depth d - t0 projected on the normal: F = k (d - t0) (-l . n) n. The wall feels k
  /// whatever the stylus tilt (the default; docs/stability.md, test T5).
  normal,
  /// The paper's eq. 2, depth along the segment: F = k (d - t0) n. A stylus tilted by theta
  /// from the normal feels k / cos(theta): 2 k at 60 degrees, 3.9 k at 75.
  along_segment,
};

/// Hooke's law (paper eq. 2): F = k (d - t0) n, with the depth converted to metres, the depth
/// projected on the normal by default (DepthLaw).
struct ForceLaw {
  /// k in N/m, > 0. The product's default (WorkspaceOptions); a law for a model comes from
  /// its Workspace (Workspace::law), which also sets metres_per_unit.
  float stiffness_n_per_m = float(WorkspaceOptions::kDefaultStiffness);
  float metres_per_unit = 0.001f;    ///< model units to metres (default: models in mm).
  DepthLaw depth = DepthLaw::normal;
};

/// Largest normal stiffness the law can make a wall feel for a stylus tilted up to
/// `max_tilt_degrees` from the normal, as a multiple of k: 1 for DepthLaw::normal,
/// 1 / cos(max tilt) along the segment (the servo's stiffness limit uses it).
inline float felt_stiffness_factor(const ForceLaw& law, float max_tilt_degrees = 75.f) noexcept {
  if (law.depth == DepthLaw::normal) return 1.f;
  const float c = std::cos(std::min(std::max(max_tilt_degrees, 0.f), 89.f) * 3.14159265f / 180.f);
  return 1.f / c;
}

/// The factor the force law applies to k (d - t0) n for unit direction l and unit normal n:
/// max(0, -l . n) for DepthLaw::normal, 1 along the segment. (Sums in a fixed order, so the
/// batched query's lanes give the same bits.)
inline float depth_law_scale(const ForceLaw& law, float lx, float ly, float lz, const Vec3& n) noexcept {
  if (law.depth == DepthLaw::along_segment) return 1.f;
  const float c = -(lx * n.x() + ly * n.y() + lz * n.z());
  return c > 0.f ? c : 0.f;
}

/// Contact definition (paper Figure 7), the same for every method: walking the line of the
/// segment from outside the object towards the tip, the first surface met must lie on the
/// segment, between the handle S and the tip E. A handle already inside the object (the first
/// surface is behind S) or a tip short of the surface is no contact.
struct Contact {
  bool contact = false;         ///< true when the definition above holds.
  float depth = 0.f;            ///< penetration d - t0 along the segment, model units, >= 0.
  Vec3 point{Vec3::Zero()};     ///< surface point on the segment, model units.
  Vec3 normal{Vec3::Zero()};    ///< unit outward (shaded) surface normal at `point`.
  Vec3 force{Vec3::Zero()};     ///< k * depth * metres_per_unit * normal, in N.
  /// Unit outward geometric normal of the triangle crossed, where the answerer knows the
  /// triangle (exact Embree, the scene's cells route); zero otherwise (a box's interpolated
  /// answer). A proxy's constraint planes are the faces' planes: the shaded normal's plane
  /// through the point cuts into a faceted surface (GodObject).
  Vec3 face_normal{Vec3::Zero()};
};

/// Memory a caller lends to ContactQuery::query_star between calls (a tool keeps one), so that
/// the query allocates nothing once it has grown to the tool's size.
struct StarScratch {
  std::vector<Segment> segments;
  std::vector<std::uint32_t> ids, order, buckets, counts, triangles;
  std::vector<float> directions;
  std::vector<std::uint64_t> pairs;
  std::vector<std::uint32_t> stamps;  ///< per triangle, the call that last listed it
  std::uint32_t call = 0;
};

/// Anything that answers a probe segment: the exact reference, one haptic box, a scene of
/// boxes. Implementations are noexcept, allocation-free and safe from many threads.
class ContactQuery {
public:
  virtual ~ContactQuery() = default;
  virtual Contact query(const Segment& segment, const ForceLaw& law) const noexcept = 0;
  /// Answers segments[0, count) into out[0, count), the same answers as query() one by one.
  /// Implementations may overlap the work of several queries (see HapticBox::query_many);
  /// this default runs query() in a loop.
  virtual void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                          Contact* out) const noexcept {
    for (std::size_t i = 0; i < count; ++i) out[i] = query(segments[i], law);
  }
  /// Segments that share the handle `start`, to tips[0, count) (a tool's points around its
  /// centre), answered as query() answers each into out[0, count). An answerer may skip the
  /// segments it can tell cross no surface (BoxScene: by the grid's surface cells around the
  /// handle). This default: query_many() on the segments.
  virtual void query_star(const Vec3& start, const Vec3* tips, std::size_t count, const ForceLaw& law, Contact* out,
                          StarScratch& scratch) const noexcept {
    scratch.segments.resize(count);
    for (std::size_t i = 0; i < count; ++i) scratch.segments[i] = Segment{start, tips[i]};
    query_many(scratch.segments.data(), count, law, out);
  }
  /// The broad phase of a tool: whether any surface may lie within `radius` of `centre`
  /// (model units). False only when none does, so that a tool out of reach skips its points'
  /// queries (ToolProbe); this default: true.
  virtual bool within_reach(const Vec3& centre, float radius) const noexcept {
    (void)centre;
    (void)radius;
    return true;
  }
  /// Reads what a query of `segment` reads and discards the answer, leaving any state of
  /// this object as it was: a servo loop primes its caches with the last tick's segment in
  /// the busy-wait before the next tick (ServoOptions::prime), so that tick's query, a few
  /// micrometres away, finds its cells and triangles in cache instead of evicted by a
  /// millisecond's sleep. This default asks query(), for queries without state.
  virtual void prime(const Segment& segment, const ForceLaw& law) const noexcept {
    keep_result(query(segment, law));
  }
  /// Keeps the compiler from dropping a query whose answer is discarded (prime's reads).
  static void keep_result(const Contact& c) noexcept { asm volatile("" : : "r"(&c) : "memory"); }
};

/// Fills `c.force` from `c.depth` and `c.normal`, the depth along the segment (eq. 2 as
/// printed, whatever law.depth says); the force law proper is the overload with l.
inline void apply_force_law(Contact& c, const ForceLaw& law) noexcept {
  c.force = c.contact ? Vec3(c.normal * (law.stiffness_n_per_m * c.depth * law.metres_per_unit))
                      : Vec3(Vec3::Zero());
}

/// Fills `c.force` by the law for a segment of unit direction `l` (handle -> tip).
inline void apply_force_law(Contact& c, const ForceLaw& law, const Vec3& l) noexcept {
  apply_force_law(c, law);
  if (c.contact && law.depth == DepthLaw::normal) c.force *= depth_law_scale(law, l.x(), l.y(), l.z(), c.normal);
}

/// The contact of a surface crossed at distance t (<= length) from the handle `start` along
/// unit direction l, with outward `normal` there: depth length - t, the point, the force law;
/// `face_normal` the crossed triangle's unit geometric normal when known (else zero).
inline Contact contact_along(const Vec3& start, const Vec3& l, float length, float t, const Vec3& normal,
                             const ForceLaw& law, const Vec3& face_normal = Vec3::Zero()) noexcept {
  Contact c;
  c.contact = true;
  c.depth = std::max(0.f, length - t);  // Embree may return t a rounding past tfar = length
  c.point = start + t * l;
  c.normal = normal;
  c.face_normal = face_normal;
  apply_force_law(c, law, l);
  return c;
}

} // namespace hb
