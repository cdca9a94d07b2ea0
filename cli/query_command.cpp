// hapticbox query BOX --segment sx sy sz ex ey ez | --segments IN.csv [--out OUT.csv] [--exact MESH]
#include "cli_support.h"
#include "commands.h"
#include "errors.h"
#include "exact/exact_query.h"
#include "haptic_box/box_file.h"
#include "mesh/mesh_io.h"
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace {

std::vector<hb::Segment> read_segments_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw hb::IoError(path + ": cannot open segments file");
  std::string line;
  std::vector<hb::Segment> out;
  std::size_t line_no = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    if (!header_seen) {
      header_seen = true;
      std::string compact;
      for (char c : line)
        if (c != ' ' && c != '\t') compact += c;
      if (compact != "sx,sy,sz,ex,ey,ez")
        throw hb::InvalidInput(path + ":" + std::to_string(line_no) + ": expected the header sx,sy,sz,ex,ey,ez");
      continue;
    }
    std::stringstream ss(line);
    std::string cell;
    float v[6];
    int k = 0;
    while (std::getline(ss, cell, ',')) {
      if (k >= 6) throw hb::InvalidInput(path + ":" + std::to_string(line_no) + ": more than 6 values");
      try {
        std::size_t used = 0;
        v[k] = std::stof(cell, &used);
        if (cell.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument(cell);
      } catch (const std::exception&) {
        throw hb::InvalidInput(path + ":" + std::to_string(line_no) + ": not a number: '" + cell + "'");
      }
      if (!std::isfinite(v[k]))
        throw hb::InvalidInput(path + ":" + std::to_string(line_no) + ": value is not finite: '" + cell + "'");
      ++k;
    }
    if (k != 6) throw hb::InvalidInput(path + ":" + std::to_string(line_no) + ": expected 6 values, got " + std::to_string(k));
    out.push_back({hb::Vec3(v[0], v[1], v[2]), hb::Vec3(v[3], v[4], v[5])});
  }
  if (!header_seen) throw hb::InvalidInput(path + ": empty segments file (expected the header sx,sy,sz,ex,ey,ez)");
  return out;
}

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
    std::vector<float> segment;
    hb::ForceLaw law;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("BOX", opts->box, "Box file (.hbox)")->required();
  auto* seg = cmd->add_option("--segment", opts->segment, "One segment: sx sy sz ex ey ez")->expected(6);
  auto* segs = cmd->add_option("--segments", opts->segments_csv, "CSV with header sx,sy,sz,ex,ey,ez");
  seg->excludes(segs);
  cmd->add_option("--out", opts->out_csv, "Output CSV (default: stdout)");
  cmd->add_option("--exact", opts->exact_mesh, "Also answer exactly against this mesh");
  hb::cli::add_force_law_options(*cmd, opts->law);
  cmd->callback([opts] {
    std::vector<hb::Segment> segments;
    if (!opts->segment.empty()) {
      const auto& v = opts->segment;
      for (float x : v)
        if (!std::isfinite(x)) throw hb::cli::UsageError("--segment: values must be finite");
      segments.push_back({hb::Vec3(v[0], v[1], v[2]), hb::Vec3(v[3], v[4], v[5])});
    } else if (!opts->segments_csv.empty()) {
      segments = read_segments_csv(opts->segments_csv);
    } else {
      throw hb::cli::UsageError("query: give --segment sx sy sz ex ey ez or --segments IN.csv");
    }
    const hb::BoxScene scene = hb::load_box_file(opts->box);
    hb::TriangleMesh mesh;
    std::unique_ptr<hb::ExactQuery> exact;
    if (!opts->exact_mesh.empty()) {
      mesh = hb::cli::load_mesh(opts->exact_mesh, opts->model);
      exact = std::make_unique<hb::ExactQuery>(mesh);
    }
    std::ofstream file;
    if (!opts->out_csv.empty()) {
      file.open(opts->out_csv);
      if (!file) throw hb::IoError(opts->out_csv + ": cannot open for writing");
    }
    std::ostream& out = opts->out_csv.empty() ? std::cout : file;
    out << "contact,depth,nx,ny,nz,fx,fy,fz";
    if (exact) out << ",exact_contact,exact_depth,exact_nx,exact_ny,exact_nz,exact_fx,exact_fy,exact_fz";
    out << "\n";
    for (const hb::Segment& s : segments) {
      write_contact(out, scene.query(s, opts->law));
      if (exact) {
        out << ',';
        write_contact(out, exact->query(s, opts->law));
      }
      out << "\n";
    }
    if (!out) throw hb::IoError((opts->out_csv.empty() ? std::string("stdout") : opts->out_csv) + ": write failed");
  });
}
