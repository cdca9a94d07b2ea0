// Tool slides and their judgement.
//  1. A slide starts at an area-weighted random surface point p with face normal n, the tool in
//     a random orientation (turning about a random axis at 1 rad/s), its centre where its
//     lowest point along -n is just above p.
//  2. Each tick: the pose is recorded (once the tool touches), exact answers it, the centre
//     moves along exact's resolving translation by (penetration - depth) (out of contact: down
//     along the last normal by a tick's travel), then along the tangent of the slide's
//     direction by a tick's travel.
//  3. Judging: per tick both answers, perceive_tool; a jump is a tick whose net force differs
//     perceptibly from the same method's previous tick.
#include "evaluation/tool_ticks.h"
#include "errors.h"
#include "mesh/surface_sampler.h"
#include "mesh/triangle_mesh.h"
#include "tool/tool_verdict.h"
#include <tbb/parallel_for.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <random>

namespace hb {
namespace {

constexpr double kTick = 1e-3;              // s
constexpr double kTurnRadPerS = 1.0;        // the tool's slow turn during a slide

Eigen::Quaternionf random_orientation(std::mt19937_64& rng) {
  std::normal_distribution<float> g(0.f, 1.f);
  Eigen::Quaternionf q(g(rng), g(rng), g(rng), g(rng));
  return q.norm() > 1e-6f ? q.normalized() : Eigen::Quaternionf::Identity();
}

Vec3 any_tangent(const Vec3& n, std::mt19937_64& rng) {
  std::normal_distribution<float> g(0.f, 1.f);
  for (int tries = 0; tries < 16; ++tries) {
    Vec3 d(g(rng), g(rng), g(rng));
    d -= n * n.dot(d);
    if (d.norm() > 1e-3f) return d.normalized();
  }
  return n.unitOrthogonal();
}

} // namespace

std::vector<std::vector<ToolPose>> tool_slides(const TriangleMesh& mesh, const ContactQuery& exact, const ToolShape& tool,
                                               const Workspace& workspace, const ToolSlideOptions& options) {
  if (options.slides == 0 || options.ticks == 0 || options.slides * options.ticks > 10000000)
    throw InvalidInput("tool slides: give 1 or more slides and ticks (at most 10,000,000 ticks in all)");
  if (!(options.speed_m_per_s > 0.0 && options.speed_m_per_s <= 1.0) || !(options.depth_m > 0.0 && options.depth_m <= 0.01))
    throw InvalidInput("tool slides: speed must be in (0, 1] m/s and depth in (0, 10] mm");
  if (mesh.triangle_count() == 0) throw InvalidInput("tool slides: the mesh has no triangles");
  const SurfaceSampler sampler(mesh, "tool slides");
  const double mpu = workspace.metres_per_unit;
  const float step = float(options.speed_m_per_s * kTick / mpu), depth = float(options.depth_m / mpu);
  const ForceLaw law = workspace.law();
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  ToolProbe probe(tool, mpu);
  std::vector<std::vector<ToolPose>> slides;
  for (std::size_t s = 0; s < options.slides; ++s) {
    Vec3 p, n;
    const double r = uniform(rng), u = uniform(rng), v = uniform(rng);
    sampler.sample(r, u, v, p, n);
    const Eigen::Quaternionf start = random_orientation(rng);
    const Vec3 axis = any_tangent(Vec3::UnitZ(), rng);
    Vec3 direction = any_tangent(n, rng);
    ToolPose pose;
    pose.orientation = start;
    float support = 0.f;  // how far the tool reaches below its centre along -n
    for (const Vec3& q : tool.points) support = std::max(support, -n.dot(start * q) / float(mpu));
    pose.position = p + n * (support + 0.25f * depth);
    std::vector<ToolPose> ticks;
    for (std::size_t it = 0; it < 4 * options.ticks && ticks.size() < options.ticks; ++it) {
      const ToolAnswer answer = probe.answer(exact, pose, law);
      const float pen = answer.translation.norm();
      if (answer.contacts > 0 || !ticks.empty()) ticks.push_back(pose);
      if (answer.contacts > 0 && pen > 0.f) {
        n = answer.translation / pen;
        pose.position += n * std::max(-step, std::min(step, pen - depth));
      } else {
        pose.position -= n * step;
      }
      direction -= n * n.dot(direction);
      direction = direction.norm() > 1e-3f ? Vec3(direction.normalized()) : any_tangent(n, rng);
      pose.position += direction * step;
      pose.orientation = Eigen::Quaternionf(Eigen::AngleAxisf(float(kTurnRadPerS * kTick * double(it + 1)), axis)) * start;
    }
    if (!ticks.empty()) slides.push_back(std::move(ticks));
  }
  return slides;
}

ToolTickStats compare_tool_ticks(const ContactQuery& approx, const ContactQuery& exact, const ToolShape& tool,
                                 const std::vector<std::vector<ToolPose>>& slides, const Workspace& workspace,
                                 const PerceptualThresholds& thresholds) {
  ToolTickStats total;
  double force_error_sum = 0.0, contacts_sum = 0.0;
  std::mutex mutex;
  const ForceLaw law = workspace.law();
  tbb::parallel_for(std::size_t(0), slides.size(), [&](std::size_t s) {
    ToolProbe box_probe(tool, workspace.metres_per_unit), exact_probe(tool, workspace.metres_per_unit);
    ToolTickStats local;
    double error_sum = 0.0, contacts = 0.0;
    ToolAnswer last_box, last_exact;
    for (std::size_t t = 0; t < slides[s].size(); ++t) {
      const ToolAnswer e = exact_probe.answer(exact, slides[s][t], law);
      const ToolAnswer b = box_probe.answer(approx, slides[s][t], law);
      ++local.ticks;
      if (t > 0) {
        local.box_jumps += perceive(as_contact(last_box), as_contact(b), thresholds, workspace.max_force_n).perceptible();
        local.exact_jumps += perceive(as_contact(last_exact), as_contact(e), thresholds, workspace.max_force_n).perceptible();
      }
      last_box = b;
      last_exact = e;
      if (e.contacts == 0 && b.contacts == 0) continue;
      ++local.contact_ticks;
      contacts += double(e.contacts);
      const ToolDifference d = perceive_tool(e, b, thresholds, workspace.max_force_n, tool.radius_m);
      local.force_felt += d.force.perceptible();
      local.torque_felt += d.torque_felt;
      local.perceptible_ticks += d.perceptible();
      const double fe = double((b.force - e.force).norm());
      error_sum += fe;
      local.max_force_error_n = std::max(local.max_force_error_n, fe);
      local.max_torque_error_nm = std::max(local.max_torque_error_nm, d.torque_difference_nm);
    }
    std::lock_guard<std::mutex> lock(mutex);
    total.ticks += local.ticks;
    total.contact_ticks += local.contact_ticks;
    total.perceptible_ticks += local.perceptible_ticks;
    total.force_felt += local.force_felt;
    total.torque_felt += local.torque_felt;
    total.box_jumps += local.box_jumps;
    total.exact_jumps += local.exact_jumps;
    total.max_force_error_n = std::max(total.max_force_error_n, local.max_force_error_n);
    total.max_torque_error_nm = std::max(total.max_torque_error_nm, local.max_torque_error_nm);
    force_error_sum += error_sum;
    contacts_sum += contacts;
  });
  if (total.contact_ticks > 0) {
    total.mean_force_error_n = force_error_sum / double(total.contact_ticks);
    total.mean_contacts = contacts_sum / double(total.contact_ticks);
  }
  return total;
}

ToolTickTiming time_tool_ticks(const ContactQuery& query, const ToolShape& tool,
                               const std::vector<std::vector<ToolPose>>& slides, const Workspace& workspace, int rounds) {
  using clock = std::chrono::steady_clock;
  rounds = std::max(1, rounds);
  const ForceLaw law = workspace.law();
  ToolProbe probe(tool, workspace.metres_per_unit);
  std::size_t ticks = 0;
  for (const auto& s : slides) ticks += s.size();
  std::vector<float> times(ticks * std::size_t(rounds));
  for (int r = 0; r < rounds; ++r) {
    std::size_t i = 0;
    for (const auto& slide : slides)
      for (const ToolPose& pose : slide) {
        const auto t0 = clock::now();
        const ToolAnswer a = probe.answer(query, pose, law);
        const auto t1 = clock::now();
        asm volatile("" : : "r"(&a) : "memory");
        times[i * std::size_t(rounds) + std::size_t(r)] = float(std::chrono::duration<double, std::micro>(t1 - t0).count());
        ++i;
      }
  }
  std::vector<float> per_tick(ticks);
  for (std::size_t i = 0; i < ticks; ++i) {
    float* b = times.data() + i * std::size_t(rounds);
    std::nth_element(b, b + rounds / 2, b + rounds);
    per_tick[i] = b[rounds / 2];
  }
  ToolTickTiming out;
  out.ticks = ticks;
  if (ticks == 0) return out;
  std::sort(per_tick.begin(), per_tick.end());
  const auto at = [&](double q) { return double(per_tick[std::min(ticks - 1, std::size_t(q * double(ticks)))]); };
  out.p50_us = at(0.5);
  out.p99_us = at(0.99);
  out.max_us = double(per_tick.back());
  return out;
}

} // namespace hb
