#include "contact/workspace.h"
#include "errors.h"
#include "spec_parse.h"
#include <cmath>

namespace hb {
namespace {

void check_range(double v, double lo, double hi, const char* what, const char* unit) {
  if (!(std::isfinite(v) && v > lo && v <= hi))
    throw InvalidInput(std::string(what) + " " + spec_format(v) + " " + unit + " is outside (" + spec_format(lo) +
                       ", " + spec_format(hi) + "]");
}

std::string millimetres(double m) { return spec_format(m * 1000.0) + " mm"; }

} // namespace

ForceLaw Workspace::law() const noexcept {
  ForceLaw l;
  l.stiffness_n_per_m = static_cast<float>(stiffness_n_per_m);
  l.metres_per_unit = static_cast<float>(metres_per_unit);
  l.depth = DepthLaw::normal;
  return l;
}

const char* Workspace::fit_name() const noexcept {
  switch (fit) {
    case WorkspaceFit::device: return "device";
    case WorkspaceFit::real_size: return "real-size";
    case WorkspaceFit::scale: return "scale";
  }
  return "device";
}

std::string Workspace::describe() const {
  std::string how;
  switch (fit) {
    case WorkspaceFit::device: how = "model fitted to the device's workspace"; break;
    case WorkspaceFit::real_size: how = "model at real size"; break;
    case WorkspaceFit::scale: how = "model at the given scale"; break;
  }
  return how + " (diagonal " + millimetres(diagonal_m()) + ", 1 unit = " + millimetres(metres_per_unit) +
         "), k " + spec_format(stiffness_n_per_m) + " N/m, forces up to " + spec_format(max_force_n) + " N";
}

Workspace make_workspace(const Bounds& model_bounds, const WorkspaceOptions& options) {
  return make_workspace(double(model_bounds.diagonal()), options, 0.5f * (model_bounds.min + model_bounds.max));
}

Workspace make_workspace(double model_diagonal, const WorkspaceOptions& o, const Vec3& model_origin) {
  check_range(o.stiffness_n_per_m, 0.0, 1e5, "stiffness", "N/m");
  check_range(o.max_force_n, 0.0, 500.0, "maximum force", "N");
  Workspace w;
  w.fit = o.fit;
  w.stiffness_n_per_m = o.stiffness_n_per_m;
  w.max_force_n = o.max_force_n;
  w.model_diagonal = std::isfinite(model_diagonal) && model_diagonal > 0 ? model_diagonal : 0.0;
  if (!model_origin.allFinite()) throw InvalidInput("the model's bounding box has a non-finite centre");
  w.model_origin = model_origin;
  w.probe_length = w.model_diagonal > 0 ? float(Workspace::kProbeFraction * w.model_diagonal) : 1.f;
  switch (o.fit) {
    case WorkspaceFit::device:
      check_range(o.diagonal_m, 1e-3 - 1e-12, 4.0, "workspace diagonal", "m");
      if (!(w.model_diagonal > 0.0))
        throw InvalidInput("the model's bounding box is empty or degenerate: it cannot be fitted to the workspace");
      w.metres_per_unit = o.diagonal_m / w.model_diagonal;
      break;
    case WorkspaceFit::real_size:
      check_range(o.model_unit_mm, 0.0, 1e9, "model unit", "mm");
      w.metres_per_unit = o.model_unit_mm * 1e-3;
      break;
    case WorkspaceFit::scale:
      check_range(o.metres_per_unit, 0.0, 1e6, "metres per unit", "m");
      w.metres_per_unit = o.metres_per_unit;
      break;
  }
  return w;
}

void parse_workspace_spec(const std::string& spec, WorkspaceOptions& options) {
  // Bounded so that k x depth x metres per unit stays finite for any model within
  // kMaxCoordinate (1e5 x 4e15 x 1e6 < 3.4e38).
  bool mm = false, mpu = false, real = options.fit == WorkspaceFit::real_size, real_given = false;
  parse_spec_keys("--workspace", spec,
                  {{"mm", [&](const std::string& v, const std::string& what) {
                      options.diagonal_m = spec_number(v, what, 1.0, 4000.0) * 1e-3;
                      mm = true;
                    }},
                   {"real-size", [&](const std::string& v, const std::string& what) {
                      if (v.empty() || v == "1" || v == "on" || v == "yes") real = true;
                      else if (v == "0" || v == "off" || v == "no") real = false;
                      else throw InvalidInput(what + ": '" + v + "' is not on or off");
                      real_given = real;
                    }},
                   {"metres-per-unit", [&](const std::string& v, const std::string& what) {
                      options.metres_per_unit = spec_number(v, what, 1e-12, 1e6);
                      mpu = true;
                    }},
                   {"stiffness", [&](const std::string& v, const std::string& what) {
                      options.stiffness_n_per_m = spec_number(v, what, 1e-3, 1e5);
                    }},
                   {"max-force", [&](const std::string& v, const std::string& what) {
                      options.max_force_n = spec_number(v, what, 1e-3, 500.0);
                    }}});
  if (int(mm) + int(mpu) + int(real_given) > 1)
    throw InvalidInput("--workspace: mm, real-size and metres-per-unit exclude each other (give one)");
  options.fit = options.metres_per_unit > 0 ? WorkspaceFit::scale : real ? WorkspaceFit::real_size : WorkspaceFit::device;
}

} // namespace hb
