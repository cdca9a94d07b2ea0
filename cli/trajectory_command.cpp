// hapticbox trajectory LOG BOX -o OUT.vtp [workspace options]: a recorded servo log (servo
// --record) as a polyline in the model's frame, for ParaView (colour by ForceMagnitude,
// Contact, SafetyFlags; play it back with Time). The mapping is the one `servo` fits to the box
// scene at the workspace scale servo used (the same --workspace-mm / --real-size / --metres-per-unit).
#include "cli_support.h"
#include "commands.h"
#include "device/servo_log.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include "figure_text.h"
#include "store/box_file.h"
#include "polydata_files.h"
#include "trajectory_export.h"
#include <vtkFieldData.h>
#include <vtkPolyData.h>
#include <cmath>
#include <iostream>
#include <limits>

namespace hb::cli {

void check_trajectory_records(const ServoLog& log, const std::string& source) {
  // The force a record holds was written to the device after the safety layer, so it is within
  // the device's peak force; 1% and 1 mN of slack for rounding.
  const double most = double(log.spec.max_force_n) * 1.01 + 1e-3;
  for (std::size_t i = 0; i < log.records.size(); ++i) {
    const LogRecord& r = log.records[i];
    const char* field = !std::isfinite(r.time_s) ? "time" : nullptr;
    for (int a = 0; a < 3 && !field; ++a) {
      if (!std::isfinite(r.position_m[a])) field = "position";
      else if (!std::isfinite(r.force_n[a])) field = "force";
    }
    if (!field && !std::isfinite(r.depth)) field = "depth";
    if (field)
      throw InvalidInput(source + ": record " + std::to_string(i) + " has a non-finite " + field + ": the log is damaged (nothing written)");
    const double f = std::hypot(double(r.force_n[0]), double(r.force_n[1]), double(r.force_n[2]));
    if (f > most)
      throw InvalidInput(source + ": record " + std::to_string(i) + " has a force of " + sig(f) + " N, beyond the " +
                         sig(log.spec.max_force_n) + " N its device (" + quoted_text(log.spec.name, 60) +
                         ") can render after its safety limits: the log is damaged (nothing written)");
  }
}

std::size_t write_trajectory_vtp(const ServoLog& log, const Workspace& workspace, const std::string& source,
                                 const std::string& path) {
  std::vector<hb::vtk::TrajectorySample> samples;
  samples.reserve(log.records.size());
  for (const LogRecord& r : log.records) {
    hb::vtk::TrajectorySample s;
    s.time_s = r.time_s;
    s.tip = workspace.to_model(Vec3(r.position_m[0], r.position_m[1], r.position_m[2]).cast<double>());
    s.force = Vec3(r.force_n[0], r.force_n[1], r.force_n[2]);
    s.depth = r.depth;
    s.contact = r.contact != 0;
    s.query_ns = r.query_ns;
    s.safety_flags = r.safety_flags;
    samples.push_back(s);
  }
  vtkSmartPointer<vtkPolyData> pd = hb::vtk::trajectory_polydata(samples);
  hb::vtk::add_provenance(pd->GetFieldData(),
                          {{{"HapticBoxVersion", HB_VERSION}, {"Source", source}, {"Device", log.spec.name}},
                           {{"Rate_Hz", log.rate_hz},
                            {"ModelUnitsPerMetre", 1.0 / workspace.metres_per_unit},
                            {"ModelOriginX", workspace.model_origin.x()},
                            {"ModelOriginY", workspace.model_origin.y()},
                            {"ModelOriginZ", workspace.model_origin.z()}}});
  hb::vtk::write_polydata_xml(pd, path);
  return samples.size();
}

} // namespace hb::cli

void add_trajectory_command(CLI::App& app) {
  struct Opts {
    std::string log, box, out;
    hb::cli::WorkspaceArgs workspace;  // as given to servo
  };
  auto opts = std::make_shared<Opts>();
  auto* cmd = app.add_subcommand("trajectory", "Export a recorded servo log (servo --record) as a polyline .vtp");
  cmd->add_option("LOG", opts->log, "Servo log written by servo --record")->required();
  cmd->add_option("BOX", opts->box, "The box file the log was recorded on (gives the model frame), or `plane`")->required();
  cmd->add_option("-o,--output", opts->out, "Output .vtp file")->required();
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->callback([opts] {
    if (hb::cli::lower_extension(opts->out) != ".vtp")
      throw hb::cli::UsageError("-o " + opts->out + ": the trajectory is written as VTK XML PolyData; name it .vtp");
    const hb::ServoLog log = hb::read_servo_log(opts->log);
    hb::cli::check_trajectory_records(log, opts->log);
    // The servo's workspace: the same call on the same box file with the same options.
    hb::Workspace workspace;
    if (opts->box != "plane") {
      const hb::BoxScene scene = hb::load_box_file(opts->box);
      if (scene.parts().boxes.empty()) throw hb::InvalidInput(opts->box + ": the box file holds no boxes");
      workspace = hb::scene_workspace(scene, opts->workspace.options());
    } else {
      hb::Bounds plane;  // `plane`, as servo: an 80 mm cube around the plane z = 0
      plane.min = hb::Vec3::Constant(-40.f);
      plane.max = hb::Vec3::Constant(40.f);
      workspace = hb::make_workspace(plane, opts->workspace.options());
    }
    const std::size_t n = hb::cli::write_trajectory_vtp(log, workspace, opts->log, opts->out);
    const double seconds = log.records.empty() ? 0.0 : log.records.back().time_s - log.records.front().time_s;
    std::cout << "trajectory " << opts->out << ": " << hb::count_text(double(n)) << " points over "
              << hb::duration_text(seconds) << " at " << hb::sig(log.rate_hz) << " Hz\n";
  });
}
