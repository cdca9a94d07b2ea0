#pragma once
// The haptic box (paper sections 3-5): a PBB whose faces carry m x m position points, each with
// a directional hemi-cube (DHC) of 4 sub-blocks x 3 faces x n x n directional samples.
#include "geometry/obb.h"
#include "geometry/surface_fit.h"
#include "codec/sample_table.h"
#include "box/box_layout.h"
#include "box/decoded_quads.h"
#include "contact/contact.h"
#include "codec/sample.h"
#include "surface/surface_triangles.h"
#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace hb {

/// Which answers of a refining box a query refines exactly (HapticBox::attach_surface).
enum class Refine {
  off,     ///< none: the blended answer only.
  misses,  ///< only where the blended answer is no contact but some samples hit.
  all,     ///< every answer (the default).
};

/// Instruction sets of query_many's batched path on raw tables (query_lanes.cpp), lowest
/// first. Every level gives the same answers, bit for bit.
enum class LaneIsa { sse2, avx, avx2, avx512 };
/// The level query_many uses: the best the CPU supports, at most the cap.
LaneIsa lane_isa() noexcept;
/// "sse2", "avx", "avx2" or "avx512".
const char* lane_isa_name(LaneIsa isa) noexcept;
/// Caps the level process-wide (tests check every level against query(); benchmarks compare
/// them). The default cap is the highest level.
void set_lane_isa_cap(LaneIsa cap) noexcept;

/// A baked box. Built once (by bake_box or by loading a file), then queried many times
/// through the const, noexcept, allocation-free query(), safe from many threads.
class HapticBox final : public ContactQuery {
public:
  /// Takes ownership of a table of params.sample_count() samples in the layout of
  /// BoxLayout::sample_index(). Throws hb::InvalidInput when the size does not match.
  HapticBox(const Obb& obb, const BoxParams& params, std::vector<Sample> table);
  /// Refers to a table owned elsewhere (a memory-mapped file kept alive by `owner`).
  HapticBox(const Obb& obb, const BoxParams& params, const Sample* table,
            std::shared_ptr<const void> owner);
  /// Takes ownership of a compressed table (see compress_table / compressed()).
  HapticBox(const Obb& obb, const BoxParams& params, CompressedTable table);
  /// Refers to a compressed payload owned elsewhere (kept alive by `owner`); validates its
  /// header only (O(1), touches one page). Throws hb::InvalidInput.
  HapticBox(const Obb& obb, const BoxParams& params, CodecId codec, const std::uint8_t* payload,
            std::size_t bytes, std::shared_ptr<const void> owner, const CodecStats& stats);
  /// A frame: the box's OBB and sampling without a table (nor triangle ids). What a scene
  /// answered by exact Embree keeps of its boxes (BoxScene::without_tables): the window draws
  /// them, `info` lists them, the route never reads a table. Its queries answer no contact;
  /// compressed() and attach_surface() throw hb::InvalidInput. Throws as the other constructors
  /// for a bad OBB or sampling.
  HapticBox(const Obb& obb, const BoxParams& params);
  /// This box's frame (see above).
  HapticBox frame() const { return HapticBox(obb_, params_); }
  /// Whether the box holds a table (false: a frame).
  bool has_table() const noexcept { return samples_.data() != nullptr; }

  /// Exact refinement (step 7 of the query, see the .cpp overview): `triangle_ids` holds,
  /// per sample in the layout of BoxLayout::sample_index(), the surface slot of the triangle the
  /// sample's ray hit (kNoTriangle for a miss), `surface` those triangles. Both are kept
  /// alive by the box (`ids_owner`, the shared surface). Throws hb::InvalidInput when the id
  /// count is not params().sample_count(), the width is not 2 or 4, or (when `validate`) an id
  /// is beyond `surface`; unvalidated ids (lazily mapped files) are bounds-checked per query.
  void attach_surface(const TriangleIds& triangle_ids, std::size_t count, std::shared_ptr<const void> ids_owner,
                      std::shared_ptr<const SurfaceTriangles> surface, bool validate = true);
  /// A copy of this box that does not refine (no triangle ids, no surface): the blend alone.
  HapticBox without_refinement() const {
    HapticBox box(*this);
    box.triangle_ids_ = TriangleIds{};
    box.ids_owner_.reset();
    box.surface_.reset();
    return box;
  }
  /// Whether queries refine with the exact triangles (attach_surface was called).
  bool refines() const { return surface_ != nullptr; }
  /// Refinement walks (step 7): when the walk from the candidate the line passes nearest
  /// fails (a crease, a border, a fold), walk from every other candidate too and keep the
  /// nearest accepted crossing (true, the default); false: the nearest candidate's walk
  /// only (the first refining boxes; docs/stability.md).
  void set_walk_all_candidates(bool on) noexcept { walk_from_all_ = on; }
  bool walk_all_candidates() const noexcept { return walk_from_all_; }
  /// Refinement walks (step 7): when every bounded walk failed, the walk from the nearest
  /// candidate goes on up to this many edges (a surface far from the box face, where the
  /// samples' hits lie several triangles from the crossing; around a pole, the chess
  /// piece's 256-triangle fan at its top). 8 or less: no long walk (the first refining boxes).
  /// Default 256: 64 left 18 of the chess piece's 21 remaining lost slide ticks at the pole.
  void set_long_walk_steps(int steps) noexcept { long_walk_steps_ = steps; }
  int long_walk_steps() const noexcept { return long_walk_steps_; }
  /// Refinement (step 7): test the candidate whose plane the line crosses nearest first and
  /// shade it alone, answering at once when it is accepted (true, the default), or shade
  /// every nearer crossing in candidate order (false: the plain loop). The same
  /// answers either way, bit for bit (tests/core/refinement_test.cpp); for tests and timing.
  void set_nearest_first(bool on) noexcept { nearest_first_ = on; }
  bool nearest_first() const noexcept { return nearest_first_; }
  const TriangleIds& triangle_ids() const { return triangle_ids_; }
  const std::shared_ptr<const SurfaceTriangles>& surface() const { return surface_; }
  /// Bytes of the triangle ids (0 without refinement); with the shared surface, per scene:
  /// BoxScene::refinement_bytes.
  std::size_t triangle_id_bytes() const {
    return triangle_ids_.data ? params_.sample_count() * std::size_t(triangle_ids_.width) : 0u;
  }

