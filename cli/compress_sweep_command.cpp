// hapticbox compress-sweep BOX [MESH] [--codecs haar,block] [--errors 1e-4,...] [--csv OUT.csv]
//                          [--json-out OUT.json] [--samples N] [--json]
// The compression curve (paper Figure 11): ratio against t, normal and force errors.
#include "cli_support.h"
#include "figure_text.h"
#include "perceptible_text.h"
#include "commands.h"
#include "errors.h"
#include "evaluation/compression_sweep.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "store/box_file.h"
#include "mesh/mesh_io.h"
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

namespace {

nlohmann::json point_json(const hb::CompressionSweepPoint& p, bool exact) {
  nlohmann::json j = {{"codec", hb::codec_name(p.codec)},
                      {"max_error", p.max_error},
                      {"compression_ratio", p.ratio},
                      {"bytes", p.bytes},
                      {"t_error_mean", p.t_error_mean},
                      {"t_error_max", p.t_error_max},
                      {"normal_error_mean_deg", p.normal_error_mean_deg},
                      {"normal_error_max_deg", p.normal_error_max_deg},
                      {"contact_agreement_vs_raw", p.contact_agreement_vs_raw},
                      {"force_error_vs_raw_median", p.force_error_vs_raw_median},
                      {"force_error_vs_raw_p95", p.force_error_vs_raw_p95},
                      {"perceptible_vs_raw", p.perceptible_vs_raw}};
  if (exact) {
    j["contact_agreement"] = p.contact_agreement;
    j["force_error_median"] = p.force_error_median;
    j["perceptible_vs_exact"] = p.perceptible_vs_exact;
  }
  return j;
}

} // namespace

