// The stability suite (stability_suite.h).
// 1. Calibration gate: free bounces and prescribed strokes on an AnalyticWall must give the
//    reference simulation's figures (docs/stability.md), else the harness is wrong
//    (stability_calibration.cpp).
// 2. Scenes: the model (its box against exact Embree on its mesh, OBB diagonal mapped to
//    80 mm) and, optionally, generated objects in mm (a wall, plates, V-grooves;
//    stability_objects.cpp), each baked into a box here with the model box's refinement.
// 3. Sites on the model: surface points by area (sample_probes), kept when exact Embree
//    answers a 1 mm-deep probe along the inward normal there.
// 4. Tests T1-T8 (stability_tests.cpp), each a trajectory run on the box and on
//    exact, the same trajectory for both; every figure becomes a StabilityMetric judged
//    against its threshold, for the box and for exact (a failure exact shares is the law's).
// 5. Ranks: the gate and each (scene, test) pair are tasks dealt to the ranks in turn; every
//    rank receives every task's figures and traces and assembles them in task order, so the
//    report is the one process's (StabilityOptions::communicator).
#include "stability/stability_harness.h"
#include "scene/scene_extent.h"
#include "errors.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "parallel/byte_buffer.h"
#include "parallel/work_split.h"
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>

namespace hb {
namespace {

// One rank's share of the suite travels as: per task, its metrics then its traces.
void put_metrics(ByteWriter& w, const std::vector<StabilityMetric>& ms) {
  w.put(std::uint64_t(ms.size()));
  for (const StabilityMetric& m : ms) {
    for (const std::string* t : {&m.test, &m.scene, &m.metric, &m.unit, &m.verdict}) w.put_string(*t);
    w.put(m.box), w.put(m.exact), w.put(m.rule), w.put(m.threshold), w.put(m.tolerance);
    w.put(std::uint8_t(m.pass)), w.put(std::uint8_t(m.exact_pass));
  }
}

std::vector<StabilityMetric> get_metrics(ByteReader& r) {
  std::vector<StabilityMetric> ms(r.get<std::uint64_t>());
  for (StabilityMetric& m : ms) {
    for (std::string* t : {&m.test, &m.scene, &m.metric, &m.unit, &m.verdict}) *t = r.get_string();
    m.box = r.get<double>(), m.exact = r.get<double>(), m.rule = r.get<StabilityRule>();
    m.threshold = r.get<double>(), m.tolerance = r.get<double>();
    m.pass = r.get<std::uint8_t>() != 0, m.exact_pass = r.get<std::uint8_t>() != 0;
  }
  return ms;
}

void put_traces(ByteWriter& w, const std::vector<ForceTrace>& ts) {
  w.put(std::uint64_t(ts.size()));
  for (const ForceTrace& t : ts) {
    w.put_string(t.test), w.put_string(t.scene), w.put_string(t.label);
    w.put_vector(t.t_s), w.put_vector(t.box_n), w.put_vector(t.exact_n);
  }
}

std::vector<ForceTrace> get_traces(ByteReader& r) {
  std::vector<ForceTrace> ts(r.get<std::uint64_t>());
  for (ForceTrace& t : ts) {
    t.test = r.get_string(), t.scene = r.get_string(), t.label = r.get_string();
    t.t_s = r.get_vector<double>(), t.box_n = r.get_vector<double>(), t.exact_n = r.get_vector<double>();
  }
  return ts;
}

using stability::Scene;
using stability::Site;
using stability::Suite;

// The scenes the tests run on, made on first use: the model (its sites picked the first
// time a test asks) and the generated objects, baked with the model box's settings.
class SuiteScenes {
public:
  struct Generated {
    std::string name;
    TriangleMesh mesh;
    std::unique_ptr<BoxScene> box;
    std::unique_ptr<ExactQuery> exact;
  };

  // Every rank fits the model and picks the same sites: both are deterministic.
  SuiteScenes(const BoxScene& box, const TriangleMesh& mesh, const StabilityOptions& o)
      : box_(box), mesh_(mesh), o_(o), exact_(o.exact ? *o.exact : own_exact_.emplace(mesh)) {
    model_.name = o.model_name;
    model_.box = &box;
    model_.exact = &exact_;
    model_.box_scene = &box;
    model_.workspace = scene_workspace(box, o.workspace);  // the scale `hapticbox servo` runs this box at
    bake_.params.m = o.generated_m;
    bake_.params.n = o.generated_n;
    bake_.refine = o.generated_refine;
  }