  /// A copy of this (raw) box with its table compressed; throws hb::InvalidInput when this
  /// box is already compressed or the options are out of range.
  HapticBox compressed(const CodecOptions& options) const;

  /// A blended hit whose unit normal makes n . l above -kGrazingCosine (the line more than
  /// 53 degrees from the normal) is settled across the surface (step 6a of the .cpp overview).
  static constexpr float kGrazingCosine = 0.6f;
  /// A grazing blend is settled only when its crossing is within kSettleReachCells / |n . l|
  /// position cells of the segment (the blend's error along l grows as 1 / |n . l|).
  static constexpr float kSettleReachCells = 2.f;
  /// A blended hit with n . l in [-kRefitCosine, -kGrazingCosine) is refitted on the line's
  /// own samples (step 6b of the .cpp overview).
  static constexpr float kRefitCosine = 0.8f;

  /// Paper section 5, see the .cpp overview. Contact per hb::Contact. Works on raw and
  /// compressed tables alike (the codec is dispatched once per query).
  Contact query(const Segment& segment, const ForceLaw& law) const noexcept override;

  /// Answers segments[0, count) into out[0, count), the same answers as query() bit for bit.
  /// The queries run in groups whose sample fetches all start before any is blended, so
  /// their memory latency overlaps: cheaper per query than query() when the table is not in
  /// cache (several contact points per tick, error fields, evaluations).
  void query_many(const Segment* segments, std::size_t count, const ForceLaw& law,
                  Contact* out) const noexcept override;

  /// As query(), and also the distance from the handle to the surface point along the
  /// segment (for scenes: the contact nearest the handle wins). Returns false and leaves
  /// `out.contact` false when there is no contact. `refine` limits the exact
  /// refinement (for callers that need only whether and roughly where a surface is).
  /// `refined`, when given, is set to whether the answer came from the exact triangles
  /// (false: the blended samples alone, unconfirmed by refinement).
  /// `triangle`, when given, receives the surface slot of the triangle a refined answer came
  /// from (kNoTriangle otherwise).
  /// `quads`, when given, keeps a block-coded table's decoded quads from one call to the next
  /// (DecodedQuads; the same answers bit for bit, decoded once while the cells stay).
  bool query_into(const Segment& segment, const ForceLaw& law, Contact& out,
                  float& distance_from_handle, Refine refine = Refine::all, bool* refined = nullptr,
                  std::uint32_t* triangle = nullptr, DecodedQuads* quads = nullptr) const noexcept;

  /// The answer of a refining box from a known triangle (a probe's last contact): the
  /// segment's line from the box entry P1, as in query_into, against `triangle`, walking at
  /// most `max_steps` edges from it to the triangle it crosses; a contact when that crossing
  /// is a front face on the segment (the contact test of query_into, same force law).
  /// No samples are read. False (no contact claimed) when the box does not refine, the line
  /// misses the box, the walk fails or the crossing is no contact. `crossed` receives the
  /// triangle crossed.
  bool query_near(const Segment& segment, const ForceLaw& law, std::uint32_t triangle, int max_steps, Contact& out,
                  float& distance_from_handle, std::uint32_t* crossed) const noexcept;

  /// The answer of a refining box from its triangle ids alone (no sample is read or
  /// decoded): the candidates of step 7 at the located cell, the nearest front-face crossing
  /// among them (or the bounded walk from the one the line passes nearest) with no blended t
  /// to agree with, then the contact test of step 6. What query_into(..., Refine::all)
  /// returns when its refinement confirms a contact and the blend is not consulted; a scene
  /// (which never answers with an unconfirmed blend) routes a probe's
  /// box query here (box_scene.cpp). False (no contact) when the box does not refine, the
  /// line misses the box, no sample of the cell hit, or the crossing is no contact.
  bool query_refined(const Segment& segment, const ForceLaw& law, Contact& out, float& distance_from_handle,
                     std::uint32_t* triangle = nullptr) const noexcept;

