#pragma once
// The hapticbox command: one file per sub-command, each registering itself on the app.
#include <CLI/CLI.hpp>
#include <string>

void add_info_command(CLI::App& app);
void add_bake_command(CLI::App& app);
void add_query_command(CLI::App& app);
void add_eval_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_subdivide_command(CLI::App& app);
void add_simplify_command(CLI::App& app);
void add_devices_command(CLI::App& app);
void add_servo_command(CLI::App& app);
void add_decompose_command(CLI::App& app);
void add_sweep_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_field_command(CLI::App& app);
void add_trajectory_command(CLI::App& app);
void add_compress_sweep_command(CLI::App& app);
void add_compress_command(CLI::App& app);
void add_cache_command(CLI::App& app);
void add_stability_command(CLI::App& app);

namespace hb {
struct StabilityReport;
class BoxScene;
struct TriangleMesh;
}
namespace hb::cli {
/// The stability suite with the command's defaults (Falcon profile, the servo's safety with
/// hold-and-ramp), for `report --stability` (defined in stability_command.cpp).
StabilityReport default_stability(const BoxScene& scene, const TriangleMesh& mesh, const std::string& model_name,
                                  std::size_t sites);
}
