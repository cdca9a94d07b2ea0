// hapticbox compress BOX -o OUT.hbox --codec haar|block [--max-error E | --ratio R] [--json]
// Compresses the tables of an uncompressed box file without baking again.
#include "cli_support.h"
#include "figure_text.h"
#include "commands.h"
#include "errors.h"
#include "store/box_file.h"
#include <algorithm>
#include <filesystem>
#include <iostream>

void add_compress_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("compress", "Compress the tables of an uncompressed box file");
  struct Opts {
    std::string box, out, codec = "block";
    hb::CodecOptions codec_options;
    bool json = false;
    bool strict = false;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_option("BOX", opts->box, "Box file with uncompressed tables")->required();
  cmd->add_option("-o,--output", opts->out, "Output box file (.hbox)")->required();
  cmd->add_option("--codec", opts->codec, "Table codec: haar (the paper's) or block (ours)")
      ->check(CLI::IsMember({"haar", "block"}))->capture_default_str();
  hb::cli::add_codec_bound_options(*cmd, opts->codec_options, &opts->strict);
  cmd->add_flag("--json", opts->json, "Print a JSON summary");
  cmd->callback([opts] {
    hb::cli::check_output_file(opts->out);
    const hb::BoxScene scene = hb::load_box_file(opts->box);
    opts->codec_options.codec = hb::parse_codec(opts->codec);
    if (!has_tables(scene.parts()))
      throw hb::cli::UsageError(opts->box + ": its boxes are frames without tables (the bake answered the scene by "
                                "exact Embree): nothing to compress");
    for (const hb::HapticBox& box : scene.parts().boxes)
      if (box.codec() != hb::CodecId::none)
        throw hb::cli::UsageError(opts->box + ": already compressed (codec " + hb::codec_name(box.codec()) + ")");
    const hb::BoxScene out(hb::compressed(scene, opts->codec_options));
    hb::save_box_file(out, opts->out);
    std::uint64_t raw = 0, bytes = 0;
    double t_max = 0, t_mean = 0, bound = 0;
    for (const hb::HapticBox& box : out.parts().boxes) {
      raw += box.raw_table_bytes();
      bytes += box.table_bytes();
      t_max = std::max<double>(t_max, box.codec_stats().t_error_max);
      t_mean += box.codec_stats().t_error_mean / double(out.parts().boxes.size());
      bound = std::max<double>(bound, box.codec_stats().max_error_bound);
    }
    nlohmann::json j = {{"input", opts->box}, {"output", opts->out}, {"codec", opts->codec},
                              {"bytes", std::filesystem::file_size(opts->out)}, {"table_bytes", bytes},
                              {"compression_ratio", double(raw) / double(bytes)}, {"max_error_bound", bound},
                              {"t_error_max", t_max}};
    hb::cli::check_ratio_target(opts->codec_options.ratio, double(raw) / double(bytes), bound, t_mean, opts->strict, j);
    if (opts->json) {
      hb::cli::print_json(j);
      return;
    }
    std::cout << "compressed " << opts->out << ": codec " << opts->codec << ", ratio " << hb::sig(double(raw) / double(bytes))
              << ":1, bound " << hb::percent(bound) << ", t error max " << hb::percent(t_max) << " (of the box diagonal)\n";
  });
}
