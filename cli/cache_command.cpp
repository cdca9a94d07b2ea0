// hapticbox cache [--clear] [--json]
// The box cache (hb::BoxCache, shared with the window): where it is, how many boxes and how
// many bytes it holds; --clear removes them.
#include "cli_support.h"
#include "figure_text.h"
#include "commands.h"
#include "recipe/box_cache.h"
#include <iostream>

void add_cache_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("cache", "Show (or clear) the box cache shared by sweep, report and the window");
  struct Opts {
    bool clear = false;
    bool json = false;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_flag("--clear", opts->clear, "Remove every cached box file");
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->callback([opts] {
    const hb::BoxCache cache;
    const hb::BoxCacheUsage before = cache.usage();
    const hb::BoxCacheUsage removed = opts->clear ? cache.clear() : hb::BoxCacheUsage{};
    const hb::BoxCacheUsage now = opts->clear ? cache.usage() : before;
    if (opts->json) {
      nlohmann::json j = {{"dir", cache.dir()}, {"files", now.files}, {"bytes", now.bytes}};
      if (opts->clear) j["removed"] = {{"files", removed.files}, {"bytes", removed.bytes}};
      hb::cli::print_json(j);
      return;
    }
    if (opts->clear)
      std::cout << "removed " << removed.files << " box file(s), " << hb::bytes_text(removed.bytes) << " from "
                << cache.dir() << "\n";
    else
      std::cout << cache.dir() << ": " << now.files << " box file(s), " << hb::bytes_text(now.bytes) << "\n";
  });
}
