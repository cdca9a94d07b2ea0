// hapticbox.perceive (the perceptual verdict of two answers, hb::perceive) and
// hapticbox.evaluate (eval's figures: hb::compare_queries and hb::compare_light_touches on the
// same probes as `hapticbox eval`, its JSON through hb::eval_json).
#include "arrays.h"
#include "bindings.h"
#include "eval_json.h"
#include "evaluation/probe_sampling.h"
#include "scene_access.h"
#include <pybind11/numpy.h>
#include <cstring>
#include <vector>

namespace hb::python {

namespace {

py::dict perceive_arrays(py::handle exact, py::handle box, const py::object& workspace, const std::string& perceptual) {
  const std::vector<Contact> e = contacts_from_dict(exact, "exact"), b = contacts_from_dict(box, "box");
  if (e.size() != b.size())
    throw py::value_error("exact and box: answers to different probe counts (" + std::to_string(e.size()) + " and " +
                          std::to_string(b.size()) + ")");
  const PerceptualJudge judge = judge_of(workspace, perceptual);
  const py::ssize_t n = py::ssize_t(e.size());
  py::array_t<bool> perceptible(n);
  py::array_t<std::uint8_t> by(n);
  py::array_t<double> ratio(n), magnitude(n), threshold(n), angle(n);
  bool* p = perceptible.mutable_data();
  std::uint8_t* y = by.mutable_data();
  double *r = ratio.mutable_data(), *mg = magnitude.mutable_data(), *t = threshold.mutable_data(), *a = angle.mutable_data();
  {
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < e.size(); ++i) {
      const PerceivedDifference d = hb::perceive(e[i], b[i], judge.thresholds, judge.max_force_n);
      p[i] = d.perceptible();
      y[i] = d.by;
      r[i] = d.ratio;
      mg[i] = d.magnitude_difference_n;
      t[i] = d.magnitude_threshold_n;
      a[i] = d.angle_deg;
    }
  }
  py::dict out;
  out["perceptible"] = perceptible;
  out["by"] = by;
  out["ratio"] = ratio;
  out["magnitude_difference_n"] = magnitude;
  out["magnitude_threshold_n"] = threshold;
  out["angle_deg"] = angle;
  out["thresholds"] = thresholds_spec(judge.thresholds);
  return out;
}

py::object evaluate(const Scene& scene, const Model& model, std::size_t samples, std::uint64_t seed,
                    const py::object& workspace, const std::string& perceptual) {
  if (samples < 1 || samples > 100000000) throw py::value_error("samples: " + std::to_string(samples) + " is outside [1, 1e8]");
  const TriangleMesh& mesh = model.mesh();
  const float diag = mesh.bounds().diagonal();
  const Workspace ws = workspace_of(diag, workspace);  // as eval: the mesh's diagonal
  const PerceptualJudge judge = judge_of(workspace, perceptual);
  const std::string route = scene_facts(*scene.scene).route;
  nlohmann::json j;
  {
    py::gil_scoped_release release;
    const ExactQuery exact(mesh);
    ProbeOptions probes;
    probes.seed = seed;
    const ComparisonStats s =
        compare_queries(*scene.scene, exact, sample_probes(mesh, samples, probes), ws.law(), diag, nullptr, nullptr, nullptr, judge);
    const ComparisonStats light =
        compare_light_touches(*scene.scene, exact, mesh, samples, seed, ws.law(), diag, nullptr, judge);
    j = eval_json(s, scene.path, model.path, seed, route);
    j["workspace"] = workspace_json(ws, judge);
    j["light_touch"] = light_touch_json(light);
  }
  return py::module_::import("json").attr("loads")(j.dump());
}

py::array_t<float> probes_of(const Model& model, std::size_t count, std::uint64_t seed) {
  if (count > 100000000) throw py::value_error("count: " + std::to_string(count) + " is over 1e8");
  ProbeOptions options;
  options.seed = seed;
  std::vector<Segment> probes;
  {
    py::gil_scoped_release release;
    probes = sample_probes(model.mesh(), count, options);
  }
  py::array_t<float> out({py::ssize_t(probes.size()), py::ssize_t(6)});
  std::memcpy(out.mutable_data(), probes.data(), probes.size() * sizeof(Segment));  // six floats a segment
  return out;
}

} // namespace

void bind_evaluation(py::module_& m) {
  m.def("sample_probes", &probes_of, py::arg("model"), py::arg("count"), py::kw_only(), py::arg("seed") = 1,
        R"doc(eval's random probes of a model: `count` segments (an (N, 6) float32 array, handle then tip, model
units), aimed at the surface from a cone of directions, the tip past it by up to 3% of the
diagonal (hb::sample_probes). The same count and seed give the probes `hapticbox eval --samples
N --seed S` and `hapticbox bench` use.)doc");
  m.def("perceive", &perceive_arrays, py::arg("exact"), py::arg("box"), py::kw_only(), py::arg("workspace") = py::none(),
        py::arg("perceptual") = "nominal",
        R"doc(Whether a hand on the device could tell two answers to the same probes apart (hb::perceive).

exact, box: dicts of answers as Scene.query / Exact.query return them (forces in N, computed at
the same workspace). workspace: its max-force (default 8 N) clamps the forces as the device
renders them. perceptual: "nominal" (10% of |F|, 0.04 N, 25 degrees between forces of at least
0.2 N), "strict" (7%, 0.03 N, 18 degrees) or "w=10,f0=0.04,theta=25,fmin=0.2".
Returns a dict of arrays: "perceptible" (N,) bool; "by" (N,) uint8 bits (1 magnitude,
2 direction, 4 contact on one side only); "ratio" the difference over its threshold (above 1:
felt); "magnitude_difference_n" and "magnitude_threshold_n" (N); "angle_deg"; and "thresholds"
(the spec used).)doc");
  m.def("evaluate", &evaluate, py::arg("scene"), py::arg("model"), py::kw_only(), py::arg("samples") = 20000,
        py::arg("seed") = 1, py::arg("workspace") = py::none(), py::arg("perceptual") = "nominal",
        R"doc(eval's figures: the scene against exact Embree on the model, on `samples` random probes of
`seed` (the same probes as `hapticbox eval BOX MODEL --samples N --seed S`) and as many light
touches at any angle. Returns the dict `hapticbox eval --json` prints: "perceptible" (probes,
share, by which test), contact agreement, force error median/p95/max (fractions), direction
error (degrees), "force_difference_n", "workspace", "light_touch". The GIL is released.)doc");
}

} // namespace hb::python
