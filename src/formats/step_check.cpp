// STEP references: one pass over the DATA section, skipping strings ('...', '' inside) and
// comments (/* */); "#N =" at the start of a statement defines N, any other "#N" refers to it.
#include "formats/step_check.h"
#include "errors.h"
#include <cctype>
#include <cstdint>
#include <unordered_set>
#include <utility>
#include <vector>

namespace hb {

void check_step_references(const std::string& name, const std::string& bytes) {
  std::size_t at = bytes.find("DATA;");
  if (at == std::string::npos) throw InvalidInput(name + ": not a STEP file (no DATA section)");
  at += 5;
  std::unordered_set<std::uint64_t> defined;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> references;  // (from, to)
  bool statement_start = true;
  std::uint64_t current = 0;
  const std::size_t n = bytes.size();
  while (at < n) {
    const char c = bytes[at];
    if (c == '\'') {
      std::size_t k = at + 1;
      for (;;) {
        if (k >= n) throw InvalidInput(name + ": a STEP string is not closed (instance #" + std::to_string(current) + ")");
        if (bytes[k] == '\'') {
          if (k + 1 < n && bytes[k + 1] == '\'') {
            k += 2;
            continue;
          }
          break;
        }
        ++k;
      }
      at = k + 1;
      statement_start = false;
      continue;
    }
    if (c == '/' && at + 1 < n && bytes[at + 1] == '*') {
      const std::size_t end = bytes.find("*/", at + 2);
      if (end == std::string::npos) throw InvalidInput(name + ": a STEP comment is not closed");
      at = end + 2;
      continue;
    }
    if (c == '#') {
      std::size_t k = at + 1;
      std::uint64_t id = 0;
      while (k < n && std::isdigit((unsigned char)bytes[k]) && id < (std::uint64_t(1) << 60)) id = id * 10 + std::uint64_t(bytes[k++] - '0');
      if (k == at + 1) {  // '#' without digits
        if (statement_start) throw InvalidInput(name + ": a STEP instance name '#' without a number");
        ++at;
        continue;
      }
      if (statement_start) {
        std::size_t e = k;
        while (e < n && std::isspace((unsigned char)bytes[e])) ++e;
        if (e >= n || bytes[e] != '=')
          throw InvalidInput(name + ": STEP statement starting with #" + std::to_string(id) + " is not an instance definition (no '=')");
        if (id == 0) throw InvalidInput(name + ": STEP instance #0 (instance numbers start at 1)");
        if (!defined.insert(id).second) throw InvalidInput(name + ": STEP instance #" + std::to_string(id) + " is defined twice");
        current = id;
        statement_start = false;
        at = e + 1;
        continue;
      }
      references.emplace_back(current, id);
      at = k;
      continue;
    }
    if (c == ';') {
      statement_start = true;
      ++at;
      continue;
    }
    if (statement_start && !std::isspace((unsigned char)c)) {
      if (bytes.compare(at, 7, "ENDSEC;") == 0) break;
      statement_start = false;
    }
    ++at;
  }
  if (defined.empty()) throw InvalidInput(name + ": the STEP DATA section defines no instance");
  for (const auto& [from, to] : references)
    if (!defined.count(to))
      throw InvalidInput(name + ": STEP instance #" + std::to_string(from) + " refers to #" + std::to_string(to) +
                         ", which the file does not define (a damaged file)");
}

} // namespace hb
