// hapticbox query BOX --segment sx sy sz ex ey ez | --segments IN.csv [--out OUT.csv] [--exact MESH]
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "evaluation/segments_csv.h"
#include "exact/exact_query.h"
#include "haptic_box/box_file.h"
#include "mesh/mesh_io.h"
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace {

void write_contact(std::ostream& out, const hb::Contact& c) {
  out << (c.contact ? 1 : 0) << ',' << c.depth << ',' << c.normal.x() << ',' << c.normal.y() << ','
      << c.normal.z() << ',' << c.force.x() << ',' << c.force.y() << ',' << c.force.z();
}

} // namespace

void add_query_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("query", "Answer probe segments with a box file (and the exact method)");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string box, segments_csv, out_csv, exact_mesh;
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
  cmd->add_option("--out", opts->out_csv, "Output CSV (default: stdout)");
  cmd->add_option("--exact", opts->exact_mesh, "Also answer exactly against this mesh");
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->callback([opts] {
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
    const hb::BoxScene scene = hb::load_box_file(opts->box);
    hb::TriangleMesh mesh;
    std::unique_ptr<hb::ExactQuery> exact;
    if (!opts->exact_mesh.empty()) {
      mesh = hb::cli::load_mesh(opts->exact_mesh, opts->model);
      exact = std::make_unique<hb::ExactQuery>(mesh);
    }
    // The box file's mesh diagonal (the same as the mesh's when both are given: the scale of
    // `eval`, `servo` and the window for this model).
    const double diagonal = exact ? double(mesh.bounds().diagonal()) : hb::cli::model_diagonal(scene);
    const hb::ForceLaw law = opts->workspace.workspace(diagonal).law();
    const hb::PerceptualJudge judge = opts->workspace.judge();
    std::ofstream file;
    if (!opts->out_csv.empty()) {
      file.open(opts->out_csv);
      if (!file) throw hb::IoError(opts->out_csv + ": cannot open for writing");
    }
    std::ostream& out = opts->out_csv.empty() ? std::cout : file;
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