  const Scene& model(Suite& suite) {
    if (!sites_picked_) {
      model_.sites = stability::pick_sites(mesh_, exact_, model_.workspace, suite.law(model_, suite.k_half()), o_.sites, o_.seed, o_.stylus_m);
      sites_picked_ = true;
    }
    return model_;
  }

  const Scene& wall() {
    if (!wall_) {
      wall_ = make("flat wall", stability::extrude({{-20, -10}, {20, -10}, {20, 0}, {-20, 0}}, 20.f, 8));
      wall_scene_ = scene_of(*wall_);
      for (double x : {-3.1, 0.0, 2.7, 5.3}) wall_scene_.sites.push_back(Site{Vec3d(x * 1e-3, 1.3e-3 * x, 0), Vec3d(0, 0, -1)});
    }
    return wall_scene_;
  }

  // A generated object baked with the model box's settings and its exact reference.
  std::unique_ptr<Generated> make(std::string name, TriangleMesh m) const {
    auto g = std::make_unique<Generated>();
    g->name = std::move(name);
    g->mesh = std::move(m);
    SceneParts parts = bake_scene(g->mesh, {}, bake_, SourceInfo{}).parts();
    // The model's route where the generated scene can take it (an embree route needs a
    // surface; a generated scene without one keeps its own).
    if (box_.route() != SceneRoute::embree || parts.surface) parts.route = box_.route();
    const bool walk_all = box_.parts().boxes.empty() || box_.parts().boxes[0].walk_all_candidates();
    for (HapticBox& b : parts.boxes) b.set_walk_all_candidates(walk_all);
    g->box = std::make_unique<BoxScene>(std::move(parts));
    g->exact = std::make_unique<ExactQuery>(g->mesh);
    return g;
  }

