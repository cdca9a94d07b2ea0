#include "workspace_options.h"
#include "perception/perceptible.h"
#include "errors.h"
#include "spec_option.h"

namespace hb::cli {

Workspace WorkspaceArgs::workspace(double model_diagonal) const { return make_workspace(model_diagonal, options()); }

PerceptualJudge WorkspaceArgs::judge() const {
  PerceptualJudge j;
  j.thresholds = parse_thresholds(perceptual);
  j.max_force_n = given.max_force_n;
  return j;
}

void add_workspace_options(CLI::App& cmd, WorkspaceArgs& args) {
  const std::string group = "Workspace (the scale forces are computed and judged at)";
  const WorkspaceArgs d;
  cmd.add_option_function<std::string>(
         "--workspace",
         [&args](const std::string& spec) {
           try {
             parse_workspace_spec(spec, args.given);
           } catch (const InvalidInput& e) {
             throw UsageError(e.what());
           }
         },
         "Where the model sits at the device: mm=D (the diagonal of its bounding box, mm; default " +
             spec_format(d.given.diagonal_m * 1000.0) +
             ": the Falcon's workspace sphere), real-size (1 model unit = 1 mm: anatomy at true scale) or "
             "metres-per-unit=S (an explicit scale); stiffness=K (the spring, N/m; default " +
             spec_format(d.given.stiffness_n_per_m) + ": half the Falcon's stable 3000), max-force=F (the largest force the device "
             "renders, N; forces are judged clamped to it; default " + spec_format(d.given.max_force_n) + ")")
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
