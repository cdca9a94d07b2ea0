// STEP references: one pass over the DATA section, skipping strings ('...', '' inside) and
// comments (/* */); "#N =" at the start of a statement defines N, any other "#N" refers to it;
// parentheses balance within each statement, nested a bounded depth;
// a number where a token starts must be whole (digits, a fraction, an exponent, a delimiter)
// and below 1e100.
#include "formats/step_check.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
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
  long depth = 0;
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
      // OpenCASCADE keeps instance numbers in an int: #2147483648 crashed its reader.
      if (id > 2147483647u)
        throw InvalidInput(name + ": STEP instance number #" + quoted_text(bytes.substr(at + 1, k - at - 1), 30) +
                           (statement_start ? "" : " (in instance #" + std::to_string(current) + ")") + " is beyond 2147483647");
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
    if (c == '(' || c == ')') {
      // Parentheses balance within a statement and nest at most kMaxStepNesting deep
      // (OpenCASCADE's parser recursed once a level: 100,000 of them overflowed its stack).
      depth += c == '(' ? 1 : -1;
      if (depth < 0) throw InvalidInput(name + ": STEP instance #" + std::to_string(current) + " closes a parenthesis it never opened");
      if (depth > kMaxStepNesting)
        throw InvalidInput(name + ": STEP instance #" + std::to_string(current) + " nests parentheses more than " +
                           std::to_string(kMaxStepNesting) + " deep");
      statement_start = false;
      ++at;
      continue;
    }
    if (c == ';') {
      if (depth != 0)
        throw InvalidInput(name + ": STEP instance #" + std::to_string(current) + " ends with " + std::to_string(depth) +
                           " parentheses left open");
      statement_start = true;
      ++at;
      continue;
    }
    // A number where a token starts: [+-]digits[.digits][E[+-]digits], then a delimiter
    // ("1.5." read as 1.5 by OpenCASCADE: a different direction without a word).
    if (!statement_start && (std::isdigit((unsigned char)c) || ((c == '-' || c == '+') && at + 1 < n && std::isdigit((unsigned char)bytes[at + 1]))) &&
        at > 0 && std::strchr("(,= \t\r\n", bytes[at - 1])) {
      std::size_t k = at + (std::isdigit((unsigned char)c) ? 0 : 1);
      auto digits = [&] {
        const std::size_t from = k;
        while (k < n && std::isdigit((unsigned char)bytes[k])) ++k;
        return k > from;
      };
      bool ok = digits();
      if (ok && k < n && bytes[k] == '.') {
        ++k;
        digits();
      }
      if (ok && k < n && (bytes[k] == 'E' || bytes[k] == 'e')) {
        ++k;
        if (k < n && (bytes[k] == '+' || bytes[k] == '-')) ++k;
        ok = digits();
      }
      if (!ok || k >= n || !std::strchr(",) \t\r\n", bytes[k]))
        throw InvalidInput(name + ": STEP instance #" + std::to_string(current) + " holds '" +
                           quoted_text(bytes.substr(at, std::min<std::size_t>(k + 1, n) - at)) + "', not a number");
      // OpenCASCADE takes 2e100 for infinite (Precision::Infinite); a point at -2.4e65535 (an
      // overflow) kept its translator busy past 60 s.
      const double v = std::strtod(bytes.substr(at, k - at).c_str(), nullptr);
      if (!(std::fabs(v) < 1e100))
        throw InvalidInput(name + ": STEP instance #" + std::to_string(current) + " holds " + quoted_text(bytes.substr(at, k - at), 40) +
                           ", beyond any model's range (1e100)");
      at = k;
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
