// hapticbox query BOX --segment sx sy sz ex ey ez | --segments IN.csv [--out OUT.csv] [--exact MESH]
// hapticbox query BOX --tool SPEC --poses POSES.csv [--out OUT.csv] [--exact MESH]
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "evaluation/segments_csv.h"
#include "evaluation/tool_poses_csv.h"
#include "exact/exact_query.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include "tool/tool_spec.h"
#include "tool/tool_verdict.h"
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

namespace {

void write_contact(std::ostream& out, const hb::Contact& c) {
  out << (c.contact ? 1 : 0) << ',' << c.depth << ',' << c.normal.x() << ',' << c.normal.y() << ','
      << c.normal.z() << ',' << c.force.x() << ',' << c.force.y() << ',' << c.force.z();
}

void write_tool_answer(std::ostream& out, const hb::ToolAnswer& a) {
  out << a.force.x() << ',' << a.force.y() << ',' << a.force.z() << ',' << a.torque.x() << ',' << a.torque.y() << ','
      << a.torque.z() << ',' << a.contacts;
}

// Each pose on its own: the tool's contact force and torque there (no coupling).
void answer_tool_poses(const hb::BoxScene& scene, const hb::ExactQuery* exact, const hb::Workspace& workspace,
                       const hb::PerceptualJudge& judge, const hb::ToolShape& tool,
                       const std::vector<hb::ToolPose>& poses, std::ostream& out) {
  const hb::ForceLaw law = workspace.law();
  hb::ToolProbe box_probe(tool, workspace.metres_per_unit), exact_probe(tool, workspace.metres_per_unit);
  out << "fx,fy,fz,tx,ty,tz,contacts";
  if (exact) out << ",exact_fx,exact_fy,exact_fz,exact_tx,exact_ty,exact_tz,exact_contacts,perceptible";
  out << "\n";
  for (const hb::ToolPose& pose : poses) {
    const hb::ToolAnswer box = box_probe.answer(scene, pose, law);
    write_tool_answer(out, box);
    if (exact) {
      const hb::ToolAnswer e = exact_probe.answer(*exact, pose, law);
      out << ',';
      write_tool_answer(out, e);
      const hb::ToolDifference d = hb::perceive_tool(e, box, judge.thresholds, judge.max_force_n, tool.radius_m);
      std::string by = hb::perceived_by_name(d.force.by);
      if (d.torque_felt) by = by == "none" ? "torque" : by + "+torque";
      out << ',' << by;
    }
    out << "\n";
  }
}

// The box file's scene, and exact Embree on MESH when given, at the workspace of the box file's
// mesh diagonal (the same as the mesh's when both are given: the scale of `eval`, `servo` and
// the window for this model).
struct Answerers {
  hb::BoxScene scene;
  hb::TriangleMesh mesh;
  std::unique_ptr<hb::ExactQuery> exact;
  hb::Workspace workspace;
};

std::unique_ptr<Answerers> load_answerers(const std::string& box, const std::string& exact_mesh,
                                          const hb::cli::ModelArgs& model, const hb::cli::WorkspaceArgs& workspace) {
  auto a = std::make_unique<Answerers>();
  a->scene = hb::load_box_file(box);
  if (!exact_mesh.empty()) {
    a->mesh = hb::cli::load_mesh(exact_mesh, model);
    a->exact = std::make_unique<hb::ExactQuery>(a->mesh);
  }
  a->workspace = workspace.workspace(a->exact ? double(a->mesh.bounds().diagonal()) : hb::model_diagonal(a->scene));
  return a;
}

// OUT (a file) or stdout, its floats written to read back the same (9 significant digits): the
// Python module's answers compare with them bit for bit.
std::ostream& output(const std::string& path, std::ofstream& file) {
  std::ostream* out = &std::cout;
  if (!path.empty()) {
    file.open(path);
    if (!file) throw hb::IoError(path + ": cannot open for writing");
    out = &file;
  }
  out->precision(std::numeric_limits<float>::max_digits10);
  return *out;
}

} // namespace

