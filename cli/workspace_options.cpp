#include "workspace_options.h"
#include "perception/perceptible.h"
#include "spec_option.h"

namespace hb::cli {

WorkspaceOptions WorkspaceArgs::options() const {
  WorkspaceOptions o;
  o.fit = metres_per_unit > 0 ? WorkspaceFit::scale : real_size ? WorkspaceFit::real_size : WorkspaceFit::device;
  o.diagonal_m = workspace_mm * 1e-3;
  o.metres_per_unit = metres_per_unit;
  o.stiffness_n_per_m = stiffness;
  o.max_force_n = max_force;
  return o;
}

Workspace WorkspaceArgs::workspace(double model_diagonal) const { return make_workspace(model_diagonal, options()); }

PerceptualJudge WorkspaceArgs::judge() const {
  PerceptualJudge j;
  j.thresholds = parse_thresholds(perceptual);
  j.max_force_n = max_force;
  return j;
}

void add_workspace_options(CLI::App& cmd, WorkspaceArgs& args) {
  const std::string group = "Workspace (the scale forces are computed and judged at)";
  const WorkspaceArgs d;
  // Bounded so that k x depth x metres per unit stays finite for any model within
  // kMaxCoordinate (1e5 x 4e15 x 1e6 < 3.4e38).
  cmd.add_option_function<std::string>(
         "--workspace",
         [&args](const std::string& spec) {
           bool mm = false, mpu = false, real = false;
           parse_spec("--workspace", spec,
                      {{"mm", [&](const std::string& v, const std::string& what) {
                          args.workspace_mm = spec_number_or_usage(v, what, 1.0, 4000.0);
                          mm = true;
                        }},
                       {"real-size", [&](const std::string& v, const std::string& what) {
                          flag_key("real-size", args.real_size).set(v, what);
                          real = args.real_size;
                        }},
                       {"metres-per-unit", [&](const std::string& v, const std::string& what) {
                          args.metres_per_unit = spec_number_or_usage(v, what, 1e-12, 1e6);
                          mpu = true;
                        }},
                       {"stiffness", [&](const std::string& v, const std::string& what) {
                          args.stiffness = spec_number_or_usage(v, what, 1e-3, 1e5);
                        }},
                       {"max-force", [&](const std::string& v, const std::string& what) {
                          args.max_force = spec_number_or_usage(v, what, 1e-3, 500.0);
                        }}});
           if (int(mm) + int(mpu) + int(real) > 1)
             throw UsageError("--workspace: mm, real-size and metres-per-unit exclude each other (give one)");
         },
         "Where the model sits at the device: mm=D (the diagonal of its bounding box, mm; default " +
             spec_format(d.workspace_mm) +
             ": the Falcon's workspace sphere), real-size (1 model unit = 1 mm: anatomy at true scale) or "
             "metres-per-unit=S (an explicit scale); stiffness=K (the spring, N/m; default " +
             spec_format(d.stiffness) + ": half the Falcon's stable 3000), max-force=F (the largest force the device "
             "renders, N; forces are judged clamped to it; default " + spec_format(d.max_force) + ")")
      ->type_name("KEY=VALUE,...")
      ->group(group);
  cmd.add_option("--perceptual", args.perceptual,
                 "When a difference is perceptible: nominal (w=10,f0=0.04,theta=25,fmin=0.2), strict "
                 "(w=7,f0=0.03,theta=18) or key=value list: w percent, f0 N, theta degrees, fmin N "
                 "(docs/perception.md)")
      ->check([](const std::string& v) {
        try {
          parse_thresholds(v);
          return std::string();
        } catch (const std::exception& e) {
          return std::string(e.what());
        }
      })
      ->capture_default_str()
      ->group(group);
}

} // namespace hb::cli
