#pragma once
// The error field: where on a model the approximation is wrong. Probes are aimed at points of
// the surface from a cone of directions; the exact and approximated answers are compared per
// point (paper 6.1.2's relative force error, mapped over the surface).
#include "contact/contact.h"
#include "perception/perceptible.h"
#include "mesh/triangle_mesh.h"
#include "parallel/communicator.h"
#include "progress.h"
#include <cstdint>
#include <vector>

namespace hb {

/// A point of the surface and its unit outward normal (the probe cone opens around -normal).
struct SurfacePoint {
  Vec3 position{Vec3::Zero()};
  Vec3 normal{Vec3::UnitZ()};
};

/// The mesh's vertices with their (shaded) vertex normals: one field value per vertex.
std::vector<SurfacePoint> surface_points_at_vertices(const TriangleMesh& mesh);

/// `count` points spread evenly over the surface: area-proportional (stratified over the
/// cumulative area, so dense and sparse regions get their share without clumping), each with
/// its triangle's flat normal. Deterministic for a seed. Throws hb::InvalidInput on an empty
/// or zero-area mesh.
std::vector<SurfacePoint> sample_surface_evenly(const TriangleMesh& mesh, std::size_t count,
                                                std::uint64_t seed = 1);

/// Options of compute_error_field. Lengths are fractions of `diagonal` (the mesh's
/// bounding-box diagonal); the defaults are those of sample_probes, so figures compare.
struct ErrorFieldOptions {
  int probes_per_point = 1;         ///< probes aimed at each point, >= 1.
  float cone_degrees = 30.f;        ///< max angle between a probe and the inward normal, [0, 89].
  float length_fraction = 0.10f;    ///< probe segment length.
  float max_depth_fraction = 0.03f; ///< tip past the point by a uniform depth in [0, this].
  std::uint64_t seed = 1;           ///< probes of point i depend on (seed, i) only.
  ForceLaw law;                     ///< the same force law for both answers (the workspace's).
  PerceptualThresholds thresholds;  ///< what a hand tells apart (hb::perceive).
  double max_force_n = 8.0;         ///< the device's force limit (forces felt clamped to it).
  /// Progress in [0, 1] from the calling thread; return false to cancel (throws hb::Cancelled).
  /// With several ranks, each rank reports its own share (rank 0's stands for the job).
  ProgressCallback progress;
  /// The ranks sharing the field (nullptr: this process alone). Every rank calls with the same
  /// points and queries; points are dealt to the ranks in chunks and each point's figures
  /// (52 bytes) travel once, to rank 0, which holds the whole field: the same numbers as one
  /// process. The other ranks return a field of size 0 (with `probes` and `seconds` set).
  Communicator* communicator = nullptr;
};

/// Per-point statistics over the probes aimed at that point. Force and direction errors are
/// over the probes where both answers are in contact, NaN where there is none (no data: a
/// renderer shows it as such rather than as zero error).
struct ErrorField {
  std::vector<Vec3> exact_force;        ///< mean exact force over the point's probes, N.
  std::vector<Vec3> approx_force;       ///< mean approximated force, N.
  std::vector<float> force_error;       ///< mean relative |F1 - F0| / |F0|, NaN when no data.
  /// Mean absolute |F1 - F0| over all the point's probes, N (a probe out of contact has zero
  /// force): defined everywhere, missed and false contacts included.
  std::vector<float> force_error_newtons;
  std::vector<float> direction_error;   ///< mean angle between the normals, degrees, NaN when no data.
  std::vector<float> contact_disagreement; ///< fraction of probes whose contact flags differ, [0, 1].
  std::vector<float> exact_contact_fraction; ///< fraction of probes in exact contact, [0, 1].
  /// The largest difference over its threshold among the point's probes (hb::perceive's
  /// ratio; 1 = at the threshold, so a colour scale anchored at 1 shows nothing a hand
  /// cannot feel), and the fraction of its probes whose difference is perceptible.
  std::vector<float> perceptible_ratio;
  std::vector<float> perceptible_fraction;
  std::size_t probes = 0;               ///< total probes run.
  double seconds = 0.0;                 ///< wall time of the computation.
  std::size_t size() const { return force_error.size(); }
};

/// Aims `options.probes_per_point` probes at each point (tip past the point along a direction
/// within the cone around -normal, handle one segment length back: the distribution of
/// sample_probes, centred on the given points; each aimed 1e-4 diagonal beside the point in its
/// tangent plane, since a ray through a mesh vertex exactly can slip between its triangles), answers each with `exact` and `approx`, and
/// reduces per point. Runs on all cores (TBB); deterministic for a seed whatever the threads.
/// Throws hb::InvalidInput (bad options, diagonal <= 0) or hb::Cancelled.
ErrorField compute_error_field(const ContactQuery& approx, const ContactQuery& exact,
                               const std::vector<SurfacePoint>& points, float diagonal,
                               const ErrorFieldOptions& options = {});

/// The probe segments compute_error_field aims at `point`, the field's point `index` (the same
/// directions, aims and depths, from (options.seed, index)): how a viewer puts the probe where
/// the field measured an error.
std::vector<Segment> error_field_probes(const SurfacePoint& point, std::size_t index, float diagonal,
                                        const ErrorFieldOptions& options = {});

/// One metric of an error field summed up (the window's error-field panel): how many points
/// have data (finite values), how many do not (NaN), how many are above zero (for the contact
/// disagreement: the points where the answers disagree), the median of the finite values, and
/// the `worst_count` points with the largest values above zero, largest first (ties by index).
struct ErrorValuesSummary {
  std::size_t with_data = 0;
  std::size_t no_data = 0;
  std::size_t above_zero = 0;
  double median = 0.0;              ///< of the finite values (the upper median); 0 when none.
  std::vector<std::size_t> worst;   ///< point indices.
};
ErrorValuesSummary summarize_error_values(const std::vector<float>& values, std::size_t worst_count);

} // namespace hb
