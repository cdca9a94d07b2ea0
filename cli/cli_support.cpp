#include "cli_support.h"
#include "evaluation/segments_csv.h"
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <unistd.h>

namespace hb::cli {
namespace {
Communicator* the_communicator = nullptr;
}

Communicator& communicator() { return communicator_or_serial(the_communicator); }

void set_communicator(Communicator* communicator) { the_communicator = communicator; }

ProgressCallback terminal_progress(const std::string& label) {
  if (!isatty(STDERR_FILENO) || !communicator().is_root()) return {};
  return [label](double fraction) {
    const int width = 40;
    const int filled = int(fraction * width + 0.5);
    std::fprintf(stderr, "\r%s [%s%s] %3d%%", label.c_str(), std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(width - filled), '.').c_str(), int(fraction * 100.0 + 0.5));
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
    std::fflush(stderr);
    return true;
  };
}

CLI::Validator finite_range(double lo, double hi) {
  const auto show = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return std::string(text);
  };
  const std::string range = "[" + show(lo) + ", " + show(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        float v = 0.f;
        if (!parse_finite_float(text, v)) return "'" + text + "' is not a finite number";
        if (!(double(v) >= lo && double(v) <= hi)) return "'" + text + "' is outside " + range;
        return {};
      },
      "FINITE in " + range);
}

CLI::Option* add_codec_bound_options(CLI::App& cmd, CodecOptions& options) {
  auto* max_error = cmd.add_option("--max-error", options.max_error,
                                   "Bound on |t1 - t0| / box diagonal for every hit sample")
                        ->check(finite_range(1e-5, 0.1))
                        ->capture_default_str();
  auto* ratio = cmd.add_option("--ratio", options.ratio,
                               "Target compression ratio (finds the tightest bound reaching it)")
                    ->check(finite_range(1.0, 1e6));
  max_error->excludes(ratio);
  cmd.add_option("--normal-bits", options.normal_bits, "Octahedral normal bits per coordinate")
      ->check(CLI::Range(6, 14))
      ->capture_default_str();
  return max_error;
}

void add_force_law_options(CLI::App& cmd, ForceLaw& law) {
  // Bounded so that k x depth x metres per unit stays finite for any model within
  // kMaxCoordinate (1e7 x 4e15 x 1e6 < 3.4e38).
  cmd.add_option("--stiffness", law.stiffness_n_per_m, "Spring stiffness k in N/m")
      ->check(finite_range(1e-6, 1e7))
      ->capture_default_str();
  cmd.add_option("--metres-per-unit", law.metres_per_unit, "Model units to metres")
      ->check(finite_range(1e-12, 1e6))
      ->capture_default_str();
}

void print_json(const nlohmann::json& j) {
  nlohmann::json out = j;
  if (out.is_object() && !out.contains("ranks")) out["ranks"] = communicator().size();
  if (communicator().is_root()) std::cout << out.dump(2) << std::endl;
}

bool is_box_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in.gcount() == 8 && std::string(magic, 8) == "HBOXFILE";
}

} // namespace hb::cli

#include "mesh/mesh_io.h"

namespace hb::cli {

TriangleMesh load_mesh(const std::string& path, MeshReadReport* report) {
  MeshReadReport local;
  TriangleMesh mesh = read_mesh(path, &local);
  for (const std::string& w : local.warnings) std::cerr << "hapticbox: warning: " << w << "\n";
  if (report) *report = local;
  return mesh;
}

} // namespace hb::cli
