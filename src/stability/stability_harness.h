#pragma once
// The stability suite's harness (internal to evaluation/): the scenes and sites the tests run
// on, the simulated free bounce, the metrics' constructor, and Suite, whose methods are the
// tests T1-T8 (stability_tests.cpp). run_stability_suite (stability_suite.cpp) deals the
// tests to the ranks; the calibration gate is stability_calibration.cpp's, the generated
// objects stability_objects.cpp's.
#include "perception/perceptible.h"
#include "stability/stability_suite.h"
#include "mesh/triangle_mesh.h"
#include <memory>
#include <string>
#include <vector>

namespace hb {
namespace stability {
constexpr double kFloor = 0.05;  // N: the JND floor of the protocol
inline const double kNaN = std::numeric_limits<double>::quiet_NaN();

StabilityMetric metric(const std::string& test, const std::string& scene, const std::string& name,
                       const std::string& unit, double box, double exact, StabilityRule rule, double threshold,
                       double tolerance = 0);

// ---- the simulated free bounce of the calibration and of T1 ----------------------------

struct Bounce {
  double restitution = 0;
  bool popped = false;  // the tip went on inward: contact lost while moving in
};

Bounce free_bounce(const ContactQuery& q, const ForceLaw& law, const Workspace& map, const DeviceProfile& dev,
                   const Vec3d& surface_m, const Vec3d& inward, double v0, double stylus_m,
                   const std::vector<Stall>& stalls = {}, TickFilter* filter = nullptr,
                   ContactLaw contact_law = ContactLaw::penalty);

// A prism: the polygon (x, z) (star-shaped from its first vertex) extruded over y in
// [-half_y, half_y], flat shaded.
TriangleMesh extrude(std::vector<Eigen::Vector2f> poly, float half_y, int div);

// ---- sites on the model -------------------------------------------------------------------

struct Site {
  Vec3d surface_m;  // device space
  Vec3d inward;     // unit, into the object
};

Vec3d tilted(const Vec3d& inward, double degrees, std::size_t which);

struct Scene {
  std::string name;
  const ContactQuery* box = nullptr;
  const ContactQuery* exact = nullptr;
  const BoxScene* box_scene = nullptr;
  Workspace workspace;  // the model at the device (its mesh in mm for the generated objects)
  std::vector<Site> sites;
};

std::vector<Site> pick_sites(const TriangleMesh& mesh, const ContactQuery& exact, const Workspace& map,
                             const ForceLaw& law, std::size_t count, std::uint64_t seed, double stylus_m);

// ---- helpers over tick records ------------------------------------------------------------

double rms_speed(const std::vector<TickRecord>& ticks, double t0, double t1);
double angle_deg(const Vec3d& a, const Vec3d& b);

// One task's tests: its figures go to out_ and traces_.
class Suite {
public:
  Suite(const StabilityOptions& o) : o_(o) {}

  bool want(const std::string& t) const {
    return o_.tests.empty() || std::find(o_.tests.begin(), o_.tests.end(), t) != o_.tests.end();
  }

  ForceLaw law(const Scene& s, double k) const {
    ForceLaw l;
    l.stiffness_n_per_m = float(k);
    l.metres_per_unit = float(s.workspace.metres_per_unit);
    l.depth = o_.depth_law;
    return l;
  }
  double k_max() const { return o_.device.max_stiffness_n_per_m; }
  ContactLaw cl() const { return o_.contact_law; }
  double k_half() const { return 0.5 * k_max(); }

  std::unique_ptr<TickFilter> filter() const {
    if (!o_.filter) return nullptr;
    auto f = o_.filter();
    // The servo has been running: the start ramp is over before the trajectory begins.
    for (int i = 0; i < 2000; ++i) f->apply(Vec3d::Zero(), Vec3d::Zero(), Vec3d::Zero(), 0.0);
    return f;
  }

  // A hold at `site`: a light grip starting 2 mm outside and pulling towards 30 mm inside
  // (reached in 0.5 s, then held), the stylus along the inward normal, for `seconds`.
  ClosedLoopRun hold_run(const Site& site, double seconds) const {
    ClosedLoopRun run;
    run.device = o_.device;
    run.hand = light_grip();
    run.start_m = site.surface_m - 0.002 * site.inward;
    const Vec3d from = run.start_m, to = site.surface_m + 0.03 * site.inward;
    run.set_point = [from, to](double t) { return t < 0.5 ? from + (to - from) * (t / 0.5) : to; };
    run.seconds = seconds;
    run.stylus_dir = site.inward;
    run.stylus_m = o_.stylus_m;
    run.contact_law = cl();
    return run;
  }

  void add(StabilityMetric m) { out_.push_back(std::move(m)); }

  // The tests (stability_tests.cpp).
  std::vector<Vec3d> surface_path(const Scene& s, const Site& site, const Vec3d& dir, double speed,
                                  std::size_t ticks, std::size_t which) const;
  void t1(const Scene& s);
  void t2(const Scene& s);
  void t3(const Scene& s, double thickness_mm);
  void t4(const Scene& s);
  double keff_ratio(const Scene& s, const ContactQuery& q, const Site& site, double tilt, std::size_t which) const;
  void t5(const Scene& s, bool model);
  void t6(const Scene& s);
  void t7(const Scene& s);
  void t8(const Scene& s);

  std::vector<StabilityMetric> out_;
  std::vector<ForceTrace> traces_;

private:
  const StabilityOptions& o_;
};

} // namespace stability
} // namespace hb
