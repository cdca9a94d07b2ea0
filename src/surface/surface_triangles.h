#pragma once
// The mesh's triangles in a query-ready form, for the exact refinement of a haptic-box
// answer (see HapticBox::query, step 6). One 64-byte record (a cache line) per triangle:
// a vertex, the two edges from it, and the three vertex normals in 32-bit octahedral code,
// so testing a triangle costs one memory line and no index chase, plus its three edge
// neighbours for walking from a candidate to the triangle the line actually crosses.
#include "mesh/triangle_mesh.h"
#include "prefetch.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <vector>

namespace hb {

/// Marks a sample that has no triangle (a miss), or a missing neighbour.
constexpr std::uint32_t kNoTriangle = 0xffffffffu;

/// A box's triangle ids, one per sample: 32-bit surface slots, or 16-bit offsets from `base`
/// (0xffff: a miss) when the box's slots span fewer than 65535 (half the memory; slots of one
/// piece are close in the surface's Morton order).
struct TriangleIds {
  const void* data = nullptr;
  int width = 4;             ///< bytes per id: 4 or 2.
  std::uint32_t base = 0;    ///< added to 16-bit ids.
  std::uint32_t at(std::size_t k) const noexcept {
    if (width == 4) return static_cast<const std::uint32_t*>(data)[k];
    const std::uint16_t v = static_cast<const std::uint16_t*>(data)[k];
    return v == 0xffffu ? 0xffffffffu : base + v;
  }
  const char* address(std::size_t k) const noexcept { return static_cast<const char*>(data) + k * std::size_t(width); }
};

/// Packs 32-bit ids (kNoTriangle for a miss) into the narrowest TriangleIds; `owner` receives
/// the storage.
TriangleIds pack_triangle_ids(const std::vector<std::uint32_t>& ids, std::shared_ptr<const void>& owner);

/// Triangle records, indexed by slot (see slot()); ids stored in boxes are slots. Immutable once built; shared by the
/// boxes of a scene.
class SurfaceTriangles {
public:
  struct alignas(64) Record {
    float a[3], e1[3], e2[3];   // vertex 0, vertex 1 - vertex 0, vertex 2 - vertex 0
    std::uint32_t normal[3];    // vertex normals, octahedral32
    std::uint32_t neighbour[3]; // across the edge opposite vertex k (kNoTriangle: none)
    std::uint32_t pad;
  };
  static_assert(sizeof(Record) == 64, "one cache line per triangle");

  SurfaceTriangles() = default;
  /// Records of every triangle of `mesh` (which needs vertex normals); edge neighbours are
  /// joined by vertex position, so faces with vertices of their own still join. Throws
  /// hb::InvalidInput when the mesh has none.
  explicit SurfaceTriangles(const TriangleMesh& mesh);
  /// Refers to `count` records stored elsewhere (a mapped box file kept alive by `owner`).
  /// Ids read from them are bounds-checked at query time, so corrupt records cannot make a
  /// query read out of bounds. Throws hb::InvalidInput on a null pointer or zero count.
  SurfaceTriangles(const Record* records, std::size_t count, std::shared_ptr<const void> owner);

  std::size_t size() const { return count_; }

  /// Shading from a normal map: a simplified surface standing in for a finer mesh whose
  /// vertex normals the exact answer interpolates (hb::fit_normal_map). Per triangle, in
  /// slot order, the octahedral32 normals of a barycentric lattice of `side` steps an edge,
  /// lattice_points(side) of them: point (i, j), at u = i / side along e1 and v = j / side
  /// along e2 (i + j <= side), is number j (side + 1) - j (j - 1) / 2 + i. The shaded normal
  /// at (u, v) interpolates the three points of the lattice triangle holding it (the cell's
  /// lower triangle (i, j) (i+1, j) (i, j+1), or its upper one (i+1, j) (i+1, j+1) (i, j+1)):
  /// exactly how the finer mesh shades where its triangles are the lattice's, as where a
  /// mesh was flat-subdivided log2(side) times. Without a map (side 0, the default) the
  /// three corner normals of each record. `map` (count * lattice_points(side) codes) stays
  /// alive with `owner`. Throws hb::InvalidInput for a side outside [1, kMaxMapSide] or a
  /// null map. Call before the surface is shared: queries read the map unsynchronised.
  static constexpr int kMaxMapSide = 64;
  static std::size_t lattice_points(int side) noexcept {
    return std::size_t(side + 1) * std::size_t(side + 2) / 2;
  }
  void set_normal_map(int side, const std::uint32_t* map, std::shared_ptr<const void> owner);
  /// The same from codes in the mesh's triangle order (hb::fit_normal_map's), for a surface
  /// built from that mesh: reordered to slot order into storage the surface keeps. Throws
  /// hb::InvalidInput as above, and for a surface not built from a mesh or a map of another size.
  void set_normal_map(int side, const std::vector<std::uint32_t>& by_triangle);
  int normal_map_side() const noexcept { return map_side_; }
  const std::uint32_t* normal_map() const noexcept { return map_; }
  /// Bytes of the normal map (0 without one).
  std::size_t normal_map_bytes() const noexcept { return map_ ? count_ * lattice_points(map_side_) * 4 : 0; }
  /// The shading of triangle `id` at barycentric (u, v) before normalisation: the map's
  /// interpolation, or the corner normals'.
  Vec3 shading_at(std::uint32_t id, float u, float v) const noexcept;
  /// The slot (record index) of mesh triangle `triangle`: records are stored in Morton order
  /// of the triangle centroids, not in the mesh's order. Only for surfaces built from a mesh
  /// (kNoTriangle otherwise, or for an unknown triangle).
  std::uint32_t slot(std::uint32_t triangle) const noexcept {
    return triangle < slot_of_.size() ? slot_of_[triangle] : kNoTriangle;
  }
  const Record* records() const { return records_; }
  /// Bytes of the records.
  std::size_t bytes() const { return count_ * sizeof(Record); }