  const Obb& obb() const { return obb_; }
  const BoxParams& params() const { return params_; }
  /// The raw records, or nullptr when the table is compressed.
  const Sample* table() const { return table_; }
  /// The table in whatever codec it is stored.
  const SampleTable& samples() const { return samples_; }
  /// What keeps the table alive (shared by copies; null for a table owned elsewhere): a
  /// probe's kept decode (DecodedQuads) is this table's while its owner is.
  const std::shared_ptr<const void>& table_owner() const { return owner_; }
  CodecId codec() const { return samples_.codec(); }
  /// Compression statistics (zero for a raw table, except the byte counts).
  const CodecStats& codec_stats() const { return stats_; }
  /// Bytes of the stored table (compressed payload, or 8 bytes a sample when raw).
  std::size_t table_bytes() const { return samples_.bytes(); }
  /// Bytes of the table uncompressed (0 for a frame).
  std::size_t raw_table_bytes() const { return has_table() ? params_.sample_count() * sizeof(Sample) : 0u; }

  /// Where the samples are, in space and in the table (box_layout.h).
  const BoxLayout& layout() const { return layout_; }

private:
  // Throws hb::InvalidInput when the box cannot be queried (obb_problem, m or n too large).
  void check_geometry() const;
  // The query in two phases (see the .cpp): locate() runs the geometry and starts the
  // sample fetches, finish() blends the samples, refines and tests the contact.
  template <class Fetch> struct Located;
  template <class Fetch>
  bool locate(const Fetch& fetch, const Segment& segment, Located<Fetch>& q) const noexcept;
  template <class Fetch>
  bool blend(const Fetch& fetch, const Located<Fetch>& q, float& t0, float& nx, float& ny, float& nz,
             int& corners_hit, bool any_hit) const noexcept;
  template <class Fetch>
  int surface_points(const Fetch& fetch, Located<Fetch>& q, OrientedPoint out[16]) const noexcept;
  // The largest position cell's side, model units (the settle's unit of length).
  float position_cell() const noexcept {
    const BoxLayout::Local& L = layout_.local();
    return 1.f / std::min(std::min(L.grid_scale[0], L.grid_scale[1]), L.grid_scale[2]);
  }
  template <class Fetch>
  bool refit_on_own_samples(const Fetch& fetch, const Located<Fetch>& q, const Vec3& p1, const Vec3& l, float& t0,
                            float& nx, float& ny, float& nz) const noexcept;
  template <class Fetch>
  bool settle_grazing(const Fetch& fetch, float p1x, float p1y, float p1z, float lx, float ly, float lz, float& t0,
                      float& nx, float& ny, float& nz) const noexcept;
  template <class Fetch>
  bool finish(const Fetch& fetch, const Located<Fetch>& q, const ForceLaw& law, Contact& out,
              float& distance_from_handle, Refine refine, bool* refined = nullptr,
              std::uint32_t* triangle = nullptr) const noexcept;
  template <class Fetch>
  void query_many_with(const Fetch& fetch, const Segment* segments, std::size_t count, const ForceLaw& law,
                       Contact* out) const noexcept;
  // query_many's path for raw tables without refinement: several queries side by side in
  // SIMD lanes, the same arithmetic as query() (query_lanes.cpp).
  void query_many_lanes(const Segment* segments, std::size_t count, const ForceLaw& law, Contact* out) const noexcept;
  bool refine(std::size_t p00, int a0, int b0, std::size_t sf, const float p1[3], const float l[3], float t_blend,
              float& t0, Vec3& normal, std::uint32_t& triangle) const noexcept;
  // refine()'s steps (haptic_box.cpp).
  struct RefineHit;
  bool refine_accepts(float s, bool front, float t_blend) const noexcept;
  int refine_candidates(std::size_t p00, int a0, int b0, std::size_t sf, std::uint32_t candidates[16]) const noexcept;
  bool refine_walks(std::uint32_t start, const std::uint32_t* candidates, int count, const float p1[3], const float l[3],
                    float t_blend, RefineHit& best) const noexcept;
  template <class Fetch>
  bool query_with(const Fetch& fetch, const Segment& segment, const ForceLaw& law, Contact& out,
                  float& distance_from_handle, Refine refine, bool* refined = nullptr,
                  std::uint32_t* triangle = nullptr) const noexcept;

  BoxLayout layout_;  // built from obb_ and params_ once they are checked
  Obb obb_;
  BoxParams params_;
  const Sample* table_ = nullptr;
  SampleTable samples_;
  CodecStats stats_;
  std::shared_ptr<const void> owner_;  // keeps the table alive; shared by copies
  TriangleIds triangle_ids_;
  std::shared_ptr<const void> ids_owner_;
  std::shared_ptr<const SurfaceTriangles> surface_;
  float refine_tolerance_ = 0.f;  // largest |refined t - blended t| accepted (attach_surface)
  bool walk_from_all_ = true;     // set_walk_all_candidates
  int long_walk_steps_ = 256;     // set_long_walk_steps
  bool nearest_first_ = true;     // set_nearest_first
};

} // namespace hb
