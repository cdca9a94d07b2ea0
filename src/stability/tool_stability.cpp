// The tool stability suite.
//  1. Each test is a path of device poses (1 ms apart); the tool's coupling follows it over the
//     box and, separately, over exact (ToolCoupling: sub-steps resolved out of the surface).
//  2. Per tick: the coupling force and the simulated tool; exact's own contact of the tool at
//     the device pose (the penalty a tool there would feel).
//  3. Counts: a pop-through is a tick where the device presses (exact's penalty above 0.5 N)
//     but the coupling renders under a quarter of it (the simulated tool went in with the
//     device); a ghost tick renders above the force floor with no surface within the tool's
//     reach of the simulated tool (nothing holds it off); a jump is a tick whose force differs perceptibly from the last.
//  4. Criteria per test (ToolStabilityResult::criterion); the box is held to exact's figures
//     where geometry itself makes them (jumps along slides, the energy of a press).
#include "stability/tool_stability.h"
#include "errors.h"
#include "evaluation/tool_ticks.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "mesh/generators.h"
#include "mesh/triangle_mesh.h"
#include "tool/tool_verdict.h"
#include <algorithm>
#include <cmath>

namespace hb {
namespace {

struct Path {
  std::vector<ToolPose> poses;
};

struct Driven {
  std::vector<Vec3> force, tool;
};

Driven drive(const ContactQuery& query, const ToolShape& tool, const Workspace& ws, const Path& path) {
  ToolCoupling coupling(query, tool, ws);
  Driven d;
  const ForceLaw law = ws.law();
  for (const ToolPose& p : path.poses) {
    const ToolCouplingStep& s = coupling.step(p, law);
    d.force.push_back(s.force);
    d.tool.push_back(s.tool.position);
  }
  return d;
}

// Exact's view of each device pose: the penalty force a tool there would feel.
std::vector<float> reference(const ContactQuery& exact, const ToolShape& tool, const Workspace& ws, const Path& path) {
  ToolProbe probe(tool, ws.metres_per_unit);
  std::vector<float> penalty_n;
  for (const ToolPose& p : path.poses) penalty_n.push_back(probe.answer(exact, p, ws.law()).force.norm());
  return penalty_n;
}

void count(ToolStabilityResult& out, const Driven& d, const std::vector<float>& penalty_n, const ContactQuery& exact,
           float reach, const PerceptualThresholds& t, double max_force_n) {
  for (std::size_t k = 0; k < d.force.size(); ++k) {
    const float f = d.force[k].norm();
    ++out.ticks;
    out.max_force_n = std::max(out.max_force_n, double(f));
    if (penalty_n[k] > 0.5f && f < 0.25f * penalty_n[k]) ++out.pop_throughs;
    // A ghost: the simulated tool held off with no surface within its reach.
    if (f > t.floor_n && !exact.within_reach(d.tool[k], 1.1f * reach)) ++out.ghost_ticks;
    if (k > 0) {
      Contact a, b;
      a.contact = d.force[k - 1].squaredNorm() > 0.f;
      a.force = d.force[k - 1];
      b.contact = f > 0.f;
      b.force = d.force[k];
      out.jumps += perceive(a, b, t, max_force_n).perceptible();
    }
  }
}

ToolPose at(const Vec3& p, const Eigen::Quaternionf& q = Eigen::Quaternionf::Identity()) {
  ToolPose pose;
  pose.position = p;
  pose.orientation = q;
  return pose;
}

// A round channel of radius r (mm) through material: a slab 140 x 140 x 20 mm with a torus
// turned inside out within it (a closed cavity), the tube's centre line the circle of radius
// 60 mm in the plane z = 0.
TriangleMesh channel(float r) {
  TriangleMesh solid = make_cube(Vec3(70.f, 70.f, 10.f), 8);
  const TriangleMesh tube = make_torus(60.f, r, 512, 48);
  const auto offset = std::uint32_t(solid.positions.size());
  solid.positions.insert(solid.positions.end(), tube.positions.begin(), tube.positions.end());
  for (const Triangle& t : tube.triangles) solid.triangles.push_back({t[0] + offset, t[2] + offset, t[1] + offset});
  solid.compute_vertex_normals();
  return solid;
}

// The path along the channel's centre line (30 mm/s), the tool's z axis along it, moved
// `offset` mm towards +z.
Path along_channel(std::size_t ticks, float offset) {
  Path p;
  for (std::size_t k = 0; k < ticks; ++k) {
    const float phi = 0.03f * float(k) / 60.f;
    const Vec3 tangent(-std::sin(phi), std::cos(phi), 0.f);
    p.poses.push_back(at(Vec3(60.f * std::cos(phi), 60.f * std::sin(phi), offset),
                         Eigen::Quaternionf::FromTwoVectors(Vec3::UnitZ(), tangent)));
  }
  return p;
}

BoxScene refined(const TriangleMesh& mesh, const ToolStabilityOptions& options) {
  if (options.bake_object) return options.bake_object(mesh);
  BakeOptions o;
  o.params = {12, 6};
  o.refine = true;
  return BoxScene(without_triangle_ids(bake_scene(mesh, {}, o, SourceInfo{})));
}

// Runs `path` over both answerers of a scene; `judge` fills pass and the figure per method.
template <class Judge>
void both(std::vector<ToolStabilityResult>& out, const std::string& test, const std::string& criterion,
          const ContactQuery& box, const ContactQuery& exact, const ToolShape& tool, const Workspace& ws,
          const PerceptualThresholds& t, const std::vector<Path>& paths, Judge&& judge) {
  ToolStabilityResult r[2];
  std::vector<Driven> driven[2];
  for (int m = 0; m < 2; ++m) {
    r[m].test = test;
    r[m].method = m == 0 ? "box" : "exact";
    r[m].criterion = criterion;
  }
  const float reach = ToolProbe(tool, ws.metres_per_unit).reach();
  for (const Path& path : paths) {
    const std::vector<float> penalty_n = reference(exact, tool, ws, path);
    for (int m = 0; m < 2; ++m) {
      driven[m].push_back(drive(m == 0 ? box : exact, tool, ws, path));
      count(r[m], driven[m].back(), penalty_n, exact, reach, t, ws.max_force_n);
    }
  }
  judge(r[0], r[1], driven[0], driven[1]);
  out.push_back(r[0]);
  out.push_back(r[1]);
}

// The generated objects, at true size (1 unit = 1 mm): a thin plate, a channel, a hole.
void object_tests(std::vector<ToolStabilityResult>& out, const ToolShape& tool, const Workspace& ws,
                  const PerceptualThresholds& t, const ToolStabilityOptions& options) {
  const double k_n_per_m = ws.stiffness_n_per_m;
  Workspace mm_ws = ws;
  mm_ws.metres_per_unit = 1e-3;
  mm_ws.model_diagonal = 100.0;
  const float size_mm = float(tool.size_m * 1e3);
  {
    TriangleMesh plate = make_cube(Vec3(30.f, 30.f, 0.5f), 16);
    plate.compute_vertex_normals();
    const ExactQuery plate_exact(plate);
    const BoxScene plate_box = refined(plate, options);
    Path p;
    const float top = 0.5f + float(tool_support(tool, Vec3(0.f, 0.f, -1.f)) * 1e3);
    for (int k = 0; k <= 40; ++k) p.poses.push_back(at(Vec3(0.3f, -0.2f, top + 5.f - 0.5f * float(k))));
    both(out, "thin-plate", "a 1 mm plate pushed through at 0.5 m/s: the tool stays on top, the force ends at k x depth",
         plate_box, plate_exact, tool, mm_ws, t, {p}, [&](ToolStabilityResult& b, ToolStabilityResult& e, auto& db, auto& de) {
           for (int m = 0; m < 2; ++m) {
             ToolStabilityResult& r = m == 0 ? b : e;
             const Driven& d = (m == 0 ? db : de)[0];
             float lowest = 1e30f;
             for (const Vec3& x : d.tool) lowest = std::min(lowest, x.z());
             const double depth_m = 15.e-3;
             r.figure_name = "final force / k depth";
             r.figure = double(d.force.back().z()) / (k_n_per_m * depth_m);
             r.pass = lowest >= top - 0.6f * size_mm && r.figure >= 0.9 && r.ghost_ticks == 0;
           }
         });
  }
  if (tool.kind == ToolKind::sphere || tool.kind == ToolKind::point) {
    const float r_mm = std::max(0.2f, size_mm);
    const TriangleMesh tight = channel(r_mm - 0.05f);
    const ExactQuery tight_exact(tight);
    const BoxScene tight_box = refined(tight, options);
    both(out, "channel", "centred in a channel 0.05 mm narrower than the tool, moving along it: lateral force under F0",
         tight_box, tight_exact, tool, mm_ws, t, {along_channel(500, 0.f)},
         [&](ToolStabilityResult& b, ToolStabilityResult& e, auto& db, auto& de) {
           for (int m = 0; m < 2; ++m) {
             ToolStabilityResult& r = m == 0 ? b : e;
             double lateral = 0;
             for (const Vec3& f : (m == 0 ? db : de)[0].force) lateral = std::max(lateral, double(f.norm()));
             r.figure_name = "largest force (N)";
             r.figure = lateral;
             r.pass = lateral <= t.floor_n && r.ghost_ticks == 0;
           }
         });
  }
  {
    const float hole = float(tool_support(tool, Vec3(1.f, 0.f, 0.f)) * 1e3) + 0.5f;
    const TriangleMesh bore = channel(hole);
    const ExactQuery bore_exact(bore);
    const BoxScene bore_box = refined(bore, options);
    both(out, "peg-in-hole", "moving along a hole with 0.5 mm clearance: no force centred; 0.6 mm off centre, k x 0.1 mm",
         bore_box, bore_exact, tool, mm_ws, t, {along_channel(300, 0.f), along_channel(300, 0.6f)},
         [&](ToolStabilityResult& b, ToolStabilityResult& e, auto& db, auto& de) {
           for (int m = 0; m < 2; ++m) {
             ToolStabilityResult& r = m == 0 ? b : e;
             const auto& d = m == 0 ? db : de;
             double centred = 0, off = 0;
             for (const Vec3& f : d[0].force) centred = std::max(centred, double(f.norm()));
             for (std::size_t k = 10; k < d[1].force.size(); ++k) off += double(d[1].force[k].norm());
             off /= double(d[1].force.size() - 10);
             const double expected = k_n_per_m * 0.1e-3;
             r.figure_name = "off-centre force / k x 0.1 mm";
             r.figure = off / expected;
             r.pass = centred <= t.floor_n && std::fabs(r.figure - 1.0) <= 0.25;
           }
         });
  }
}

} // namespace

std::vector<ToolStabilityResult> run_tool_stability(const ContactQuery& box, const ContactQuery& exact,
                                                    const TriangleMesh& mesh, const ToolShape& tool,
                                                    const Workspace& ws, const PerceptualThresholds& t,
                                                    const ToolStabilityOptions& options) {
  std::vector<ToolStabilityResult> out;
  const double mpu = ws.metres_per_unit;
  const double k_n_per_m = ws.stiffness_n_per_m;
  const float mm = float(1e-3 / mpu);  // a device millimetre in model units
  // Slides held 0.5 mm in (tool_slides: exact keeps the tool at that depth).
  ToolSlideOptions so;
  so.slides = std::max<std::size_t>(options.slides, options.pushes);
  so.ticks = options.slide_ticks;
  so.seed = options.seed;
  const auto slides = tool_slides(mesh, exact, tool, ws, so);
  if (slides.empty()) throw InvalidInput("tool stability: no slide touched the model");
  std::vector<Path> slide_paths;
  for (std::size_t s = 0; s < std::min(options.slides, slides.size()); ++s) slide_paths.push_back({slides[s]});
  both(out, "slide", "no pop-through, no ghost tick; the box's jumps at most exact's + 10% + 2", box, exact, tool, ws, t,
       slide_paths, [](ToolStabilityResult& b, ToolStabilityResult& e, auto&, auto&) {
         e.pass = e.pop_throughs == 0 && e.ghost_ticks == 0;
         b.pass = b.pop_throughs == 0 && b.ghost_ticks == 0 && double(b.jumps) <= 1.1 * double(e.jumps) + 2.0;
         b.figure_name = e.figure_name = "jumps";
         b.figure = double(b.jumps);
         e.figure = double(e.jumps);
       });
  // Pushes at 0.5 m/s along exact's normal at a slide's first contact, from 1 mm out to 3 mm in.
  ToolProbe probe(tool, mpu);
  std::vector<Path> pushes, presses, rests;
  std::vector<float> push_depth;  // the device's depth past first contact at the last tick, model units
  for (std::size_t s = 0; s < std::min(options.pushes, slides.size()); ++s) {
    const ToolPose start = slides[s].front();
    const ToolAnswer a = probe.answer(exact, start, ws.law());
    if (a.contacts == 0 || a.translation.norm() <= 0.f) continue;
    const Vec3 n = a.translation.normalized();
    const Vec3 surface = start.position + a.translation;  // the tool just touching
    Path push, press, rest;
    for (int k = 0; k <= 8; ++k) push.poses.push_back(at(surface + n * (1.f * mm - 0.5f * mm * float(k)), start.orientation));
    pushes.push_back(push);
    push_depth.push_back(3.f * mm);
    for (int k = 0; k <= 30; ++k) press.poses.push_back(at(surface + n * (0.5f * mm - 0.05f * mm * float(k)), start.orientation));
    for (int k = 29; k >= 0; --k) press.poses.push_back(at(surface + n * (0.5f * mm - 0.05f * mm * float(k)), start.orientation));
    presses.push_back(press);
    if (rests.size() < 2) {
      rest.poses.assign(std::size_t(options.rest_seconds * 1000.0), at(surface - n * 0.5f * mm, start.orientation));
      rests.push_back(rest);
    }
  }
  both(out, "fast-push", "at 0.5 m/s to 3 mm past contact, the force ends at least half of k x 3 mm (no pop-through)",
       box, exact, tool, ws, t, pushes, [&](ToolStabilityResult& b, ToolStabilityResult& e, auto& db, auto& de) {
         for (int m = 0; m < 2; ++m) {
           ToolStabilityResult& r = m == 0 ? b : e;
           const auto& d = m == 0 ? db : de;
           std::size_t held = 0;
           for (std::size_t p = 0; p < d.size(); ++p)
             held += double(d[p].force.back().norm()) >= 0.5 * k_n_per_m * double(push_depth[p]) * mpu;
           r.pop_throughs = d.size() - held;
           r.figure_name = "pushes held";
           r.figure = double(held);
           r.pass = r.pop_throughs == 0 && r.ghost_ticks == 0;
         }
       });
  both(out, "rest", "held 0.5 mm in for the whole time, the force stays within half a JND, no jump", box, exact, tool,
       ws, t, rests, [&](ToolStabilityResult& b, ToolStabilityResult& e, auto& db, auto& de) {
         for (int m = 0; m < 2; ++m) {
           ToolStabilityResult& r = m == 0 ? b : e;
           double worst = 0;
           bool ok = true;
           for (const Driven& d : m == 0 ? db : de) {
             float lo = 1e30f, hi = 0.f;
             for (std::size_t k = 20; k < d.force.size(); ++k) {
               lo = std::min(lo, d.force[k].norm());
               hi = std::max(hi, d.force[k].norm());
             }
             worst = std::max(worst, double(hi - lo));
             ok = ok && double(hi - lo) <= 0.5 * std::max(t.weber * double(hi), t.floor_n);
           }
           r.figure_name = "force range (N)";
           r.figure = worst;
           r.pass = ok && r.pop_throughs == 0 && r.ghost_ticks == 0;
         }
       });
  both(out, "press-release", "1 mm in and out at 50 mm/s: the energy returned over taken at most exact's + 0.02",
       box, exact, tool, ws, t, presses, [&](ToolStabilityResult& b, ToolStabilityResult& e, auto& db, auto& de) {
         for (int m = 0; m < 2; ++m) {
           ToolStabilityResult& r = m == 0 ? b : e;
           double taken = 0, returned = 0;
           for (std::size_t p = 0; p < presses.size(); ++p) {
             const Driven& d = (m == 0 ? db : de)[p];
             for (std::size_t k = 0; k + 1 < d.force.size(); ++k) {
               const Vec3 dx = presses[p].poses[k + 1].position - presses[p].poses[k].position;
               const double w = double(d.force[k].dot(dx)) * mpu;  // J: the held force over the tick's motion
               (w < 0 ? taken : returned) += std::fabs(w);
             }
           }
           r.figure_name = "energy returned / taken";
           r.figure = taken > 0 ? returned / taken : 0.0;
         }
         e.pass = e.figure <= 1.15 && e.pop_throughs == 0;
         b.pass = b.figure <= e.figure + 0.02 && b.pop_throughs == 0;
       });
  object_tests(out, tool, ws, t, options);
  return out;
}

} // namespace hb