  /// Ray origin + s dir (dir need not be unit; s in units of |dir|) against triangle `id`
  /// (Moller-Trumbore, both sides): true with the parameter `s` >= s_min, the shaded normal
  /// (unit, oriented like the geometric normal) and whether the ray meets the front face.
  /// When the line passes beside the triangle, `outside` (if given) receives how far: minus
  /// the most negative barycentric coordinate of its plane crossing (infinity: parallel).
  bool intersect(std::uint32_t id, const float origin[3], const float dir[3], float s_min, float& s,
                 Vec3& normal, bool& front, float* outside = nullptr) const noexcept;

  /// A probe's last normal-map cell: the three lattice normals decoded for triangle `id`'s
  /// cell (i, j, upper) of this surface's map (`map` tells the surface). Along a stroke the
  /// crossing stays in one cell for tens of ticks, and decoding the three is most of a
  /// shading (BoxScene::query with a SceneQueryState keeps one).
  struct LatticeCache {
    const void* map = nullptr;
    std::uint32_t id = 0xffffffffu;
    int i = -1, j = -1;
    bool upper = false;
    Vec3 n[3];
  };
  /// intersect() with the map's decode kept in `cache` (the same bits).
  bool intersect(std::uint32_t id, const float origin[3], const float dir[3], float s_min, float& s, Vec3& normal,
                 bool& front, LatticeCache& cache) const noexcept;

  /// Unit geometric normal (e1 x e2, the winding's outward side) of triangle `id`; zero when
  /// out of range or degenerate. The same float operations as EmbreeScene's on the mesh, so
  /// the same bits for the same triangle.
  Vec3 face_normal(std::uint32_t id) const noexcept;

  /// plane_hit() of up to 16 triangles at once, four side by side in SSE2 lanes with the
  /// same float operations in the same order (the same bits as intersect()'s): per triangle
  /// k of ids[0, count), u[k], v[k], s[k] and bit k of the result set when the line meets
  /// its plane (the id in range, the determinant not tiny, all three finite).
  unsigned plane_hits(const std::uint32_t* ids, int count, const float origin[3], const float dir[3], float* u,
                      float* v, float* s) const noexcept;
  /// The rest of intersect() for a plane crossing inside triangle `id` (u, v, s from
  /// plane_hits): false when s < s_min; the shaded normal and the facing otherwise.
  bool shade(std::uint32_t id, const float dir[3], float u, float v, float s, float s_min, float& s_out, Vec3& normal,
             bool& front) const noexcept {
    return id < count_ && finish(records_[id], dir, u, v, s, s_min, s_out, normal, front);
  }

  /// The crossing nearest `o` of the segment o + s d, s in [s_min, s_max], among the
  /// triangles ids[0, count), either face (the plane crossings of plane_hits(), 16 at a
  /// time): true with its parameter `s`, whether it is a front face (the geometric normal
  /// against d) and its id. No normals are decoded. Ties keep the first id listed.
  bool first_crossing(const std::uint32_t* ids, std::size_t count, const float o[3], const float d[3], float s_min,
                      float s_max, float& s, bool& front, std::uint32_t& id) const noexcept;

  /// Starts loading triangle `id`'s record (no effect when out of range).
  void prefetch(std::uint32_t id) const noexcept {
    if (id < count_) hb::prefetch(records_ + id);
  }