  static Scene scene_of(const Generated& g) {
    Scene sc;
    sc.name = g.name;
    sc.box = g.box.get();
    sc.exact = g.exact.get();
    sc.box_scene = g.box.get();
    sc.workspace.metres_per_unit = 0.001;  // mm (the objects are centred at the origin)
    return sc;
  }

private:
  const BoxScene& box_;
  const TriangleMesh& mesh_;
  const StabilityOptions& o_;
  std::optional<ExactQuery> own_exact_;
  const ExactQuery& exact_;
  Scene model_;
  bool sites_picked_ = false;
  BakeOptions bake_;
  std::unique_ptr<Generated> wall_;
  Scene wall_scene_;
};

using SuiteTask = std::function<void(Suite&)>;

// The tasks, in the order of the report: the calibration gate, the model's tests, then the
// generated objects'.
std::vector<SuiteTask> suite_tasks(SuiteScenes& scenes, const StabilityOptions& o) {
  const Suite wanted(o);
  std::vector<SuiteTask> tasks;
  tasks.push_back([&](Suite& s) { s.out_ = run_calibration(o.device); });
  if (wanted.want("T1")) tasks.push_back([&](Suite& s) { s.t1(scenes.model(s)); });
  if (wanted.want("T2")) tasks.push_back([&](Suite& s) { s.t2(scenes.model(s)); });
  if (wanted.want("T5")) tasks.push_back([&](Suite& s) { s.t5(scenes.model(s), true); });
  if (wanted.want("T6")) tasks.push_back([&](Suite& s) { s.t6(scenes.model(s)); });
  if (wanted.want("T7")) tasks.push_back([&](Suite& s) { s.t7(scenes.model(s)); });
  if (wanted.want("T8")) tasks.push_back([&](Suite& s) { s.t8(scenes.model(s)); });
  if (!o.generated) return tasks;
  if (wanted.want("T1")) tasks.push_back([&](Suite& s) { s.t1(scenes.wall()); });
  if (wanted.want("T5")) tasks.push_back([&](Suite& s) { s.t5(scenes.wall(), false); });
  if (wanted.want("T7")) tasks.push_back([&](Suite& s) { s.t7(scenes.wall()); });
  if (wanted.want("T8")) tasks.push_back([&](Suite& s) { s.t8(scenes.wall()); });
  if (wanted.want("T3"))
    for (double h : {0.25, 0.5, 1.0, 2.0})
      tasks.push_back([&scenes, h](Suite& s) {
        char name[32];
        std::snprintf(name, sizeof name, "plate %.2f mm", h);
        const auto g = scenes.make(name, make_plate(float(h)));
        s.t3(SuiteScenes::scene_of(*g), h);
      });
  if (wanted.want("T4"))
    for (double deg : {60.0, 90.0, 120.0})
      for (bool welded : {false, true})
        tasks.push_back([&scenes, deg, welded](Suite& s) {
          const std::string name = std::to_string(int(deg)) + " deg groove, " + (welded ? "welded" : "crisp");
          const auto g = scenes.make(name, make_v_groove(float(deg), welded));
          s.t4(SuiteScenes::scene_of(*g));
        });
  return tasks;
}

// Every task's figures and traces, in task order.
struct TaskResults {
  std::vector<std::vector<StabilityMetric>> metrics;
  std::vector<std::vector<ForceTrace>> traces;
};

// Each task runs into a Suite of its own; with several ranks they are dealt in turn (task k
// on rank k % ranks) and every rank receives every result: the report of one process.
TaskResults run_tasks(const std::vector<SuiteTask>& tasks, const StabilityOptions& o, Communicator& comm) {
  const DealtChunks deal{tasks.size(), 1, comm.size()};
  TaskResults res;
  res.metrics.resize(tasks.size());
  res.traces.resize(tasks.size());
  ByteWriter mine;
  try {
    deal.for_each_of(comm.rank(), [&](std::size_t k, std::size_t) {
      Suite suite(o);
      tasks[k](suite);
      res.metrics[k] = std::move(suite.out_);
      res.traces[k] = std::move(suite.traces_);
      if (comm.size() > 1) put_metrics(mine, res.metrics[k]), put_traces(mine, res.traces[k]);
    });
  } catch (const std::exception& e) {
    if (comm.size() == 1) throw;
    comm.abort("hapticbox: rank " + std::to_string(comm.rank()) + " of " + std::to_string(comm.size()) +
                   ": stability suite: " + e.what(),
               1);
  }
  if (comm.size() > 1) {
    const std::vector<Bytes> all = comm.all_gather(mine.bytes());
    for (int r = 0; r < comm.size(); ++r) {
      ByteReader in(all[std::size_t(r)], "run_stability_suite: rank " + std::to_string(r));
      deal.for_each_of(r, [&](std::size_t k, std::size_t) {
        res.metrics[k] = get_metrics(in);
        res.traces[k] = get_traces(in);
      });
    }
  }
  return res;
}

// The gate's figures (task 0), then every test's, counted.
void assemble(StabilityReport& rep, TaskResults& res) {
  rep.calibration = std::move(res.metrics[0]);
  rep.calibration_pass = std::all_of(rep.calibration.begin(), rep.calibration.end(), [](auto& m) { return m.pass; });
  for (std::size_t k = 1; k < res.metrics.size(); ++k) {
    rep.metrics.insert(rep.metrics.end(), std::make_move_iterator(res.metrics[k].begin()),
                       std::make_move_iterator(res.metrics[k].end()));
    rep.traces.insert(rep.traces.end(), std::make_move_iterator(res.traces[k].begin()),
                      std::make_move_iterator(res.traces[k].end()));
  }
  for (const auto& m : rep.metrics) {
    if (m.rule == StabilityRule::info) continue;
    if (m.pass) ++rep.passed;
    else ++rep.failed, rep.failed_law += !m.exact_pass;
  }
}

} // namespace

StabilityReport run_stability_suite(const BoxScene& box, const TriangleMesh& mesh, const StabilityOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  for (const std::string& t : o.tests)
    if (t.size() != 2 || t[0] != 'T' || t[1] < '1' || t[1] > '8')
      throw InvalidInput("stability test '" + t + "': expected T1 .. T8");
  if (mesh.triangle_count() == 0) throw InvalidInput("stability suite: the mesh has no triangles");
  Communicator& comm = communicator_or_serial(o.communicator);
  StabilityReport rep;
  rep.device = o.device.name;
  rep.filter = o.filter_name;
  rep.depth_law = o.depth_law == DepthLaw::normal ? "normal" : "along_segment";
  rep.contact_law = to_string(o.contact_law);
  SuiteScenes scenes(box, mesh, o);
  const std::vector<SuiteTask> tasks = suite_tasks(scenes, o);
  TaskResults results = run_tasks(tasks, o, comm);
  assemble(rep, results);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

StabilityOptions default_stability_options(const BoxScene& scene, const std::string& model_name, std::size_t sites) {
  StabilityOptions so;
  so.sites = sites;
  so.generated_refine = scene.refines();
  so.model_name = model_name;
  return so;
}

} // namespace hb