void add_query_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("query", "Answer probe segments with a box file (and the exact method)");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string box, segments_csv, out_csv, exact_mesh, tool, poses_csv;
    std::vector<std::string> segment;
    hb::cli::WorkspaceArgs workspace;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  // BOX is checked in the callback, after --segment: a short --segment swallows the box file
  // name, and the message must say that the segment is short, not that BOX is missing.
  cmd->add_option("BOX", opts->box, "Box file (.hbox)");
  auto* seg = cmd->add_option("--segment", opts->segment, "One segment: six numbers sx sy sz ex ey ez")->expected(1, 16);
  auto* segs = cmd->add_option("--segments", opts->segments_csv, "CSV with header sx,sy,sz,ex,ey,ez");
  seg->excludes(segs);
  auto* tool = cmd->add_option("--tool", opts->tool,
                               "A tool with volume: sphere,radius-mm=R,points=N | capsule,radius-mm=R,length-mm=L,points=N | "
                               "mesh=FILE,points=N (sizes in device mm at the workspace); answers --poses");
  cmd->add_option("--poses", opts->poses_csv,
                  "With --tool: CSV with header x,y,z[,qw,qx,qy,qz] (tool centre, model units); writes fx,fy,fz,tx,ty,tz,"
                  "contacts a pose (N, N m; each pose on its own, forces not clamped)");
  tool->excludes(seg)->excludes(segs);
  cmd->add_option("--out", opts->out_csv, "Output CSV (default: stdout)");
  cmd->add_option("--exact", opts->exact_mesh, "Also answer exactly against this mesh");
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->callback([opts] {
    if (!opts->tool.empty() || !opts->poses_csv.empty()) {
      if (opts->tool.empty()) throw hb::cli::UsageError("query: --poses needs --tool SPEC");
      if (opts->poses_csv.empty()) throw hb::cli::UsageError("query: --tool needs --poses POSES.csv (header x,y,z[,qw,qx,qy,qz])");
      if (opts->box.empty()) throw hb::cli::UsageError("query: BOX is required (the box file, first)");
      const hb::ToolSpec spec = hb::parse_tool_spec(opts->tool);
      const std::vector<hb::ToolPose> poses = hb::read_tool_poses_csv(opts->poses_csv);
      const hb::ToolShape tool = hb::make_tool(spec, [](const std::string& path) { return hb::cli::load_mesh(path); });
      const auto a = load_answerers(opts->box, opts->exact_mesh, opts->model, opts->workspace);
      std::ofstream file;
      std::ostream& out = output(opts->out_csv, file);
      answer_tool_poses(a->scene, a->exact.get(), a->workspace, opts->workspace.judge(), tool, poses, out);
      if (!out) throw hb::IoError((opts->out_csv.empty() ? std::string("stdout") : opts->out_csv) + ": write failed");
      return;
    }
    std::vector<hb::Segment> segments;
    if (!opts->segment.empty()) {
      // `query --segment 6 NUMBERS BOX`: the option takes what follows it; the seventh is BOX.
      if (opts->box.empty() && opts->segment.size() == 7) {
        opts->box = opts->segment.back();
        opts->segment.pop_back();
      }
      if (opts->segment.size() != 6) {
        std::string given;
        for (const std::string& v : opts->segment) given += " " + v;
        throw hb::cli::UsageError("--segment takes six numbers sx sy sz ex ey ez (tip last); got " +
                                  std::to_string(opts->segment.size()) + ":" + given +
                                  (opts->box.empty() ? " (and no BOX file: put it before --segment)" : ""));
      }
      float v[6];
      for (std::size_t k = 0; k < 6; ++k)
        if (!hb::parse_finite_float(opts->segment[k], v[k]) || std::fabs(v[k]) > hb::kMaxSegmentCoordinate)
          throw hb::cli::UsageError("--segment: value " + std::to_string(k + 1) + " '" + opts->segment[k] +
                                    "' is not a finite number within 4e15");
      segments.push_back({hb::Vec3(v[0], v[1], v[2]), hb::Vec3(v[3], v[4], v[5])});
    } else if (!opts->segments_csv.empty()) {
      segments = hb::read_segments_csv(opts->segments_csv);
    } else {
      throw hb::cli::UsageError("query: give --segment sx sy sz ex ey ez or --segments IN.csv");
    }
    if (opts->box.empty()) throw hb::cli::UsageError("query: BOX is required (the box file, first)");
    const auto a = load_answerers(opts->box, opts->exact_mesh, opts->model, opts->workspace);
    const hb::BoxScene& scene = a->scene;
    const hb::ExactQuery* exact = a->exact.get();
    const hb::ForceLaw law = a->workspace.law();
    const hb::PerceptualJudge judge = opts->workspace.judge();
    std::ofstream file;
    std::ostream& out = output(opts->out_csv, file);
    out << "contact,depth,nx,ny,nz,fx,fy,fz";
    if (exact) out << ",exact_contact,exact_depth,exact_nx,exact_ny,exact_nz,exact_fx,exact_fy,exact_fz,perceptible";
    out << "\n";
    for (const hb::Segment& s : segments) {
      const hb::Contact box = scene.query(s, law);
      write_contact(out, box);
      if (exact) {
        out << ',';
        const hb::Contact e = exact->query(s, law);
        write_contact(out, e);
        out << ',' << hb::perceived_by_name(hb::perceive(e, box, judge.thresholds, judge.max_force_n).by);
      }
      out << "\n";
    }
    if (!out) throw hb::IoError((opts->out_csv.empty() ? std::string("stdout") : opts->out_csv) + ": write failed");
  });
}