void add_compress_sweep_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("compress-sweep", "Compression ratio against error for each codec (paper Figure 11)");
  struct Opts {
    hb::cli::ModelArgs model;
    std::string box, mesh, csv, json_out;
    std::vector<std::string> codecs{"haar", "block"};
    std::vector<float> errors;
    std::size_t samples = 20000;
    hb::ProbeOptions probes;
    hb::cli::WorkspaceArgs workspace;
    int normal_bits = 9;
    bool json = false;
  };
  auto opts = std::make_shared<Opts>();
  hb::cli::add_model_options(*cmd, opts->model);
  cmd->add_option("BOX", opts->box, "Box file with uncompressed tables (bake --codec none)")->required();
  cmd->add_option("MESH", opts->mesh, "The mesh it was baked from, for force errors against the exact answer "
                                      "(default: the source mesh named in the box file, when it exists)");
  cmd->add_option("--codecs", opts->codecs, "Codecs to sweep")->delimiter(',')
      ->check(CLI::IsMember({"haar", "block"}))->capture_default_str();
  cmd->add_option("--errors", opts->errors, "Error bounds, relative to the box diagonal")->delimiter(',')
      ->check(hb::cli::finite_range(1e-5, 0.1));
  cmd->add_option("--normal-bits", opts->normal_bits, "Octahedral normal bits per coordinate")
      ->check(CLI::Range(6, 14))->capture_default_str();
  hb::cli::add_probe_options(*cmd, opts->samples, opts->probes.seed, 0);
  cmd->add_option("--csv", opts->csv, "Write the curve as CSV");
  cmd->add_option("--json-out", opts->json_out, "Write the curve as JSON");
  hb::cli::add_workspace_options(*cmd, opts->workspace);
  cmd->add_flag("--json", opts->json, "Print JSON to stdout");
  cmd->callback([opts] {
    const hb::BoxScene scene = hb::load_box_file(opts->box);
    if (!has_tables(scene.parts()))
      throw hb::cli::UsageError(opts->box + ": its boxes are frames without tables (the bake answered the scene by "
                                "exact Embree): no table to compress");
    for (const hb::HapticBox& box : scene.parts().boxes)
      if (box.codec() != hb::CodecId::none)
        throw hb::cli::UsageError(opts->box + ": compress-sweep needs uncompressed tables (bake with --codec none)");
    hb::CompressionSweepOptions o;
    o.codecs.clear();
    for (const auto& c : opts->codecs) o.codecs.push_back(hb::parse_codec(c));
    if (!opts->errors.empty()) o.max_errors = opts->errors;
    o.normal_bits = opts->normal_bits;
    const hb::Workspace ws = opts->workspace.workspace(hb::model_diagonal(scene));
    o.law = ws.law();
    o.judge = opts->workspace.judge();
    std::string mesh_path = opts->mesh;
    if (mesh_path.empty() && std::filesystem::exists(scene.parts().source.mesh_path)) mesh_path = scene.parts().source.mesh_path;
    hb::TriangleMesh mesh;
    std::unique_ptr<hb::ExactQuery> exact;
    if (!mesh_path.empty() && opts->samples > 0) {
      mesh = hb::cli::load_mesh(mesh_path, opts->model);
      exact = std::make_unique<hb::ExactQuery>(mesh);
      o.probes = hb::sample_probes(mesh, opts->samples, opts->probes);
      o.exact = exact.get();
    }
    o.progress = hb::cli::terminal_progress("sweeping");
    const auto points = hb::compression_sweep(scene, o);

    nlohmann::json rows = nlohmann::json::array();
    for (const auto& p : points) rows.push_back(point_json(p, exact != nullptr));
    const nlohmann::json j = {{"box", opts->box},       {"mesh", mesh_path},
                              {"samples", o.probes.size()}, {"normal_bits", opts->normal_bits},
                              {"points", rows},          {"workspace", hb::workspace_json(ws, o.judge)}};
    if (!opts->csv.empty()) {
      std::ofstream out(opts->csv);
      if (!out) throw hb::IoError(opts->csv + ": cannot open for writing");
      const std::vector<std::string> cols = {"codec", "max_error", "compression_ratio", "bytes", "t_error_mean",
                                             "t_error_max", "normal_error_mean_deg", "normal_error_max_deg",
                                             "contact_agreement_vs_raw", "force_error_vs_raw_median",
                                             "force_error_vs_raw_p95", "perceptible_vs_raw", "contact_agreement",
                                             "force_error_median", "perceptible_vs_exact"};
      for (std::size_t c = 0; c < cols.size(); ++c) out << (c ? "," : "") << cols[c];
      out << "\n" << std::setprecision(8);
      for (const auto& r : rows) {
        for (std::size_t c = 0; c < cols.size(); ++c) {
          out << (c ? "," : "");
          if (!r.contains(cols[c])) continue;
          if (r[cols[c]].is_string()) out << r[cols[c]].get<std::string>();
          else out << r[cols[c]].get<double>();
        }
        out << "\n";
      }
      if (!out) throw hb::IoError(opts->csv + ": write failed");
    }
    if (!opts->json_out.empty()) {
      std::ofstream out(opts->json_out);
      if (!out) throw hb::IoError(opts->json_out + ": cannot open for writing");
      out << j.dump(2) << "\n";
      if (!out) throw hb::IoError(opts->json_out + ": write failed");
    }
    if (opts->json) {
      hb::cli::print_json(j);
      return;
    }
    std::cout << "compress-sweep " << opts->box << (mesh_path.empty() ? "" : " vs " + mesh_path) << "\n"
              << "  workspace: " << ws.describe() << "; perceptible: " << hb::thresholds_text(o.judge.thresholds) << "\n"
              << "  codec  bound     ratio   t_mean    t_max     n_mean  n_max   F_vs_raw  agree    F_exact  felt_raw felt_exact\n";
    for (const auto& p : points)
      std::cout << "  " << std::left << std::setw(6) << hb::codec_name(p.codec) << std::right << std::setw(8)
                << std::setprecision(2) << std::scientific << p.max_error << std::fixed << std::setprecision(2)
                << std::setw(8) << p.ratio << std::scientific << std::setprecision(2) << std::setw(10)
                << p.t_error_mean << std::setw(10) << p.t_error_max << std::fixed << std::setprecision(3)
                << std::setw(7) << p.normal_error_mean_deg << std::setw(7) << p.normal_error_max_deg
                << std::setprecision(4) << std::setw(10) << p.force_error_vs_raw_median << std::setw(9)
                << p.contact_agreement << std::setw(9) << p.force_error_median << std::setw(8)
                << hb::percent(p.perceptible_vs_raw) << std::setw(10)
                << (exact ? hb::percent(p.perceptible_vs_exact) : std::string("-")) << "\n";
  });
}
