#pragma once
// The budgeted bake's first question: can the paper's raw haptic box serve this model so
// that no hand could tell it from exact? One box over the whole model, sampled coarse to fine,
// its table block-coded within a bound derived from the force threshold and the stiffness,
// is judged in the perceptual currency on the tuning probes and along the stability suite's
// slides (T2), then timed against exact Embree. The first sampling that nobody could feel,
// that fits the memory cap and that answers faster than exact is kept; a detailed model stops
// at the first sampling (most of its probes are felt), so asking costs one coarse bake.
#include "contact/contact.h"
#include "perception/perceptible.h"
#include "scene/bake.h"
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hb {

class ExactQuery;

/// One raw sampling: m position points a box face edge, n directional points.
struct RawSampling {
  int m = 0, n = 0;
};

/// What the trial needs from the budget and the workspace.
struct RawTrialOptions {
  /// Coarse to fine; the trial stops at the first that is kept, or that cannot be beaten
  /// by a finer one (over the memory cap, slower than exact, felt on most probes, or felt
  /// on more slide ticks than the finest could fix: slides_hopeless).
  std::vector<RawSampling> samplings = {{16, 8}, {24, 12}, {32, 16}};
  double allowed_share = 0.0008;        ///< perceptibly different share allowed (probes and ticks).
  double hopeless_share = 0.2;          ///< felt on more probes: a detailed model, stop.
  double memory_cap_bytes = 48e6;       ///< the raw scene's memory, at most.
  PerceptualThresholds thresholds;      ///< what a hand tells apart.
  double max_force_n = 8.0;             ///< forces judged clamped to the device's.
  /// The block codec's bound as a fraction of the box diagonal (0: no codec); see
  /// raw_codec_bound().
  float codec_bound = 0.f;
  bool slides = true;                   ///< also judge along T2's slides.
  /// Also judge on this many light touches at any angle (eval's second figure:
  /// compare_light_touches, within 85 degrees of the normal, tips up to 0.5% of the diagonal
  /// deep; 0: not judged), of seed `light_seed`: the tuning probes come within 30 degrees of
  /// the normal and miss a blend that is off along lines 37-53 degrees off it (docs/perception.md).
  std::size_t light_touches = 20000;
  std::uint64_t light_seed = 103;
  std::function<void(const std::string&, double)> on_stage;  ///< each step's seconds.
};

/// The screen's forecast along the slides: the coarsest sampling's share of slide ticks felt,
/// divided by the fifth power of the finest's refinement over it, is still above the allowed
/// share: no sampling up to the finest can serve, none is baked. Why the fifth power: with
/// the boxes block-coded at raw_codec_bound and grazing lines settled on a fitted quadric,
/// m16 n8 to m32 n16 takes the bumpy sphere from 1.57% to 0.039% (40x) and the smooth
/// ellipsoid from 1.32% to 0.039% (34x), about 2^5. (Settled by tangent-plane steps the fall
/// would be 9-11x, and without any settle the square of the refinement.)
bool slides_hopeless(double screen_ticks_felt, const RawSampling& screen, const RawSampling& finest, double allowed_share);

/// The codec bound (fraction of a box's diagonal) whose worst position error makes a force
/// error of at most an eighth of the force threshold F0 at the workspace's stiffness:
/// k d <= F0 / 8, d = bound x box diagonal x metres per unit. An eighth, not a half, for the
/// grazing lines of slides, where an error across the surface moves the crossing by it over
/// the cosine: measured on the bumpy sphere's m32 n16 (T2 slide ticks felt), F0 / 2 (0.017%
/// of the diagonal, 17.3 MB) 0.51%, F0 / 8 (19.2 MB) 0.22%, the raw table (151 MB) 0.17%.
float raw_codec_bound(const ForceLaw& law, const PerceptualThresholds& thresholds, double box_diagonal);

/// One sampling tried.
struct RawCandidate {
  int m = 0, n = 0;
  double bytes = 0;          ///< the scene's memory (coded tables).
  double probes_felt = 0;    ///< share of the tuning probes perceptibly different.
  double ticks_felt = -1;    ///< share of T2's slide ticks (-1: not judged).
  double light_felt = -1;    ///< share of the light touches at any angle (-1: not judged).
  /// One query of the raw box and of exact Embree beside it, random order, one core, on the
  /// first 5,000 tuning probes; every sampling tried is timed (the speed chart places each):
  /// against exact's best tree when it passed the accuracy tests (its time decides whether it
  /// is kept), else against the exact reference the trial was given.
  double box_ns = 0, exact_ns = 0;
  /// Along 10 hand-like strokes (sample_strokes: 500 ticks each), the scene through a
  /// SceneProbe (its query state) against exact, for a sampling that passed everything else
  /// and was faster at random (0: not timed). Kept only when faster here too.
  double box_stroke_ns = 0, exact_stroke_ns = 0;
  std::string outcome;       ///< "kept", "felt on probes", "felt on light touches", "felt on slides", "over the memory cap", "slower than exact", "slower than exact on strokes".
  /// "m16 n8 felt on probes: 4.5% of probes" style line.
  std::string describe() const;
};

struct RawTrial {
  std::optional<BoxScene> scene;  ///< the kept raw scene, if any.
  std::vector<RawCandidate> tried;
  BakeStats stats;                ///< of the kept scene's ray casting.
};

/// Runs the trial on the full mesh `mesh` (one box, no pieces), against `exact` (its exact
/// answers `exact_answers` on `probes` at `law`). `base` gives the bake's other options.
RawTrial try_raw_boxes(const TriangleMesh& mesh, const ExactQuery& exact, const std::vector<Segment>& probes,
                       const std::vector<Contact>& exact_answers, const ForceLaw& law, const BakeOptions& base,
                       const SourceInfo& source, const RawTrialOptions& options);

} // namespace hb
