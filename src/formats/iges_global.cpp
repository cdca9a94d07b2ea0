// IGES global section: the file's G lines (column 73 'G') carry, in columns 1-72, fields
// separated by the parameter delimiter (field 1, default ',') and ended by the record
// delimiter (field 2, default ';'); strings are Hollerith (nHtext, n characters after the H).
#include "formats/iges_global.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace hb {

namespace {

std::string upper_trimmed(std::string s) {
  const std::size_t a = s.find_first_not_of(' ');
  const std::size_t b = s.find_last_not_of(' ');
  s = a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
  for (char& c : s) c = char(std::toupper((unsigned char)c));
  return s;
}

// Millimetres per unit for a unit flag 1-11 (IGES 5.3, table 3), and the names that go with it.
struct UnitOfFlag {
  double mm;
  const char* names[3];
};
const UnitOfFlag kUnits[12] = {{0, {}},
                               {25.4, {"IN", "INCH", nullptr}},
                               {1.0, {"MM", nullptr, nullptr}},
                               {0, {}},  // 3: the name says
                               {304.8, {"FT", nullptr, nullptr}},
                               {1609344.0, {"MI", nullptr, nullptr}},
                               {1000.0, {"M", nullptr, nullptr}},
                               {1e6, {"KM", nullptr, nullptr}},
                               {0.0254, {"MIL", nullptr, nullptr}},
                               {0.001, {"UM", "MICRON", nullptr}},
                               {10.0, {"CM", nullptr, nullptr}},
                               {2.54e-5, {"UIN", nullptr, nullptr}}};

} // namespace

std::vector<std::string> parse_iges_global(const std::string& name, const std::string& bytes) {
  // Columns 1-72 of every line whose column 73 is 'G', in file order.
  std::string g;
  std::size_t at = 0;
  while (at < bytes.size()) {
    std::size_t nl = bytes.find('\n', at);
    if (nl == std::string::npos) nl = bytes.size();
    std::string line = bytes.substr(at, nl - at);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.size() >= 73 && line[72] == 'G') g += line.substr(0, 72);
    at = nl + 1;
  }
  if (g.empty()) throw InvalidInput(name + ": no IGES global section (no line marked G in column 73)");
  char param = ',', record = ';';
  std::vector<std::string> fields;
  std::size_t i = 0;
  auto fail = [&](const std::string& why) -> void {
    throw InvalidInput(name + ": the IGES global section is damaged (field " + std::to_string(fields.size() + 1) + ": " + why +
                       "): its length unit cannot be trusted");
  };
  // Fields 1 and 2 may redefine the delimiters ("1H|" style); empty means the default.
  for (;;) {
    while (i < g.size() && g[i] == ' ') ++i;
    std::string value;
    // A Hollerith string: digits, 'H', then that many characters.
    std::size_t d = i;
    while (d < g.size() && std::isdigit((unsigned char)g[d])) ++d;
    if (d > i && d < g.size() && (g[d] == 'H' || g[d] == 'h')) {
      const unsigned long n = std::strtoul(g.substr(i, d - i).c_str(), nullptr, 10);
      if (n > g.size() - d - 1) fail("a string of " + g.substr(i, d - i) + " characters runs past the section");
      value = g.substr(d + 1, n);
      i = d + 1 + n;
      while (i < g.size() && g[i] == ' ') ++i;
    } else {
      while (i < g.size() && g[i] != param && g[i] != record) value += g[i++];
      value = upper_trimmed(value);
    }
    if (fields.size() == 0 && !value.empty()) param = value[0];
    if (fields.size() == 1 && !value.empty()) record = value[0];
    fields.push_back(value);
    if (i >= g.size()) fail("the section ends without its record delimiter");
    if (g[i] == record) break;
    if (g[i] != param) fail("'" + quoted_text(std::string(1, g[i])) + "' where a delimiter belongs");
    ++i;
    if (fields.size() > 64) fail("more than 64 fields");
  }
  return fields;
}

double iges_mm_per_unit(const std::string& name, const std::string& bytes) {
  const std::vector<std::string> f = parse_iges_global(name, bytes);
  if (f.size() < 15)
    throw InvalidInput(name + ": the IGES global section ends after " + std::to_string(f.size()) +
                       " fields, before its unit flag and name (fields 14 and 15): its length unit cannot be trusted");
  const std::string& flag_text = f[13];
  const std::string unit = upper_trimmed(f[14]);
  char* end = nullptr;
  const long flag = flag_text.empty() ? 1 : std::strtol(flag_text.c_str(), &end, 10);  // empty: the default, inches
  if (!flag_text.empty() && (*end || flag < 1 || flag > 11))
    throw InvalidInput(name + ": the IGES global section's unit flag (field 14) is '" + quoted_text(flag_text) +
                       "', not 1 to 11: its length unit cannot be trusted");
  if (flag == 3) {
    for (int k = 1; k <= 11; ++k)
      for (const char* n : kUnits[k].names)
        if (n && unit == n) return kUnits[k].mm;
    throw InvalidInput(name + ": the IGES global section's unit flag 3 takes its unit from the name (field 15), and '" +
                       quoted_text(unit) + "' is not a unit");
  }
  if (!unit.empty()) {
    bool agrees = false;
    for (const char* n : kUnits[flag].names) agrees = agrees || (n && unit == n);
    if (!agrees)
      throw InvalidInput(name + ": the IGES global section's unit flag " + std::to_string(flag) + " (field 14) and unit name '" +
                         quoted_text(unit) + "' (field 15) disagree: the file is damaged and its length unit cannot be trusted");
  }
  return kUnits[flag].mm;
}

} // namespace hb
