#include "recipe/raw_box_trial.h"
#include "recipe/route_rule.h"
#include "recipe/bake_recipe.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/query_timing.h"
#include "stability/stability_suite.h"
#include "exact/exact_query.h"
#include "stopwatch.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>

namespace hb {
namespace {

// T2's share of contact ticks perceptibly different, box against exact (-1 when T2 found
// no contact to judge).
double slide_ticks_felt(const BoxScene& scene, const TriangleMesh& mesh, const ExactQuery& exact) {
  StabilityOptions so;
  so.tests = {"T2"};
  so.generated = false;
  so.exact = &exact;
  for (const StabilityMetric& m : run_stability_suite(scene, mesh, so).metrics)
    if (m.test == "T2" && m.metric.rfind("share of contact ticks perceptibly different", 0) == 0) return m.box;
  return -1.0;
}

} // namespace

bool slides_hopeless(double screen_ticks_felt, const RawSampling& screen, const RawSampling& finest, double allowed_share) {
  if (!(screen_ticks_felt >= 0.0) || screen.m <= 0 || screen.n <= 0) return false;
  const double refine = std::max(double(finest.m) / double(screen.m), double(finest.n) / double(screen.n));
  return screen_ticks_felt / std::pow(refine, 5.0) > allowed_share;
}

float raw_codec_bound(const ForceLaw& law, const PerceptualThresholds& thresholds, double box_diagonal) {
  const double metres = box_diagonal * double(law.metres_per_unit);
  if (!(metres > 0.0) || !(law.stiffness_n_per_m > 0.f)) return 0.f;
  const double bound = 0.125 * thresholds.floor_n / (double(law.stiffness_n_per_m) * metres);
  return float(std::clamp(bound, 1e-5, 0.1));
}

std::string RawCandidate::describe() const {
  std::ostringstream os;
  os.precision(3);
  os << "m" << m << " n" << n << " " << outcome << ": " << probes_felt * 100.0 << "% of probes";
  if (light_felt >= 0) os << ", " << light_felt * 100.0 << "% of light touches";
  if (ticks_felt >= 0) os << ", " << ticks_felt * 100.0 << "% of slide ticks";
  os << " felt, " << bytes / 1e6 << " MB";
  if (box_ns > 0) os << ", " << box_ns << " ns against exact's " << exact_ns;
  if (box_stroke_ns > 0) os << ", along strokes " << box_stroke_ns << " ns against " << exact_stroke_ns;
  return os.str();
}

RawTrial try_raw_boxes(const TriangleMesh& mesh, const ExactQuery& exact, const std::vector<Segment>& probes,
                       const std::vector<Contact>& exact_answers, const ForceLaw& law, const BakeOptions& base,
                       const SourceInfo& source, const RawTrialOptions& o) {
  RawTrial trial;
  const auto stage = [&](const char* name, double seconds) {
    if (o.on_stage) o.on_stage(name, seconds);
  };
  std::unique_ptr<ExactQuery> timing_reference;  // exact with its best tree, as `bench` times it
  const std::vector<Segment> timed(probes.begin(), probes.begin() + std::min<std::size_t>(probes.size(), 5000));
  // Every sampling tried is timed, so the speed chart can place it (hb::bake_chart_rows): one
  // that failed against the bake's own exact reference (built already; the best tree is built
  // only for a sampling that may be kept, whose time decides), one core, random order.
  std::vector<Segment> strokes;  // sampled once, for the samplings that reach the stroke timing
  const auto time_against = [&](const BoxScene& scene, const ExactQuery& reference, RawCandidate& c) {
    const auto t = std::chrono::steady_clock::now();
    const PairedTiming speed = paired_query_ns(scene, reference, timed, law);
    c.box_ns = speed.a_ns, c.exact_ns = speed.b_ns;
    stage("raw_timing", seconds_since(t));
  };
  // One sampling judged: its scene when every test passed (outcome "kept").
  // `screen`: the slides are judged even when the probes failed (the screen's forecast below).
  const auto judge = [&](const RawSampling& s, RawCandidate& c, bool screen = false) -> std::optional<BoxScene> {
    c.m = s.m, c.n = s.n;
    auto t = std::chrono::steady_clock::now();
    BakeOptions bo = search_bake_options(base, nullptr);
    bo.params.m = s.m;
    bo.params.n = s.n;
    bo.density = PositionDensity{};
    bo.whole_mesh_bvh = &exact.scene();  // the exact reference's BVH of the full mesh
    BakeStats stats;
    BoxScene scene = bake_scene(mesh, {}, bo, source, &stats);
    if (o.codec_bound > 0.f && !scene.parts().boxes.empty()) {
      CodecOptions codec;
      codec.codec = CodecId::block;
      codec.max_error = o.codec_bound;
      scene = BoxScene(compressed(scene, codec));
    }
    c.bytes = double(scene.bytes().memory);
    stage("raw_tables", seconds_since(t));
    t = std::chrono::steady_clock::now();
    std::atomic<std::size_t> felt{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes.size(), 256), [&](const auto& r) {
      std::size_t local = 0;
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        local += perceive(exact_answers[i], scene.query(probes[i], law), o.thresholds, o.max_force_n).perceptible();
      felt += local;
    });
    c.probes_felt = probes.empty() ? 1.0 : double(felt) / double(probes.size());
    stage("raw_probes", seconds_since(t));
    const auto fails = [&](const char* outcome) {
      time_against(scene, exact, c);
      c.outcome = outcome;
      return std::nullopt;
    };
    if (c.probes_felt > o.allowed_share) {
      if (screen && o.slides && c.probes_felt <= o.hopeless_share) {
        t = std::chrono::steady_clock::now();
        c.ticks_felt = slide_ticks_felt(scene, mesh, exact);
        stage("raw_slides", seconds_since(t));
      }
      return fails("felt on probes");
    }
    if (c.bytes > o.memory_cap_bytes) return fails("over the memory cap");
    if (o.light_touches > 0) {
      t = std::chrono::steady_clock::now();
      const ComparisonStats light = compare_light_touches(scene, exact, mesh, o.light_touches, o.light_seed, law,
                                                          mesh.bounds().diagonal(), nullptr,
                                                          PerceptualJudge{o.thresholds, o.max_force_n});
      c.light_felt = light.perceptible_share;
      stage("raw_light_touches", seconds_since(t));
      if (c.light_felt > o.allowed_share) return fails("felt on light touches");
    }
    if (o.slides) {
      t = std::chrono::steady_clock::now();
      c.ticks_felt = slide_ticks_felt(scene, mesh, exact);
      stage("raw_slides", seconds_since(t));
      if (c.ticks_felt > o.allowed_share) return fails("felt on slides");
    }
    t = std::chrono::steady_clock::now();
    if (!timing_reference) timing_reference = std::make_unique<ExactQuery>(mesh, BvhBuild::best);
    stage("raw_timing", seconds_since(t));
    time_against(scene, *timing_reference, c);
    if (!clearly_faster_than_embree(c.box_ns, c.exact_ns)) return c.outcome = "slower than exact", std::nullopt;
    // Along strokes too, as a servo loop asks (one probe with its query state): a hand feels
    // trajectories, and a table that is faster at random can be slower there (a codec's
    // decode costs the same while exact's walk stays in cache: measured on the bumpy sphere,
    // m32 n16 block-coded, 2.3x faster than exact at random and 1.4x slower along strokes).
    t = std::chrono::steady_clock::now();
    if (strokes.empty()) strokes = sample_strokes(mesh, 10, 500, 0.02f);
    const SceneProbe probe(scene);
    const PairedTiming along = paired_query_ns(probe, *timing_reference, strokes, law);
    c.box_stroke_ns = along.a_ns, c.exact_stroke_ns = along.b_ns;
    stage("raw_timing", seconds_since(t));
    if (!not_slower_than_embree(c.box_stroke_ns, c.exact_stroke_ns))
      return c.outcome = "slower than exact on strokes", std::nullopt;
    c.outcome = "kept";
    trial.stats = stats;
    return scene;
  };
  const std::size_t count = o.samplings.size();
  if (count == 0) return trial;
  // The coarsest first, a cheap screen: a detailed model is felt on most probes there and no
  // sampling will do. Then the finest (the most accurate the cap allows: when it fails along
  // the slides or on the probes, the coarser ones fail too), and only when it serves, the
  // cheaper ones, coarse to fine, the first that serves kept.
  std::vector<std::size_t> order{0};
  if (count > 1) order.push_back(count - 1);
  for (std::size_t k = 1; k + 1 < count; ++k) order.push_back(k);
  std::optional<BoxScene> finest;
  RawCandidate finest_candidate;
  for (std::size_t step = 0; step < order.size(); ++step) {
    const std::size_t k = order[step];
    RawCandidate c;
    std::optional<BoxScene> scene = judge(o.samplings[k], c, step == 0);
    trial.tried.push_back(c);
    if (step == 0) {
      if (scene) {
        trial.scene = std::move(scene);  // the coarsest serves: nothing is cheaper
        return trial;
      }
      if (c.probes_felt > o.hopeless_share || c.outcome.rfind("slower than exact", 0) == 0) return trial;
      if (count > 1 && slides_hopeless(c.ticks_felt, o.samplings[0], o.samplings[count - 1], o.allowed_share)) {
        trial.tried.back().outcome = "felt on slides";
        return trial;
      }
      continue;
    }
    if (step == 1) {
      if (!scene) return trial;  // the finest does not serve: no sampling does
      if (count == 2) {
        trial.scene = std::move(scene);
        return trial;
      }
      finest = std::move(scene);
      finest_candidate = c;
      trial.tried.back().outcome = "serves";  // kept unless a cheaper one serves too
      continue;
    }
    if (scene) {
      trial.scene = std::move(scene);
      return trial;
    }
  }
  // No cheaper sampling served: the finest is kept.
  for (RawCandidate& c : trial.tried)
    if (c.outcome == "serves") c.outcome = "kept";
  trial.scene = std::move(finest);
  return trial;
}

} // namespace hb