  /// What the walks of one line have already explored (walk()'s `memo`): per triangle met,
  /// whether a walk on through it ends the same whatever its budget (a crossing, a border, a
  /// turn back: kSettled) or else the steps it still had. A walk of the same line reaching a
  /// triangle it settled, or one it left with at least as many steps, follows the same edges
  /// to the same end (a walk's next edge depends only on the triangle and the line), so it
  /// stops there: it cannot find a crossing that walk did not. Not shared between lines.
  struct WalkMemo {
    static constexpr int kSlots = 256;
    static constexpr std::uint8_t kSettled = 0xff;
    std::uint32_t id[kSlots];
    std::uint8_t left[kSlots];
    int used = 0;
    WalkMemo() noexcept {
      for (std::uint32_t& i : id) i = kNoTriangle;
    }
  };

  /// As intersect(), but when the line passes beside triangle `start`, steps to the
  /// neighbour across the edge it passes (the most negative barycentric coordinate), at most
  /// `max_steps` times: finds the triangle the line crosses near a candidate that missed.
  /// `crossed`, when given, receives the triangle crossed.
  /// `memo`, when given, stops the walk where an earlier walk of the same line (recorded in
  /// the same memo) already went (false: nothing new there), and records this walk's path.
  bool walk(std::uint32_t start, const float origin[3], const float dir[3], float s_min, int max_steps, float& s,
            Vec3& normal, bool& front, std::uint32_t* crossed = nullptr, WalkMemo* memo = nullptr) const noexcept;

private:
  // Line against one record: barycentrics (u, v) and the line parameter of the plane hit;
  // false for a line parallel to the plane.
  static bool plane_hit(const Record& r, const float o[3], const float d[3], float& u, float& v, float& s) noexcept;
  // shading_at() with a map (kept out of finish()'s inline path).
  [[gnu::noinline]] Vec3 lattice_shading(std::uint32_t id, float u, float v, LatticeCache* cache = nullptr) const noexcept;
  // The lattice cell (i, j) of side k holding barycentric (u, v), i + j <= k - 1 (a point on
  // the far edge belongs to the last cell's lower triangle, whose weights there are the
  // edge's), and (u, v) within it in steps (fu, fv).
  static void lattice_cell(int k, float u, float v, int& i, int& j, float& fu, float& fv) noexcept {
    const float fu_all = u * float(k), fv_all = v * float(k);
    i = std::min(std::max(int(std::floor(fu_all)), 0), k - 1);
    j = std::min(std::max(int(std::floor(fv_all)), 0), k - 1);
    if (i + j > k - 1) {
      if (fu_all - float(i) >= fv_all - float(j)) j = k - 1 - i;
      else i = k - 1 - j;
      if (i < 0) i = 0, j = k - 1;
      if (j < 0) j = 0, i = k - 1;
    }
    fu = fu_all - float(i);
    fv = fv_all - float(j);
  }
  // The index of lattice point (i, j) of side k.
  static std::size_t lattice_index(int k, int i, int j) noexcept {
    return std::size_t(j * (k + 1) - j * (j - 1) / 2 + i);
  }
  // Starts loading the map's lattice points lattice_shading(id, u, v) reads (rows j and
  // j + 1): a crossing found in a cell's tests is shaded a little later, once the walk
  // has checked that no nearer cell holds one, and at 13M triangles the map (33 MB) is out
  // of cache (docs/speed.md). Inline: GCC drops a call to a function that only prefetches
  // (it has no side effects it can see).
  void prefetch_shading(std::uint32_t id, float u, float v) const noexcept {
    if (!map_ || id >= count_ || !(u >= 0.f && v >= 0.f)) return;
    const int k = map_side_;
    const std::uint32_t* p = map_ + std::size_t(id) * lattice_points(k);
    int i, j;
    float fu, fv;
    lattice_cell(k, u, v, i, j, fu, fv);
    // Rows j and j + 1 from column i: two points each (a line boundary may fall between them).
    const std::uint32_t* row = p + lattice_index(k, i, j);
    const std::uint32_t* next = p + lattice_index(k, i, j + 1);
    hb::prefetch(row);
    hb::prefetch(row + 1);
    hb::prefetch(next);
    hb::prefetch(next + 1);
  }
  // `r` is one of records_ (the map is found by its slot).
  bool finish(const Record& r, const float d[3], float u, float v, float s, float s_min, float& s_out, Vec3& normal,
              bool& front, LatticeCache* cache = nullptr) const noexcept;
  // Both intersect()s.
  bool intersect_with(std::uint32_t id, const float origin[3], const float dir[3], float s_min, float& s, Vec3& normal,
                      bool& front, float* outside, LatticeCache* cache) const noexcept;

  const Record* records_ = nullptr;
  std::size_t count_ = 0;
  std::shared_ptr<const void> owner_;
  std::vector<std::uint32_t> slot_of_;  // mesh triangle -> slot (built from a mesh only)
  const std::uint32_t* map_ = nullptr;  // normal map (set_normal_map), slot order
  int map_side_ = 0;
  std::shared_ptr<const void> map_owner_;
};

} // namespace hb
