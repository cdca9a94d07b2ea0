#include "recipe/raw_box_trial.h"
#include "evaluation/query_timing.h"
#include "evaluation/stability_suite.h"
#include "exact/exact_query.h"
#include "stopwatch.h"
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <atomic>
#include <chrono>
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

float raw_codec_bound(const ForceLaw& law, const PerceptualThresholds& thresholds, double box_diagonal) {
  const double metres = box_diagonal * double(law.metres_per_unit);
  if (!(metres > 0.0) || !(law.stiffness_n_per_m > 0.f)) return 0.f;
  const double bound = 0.5 * thresholds.floor_n / (double(law.stiffness_n_per_m) * metres);
  return float(std::clamp(bound, 1e-5, 0.1));
}

std::string RawCandidate::describe() const {
  std::ostringstream os;
  os.precision(3);
  os << "m" << m << " n" << n << " " << outcome << ": " << probes_felt * 100.0 << "% of probes";
  if (ticks_felt >= 0) os << ", " << ticks_felt * 100.0 << "% of slide ticks";
  os << " felt, " << bytes / 1e6 << " MB";
  if (box_ns > 0) os << ", " << box_ns << " ns against exact's " << exact_ns;
  return os.str();
}

RawTrial try_raw_boxes(const TriangleMesh& mesh, const ExactQuery& exact, const std::vector<Segment>& probes,
                       const std::vector<Contact>& exact_answers, const ForceLaw& law, const BakeOptions& base,
                       const SourceInfo& source, const RawTrialOptions& o) {
  RawTrial trial;
  const auto stage = [&](const char* name, double seconds) {
    if (o.on_stage) o.on_stage(name, seconds);
  };
  for (const RawSampling& s : o.samplings) {
    RawCandidate c;
    c.m = s.m, c.n = s.n;
    auto t = std::chrono::steady_clock::now();
    BakeOptions bo = base;
    bo.params.m = s.m;
    bo.params.n = s.n;
    bo.density = PositionDensity{};
    bo.refine = false;
    bo.surface = nullptr;
    bo.scene_grid = false;
    bo.communicator = nullptr;
    bo.progress = nullptr;
    BakeStats stats;
    BoxScene scene = bake_scene(mesh, {}, bo, source, &stats);
    if (o.codec_bound > 0.f && !scene.boxes().empty()) {
      CodecOptions codec;
      codec.codec = CodecId::block;
      codec.max_error = o.codec_bound;
      scene = scene.compressed(codec);
    }
    c.bytes = double(scene.memory_bytes());
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
    if (c.probes_felt > o.allowed_share) {
      c.outcome = "felt on probes";
      trial.tried.push_back(c);
      if (c.probes_felt > o.hopeless_share) break;  // a detailed model: no sampling will do
      continue;
    }
    if (c.bytes > o.memory_cap_bytes) {
      c.outcome = "over the memory cap";
      trial.tried.push_back(c);
      break;  // a finer sampling is larger still
    }
    if (o.slides) {
      t = std::chrono::steady_clock::now();
      c.ticks_felt = slide_ticks_felt(scene, mesh, exact);
      stage("raw_slides", seconds_since(t));
      if (c.ticks_felt > o.allowed_share) {
        c.outcome = "felt on slides";
        trial.tried.push_back(c);
        continue;
      }
    }
    t = std::chrono::steady_clock::now();
    const std::vector<Segment> timed(probes.begin(), probes.begin() + std::min<std::size_t>(probes.size(), 5000));
    const PairedTiming speed = paired_query_ns(scene, exact, timed, law);
    c.box_ns = speed.a_ns, c.exact_ns = speed.b_ns;
    stage("raw_timing", seconds_since(t));
    if (!(c.box_ns < c.exact_ns)) {
      c.outcome = "slower than exact";
      trial.tried.push_back(c);
      break;  // a finer sampling is not faster
    }
    c.outcome = "kept";
    trial.tried.push_back(c);
    trial.scene = std::move(scene);
    trial.stats = stats;
    break;
  }
  return trial;
}

} // namespace hb
