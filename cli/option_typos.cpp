// Unknown options named with the nearest real one (option_typos.h).
#include "option_typos.h"
#include <algorithm>
#include <vector>

namespace hb::cli {
namespace {

// Levenshtein distance between two short words.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

void add_long_names(const CLI::App& app, std::vector<std::string>& names) {
  for (const CLI::Option* o : app.get_options())
    for (const std::string& n : o->get_lnames()) names.push_back(n);
}

} // namespace

std::string unknown_option_message(const CLI::App& app, const std::string& command, int argc, char** argv) {
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; }))
    if (s->get_name() == command) sub = s;
  if (!sub) return "";
  std::vector<std::string> names;
  add_long_names(app, names);
  add_long_names(*sub, names);
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--") break;  // what follows is data
    if (a.size() < 3 || a.compare(0, 2, "--") != 0) continue;
    const std::string name = a.substr(2, a.find('=') == std::string::npos ? std::string::npos : a.find('=') - 2);
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    std::string nearest;
    std::size_t best = std::max<std::size_t>(2, name.size() / 3) + 1;
    for (const std::string& n : names)
      if (const std::size_t d = edit_distance(name, n); d < best) best = d, nearest = n;
    return "unknown option --" + name + " for '" + command + "'" +
           (nearest.empty() ? std::string() : " (did you mean --" + nearest + "?)") + "; hapticbox " + command +
           " --help lists its options";
  }
  return "";
}

} // namespace hb::cli
