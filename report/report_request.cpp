// The report request (report_request.h): the steps both front ends used to assemble by hand.
#include "report_request.h"
#include "errors.h"
#include "mesh/file_hash.h"
#include <algorithm>
#include <filesystem>
#include <set>
#include <utility>

namespace hb {

std::vector<SweepConfig> report_sweep_configs(const BoxScene& scene, const ReportSweep& sweep, std::string* note) {
  if (note) note->clear();
  std::vector<SweepConfig> out;
  if (!sweep.enabled || scene.parts().boxes.empty()) return out;
  const BoxParams own = scene.parts().boxes.front().params();
  const bool given = !sweep.m.empty() || !sweep.n.empty();
  if (!given) {
    if (scene.parts().boxes.size() > 1) {
      if (note)
        *note = std::to_string(scene.parts().boxes.size()) +
                " boxes: the default sweep (one box per configuration) is skipped";
      return out;
    }
    // Around the report's own (m, n): m/4, m/2, m by n/2, n, without the box itself.
    std::set<std::pair<int, int>> grid;
    for (int mm : {own.m / 4, own.m / 2, own.m})
      for (int nn : {own.n / 2, own.n})
        if (mm >= 2 && nn >= 2 && !(mm == own.m && nn == own.n)) grid.insert({mm, nn});
    for (const auto& [mm, nn] : grid) out.push_back({mm, nn, "none"});
    return out;
  }
  const std::vector<int> ms = sweep.m.empty() ? std::vector<int>{own.m} : sweep.m;
  const std::vector<int> ns = sweep.n.empty() ? std::vector<int>{own.n} : sweep.n;
  for (const SweepConfig& c : sweep_grid(ms, ns))
    if (!(c.m == own.m && c.n == own.n)) out.push_back(c);
  return out;
}

ReportData compute_report(const ReportRequest& request) {
  if (!request.mesh) throw InvalidInput("report: no mesh");
  if (!request.scene) throw InvalidInput("report: no box scene");
  ReportOptions options = request.options;
  options.sweep_configs = report_sweep_configs(*request.scene, request.sweep);
  ReportData d = compute_report(*request.mesh, request.scene->parts().piece_of_triangle, *request.scene,
                                request.bake_seconds, request.references, options);
  d.product_version = request.product_version;
  d.command_line = request.command_line;
  d.mesh_path = request.mesh_path;
  d.mesh_hash = request.mesh_hash;
  d.box_path = request.box_path;
  d.box_hash = request.box_path.empty() || !std::filesystem::exists(request.box_path) ? 0 : hash_file(request.box_path);
  d.stability = request.stability;
  return d;
}

void write_report(const ReportRequest& request, ReportData& data, const std::string& dir) {
  std::filesystem::create_directories(dir);
  data.error_field_image.clear();
  if (data.error_field.size() == 0) {
    data.error_field_note = "error field disabled (0 probes per vertex)";
  } else if (!request.error_field_image.empty()) {
    data.error_field_image = request.error_field_image;
    data.error_field_note.clear();
  } else if (request.render_error_field) {
    // Write the report without the image first: a display that vanishes mid-render can take
    // the process down inside Xlib, and the figures must survive that.
    data.error_field_note = "rendering the error field did not finish";
    write_report(data, dir);
    const std::string png = (std::filesystem::path(dir) / "charts" / "error_field.png").string();
    std::filesystem::create_directories(std::filesystem::path(png).parent_path());
    if (request.render_error_field(*request.mesh, data.error_field.perceptible_ratio, 4.0, png, &data.error_field_note)) {
      data.error_field_image = png;
      data.error_field_note.clear();
    }
  } else {
    data.error_field_note = request.no_image_note;
  }
  write_report(data, dir);
}

} // namespace hb
