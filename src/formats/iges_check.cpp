// IGES structure, checked in three passes:
//  1. Lines: column 73 the section letter (S, G, D, P, T in that order), columns 74-80 the
//     line's number within its section (1, 2, ...); the T line's counts against the sections.
//  2. Directory entries (two D lines each, eight-column integer fields): the type twice, the
//     parameter lines within the P section and pointing back at the entry (columns 66-72),
//     the pointer fields 0 or an entry; each entry's parameter data split into its values
//     (Hollerith strings nH... kept whole; delimiters from the global section).
//  3. The parameter data of the entities solids and trimmed surfaces are made of, held to
//     their layout (IGES 5.3, chapter 4): counts against the values present, numbers where
//     numbers belong, pointers to entries of a fitting type, list indices within their list.
//     B-spline curves and surfaces (126, 128): every value a number, degrees from 1 to the
//     control points less one, as many values as the counts need, knots that never decrease,
//     positive weights and a parameter range within the knots' span.
#include "formats/iges_check.h"
#include "errors.h"
#include "formats/iges_global.h"
#include "formats/quoted_text.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <initializer_list>
#include <utility>
#include <vector>

namespace hb {

namespace {

struct IgesEntry {
  long type = 0, form = 0;
  std::size_t de_line = 0;               // the entry's sequence number (odd)
  std::vector<std::string> params;       // the values after the type
};

struct IgesFile {
  std::string name;
  std::vector<std::string> d, p;  // the D and P lines, columns 1-80
  std::size_t d_first = 0, p_first = 0;  // their first lines in the file (1-based)
  std::vector<IgesEntry> entries;
};

[[noreturn]] void refuse(const IgesFile& f, const std::string& why) {
  throw InvalidInput(f.name + ": " + why + ": the IGES file is damaged");
}

std::string blank_trimmed(const std::string& s) {
  const std::size_t a = s.find_first_not_of(' ');
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(' ') - a + 1);
}

// A whole number (an optional sign and digits); empty text is 0, IGES's default.
bool parse_integer(const std::string& text, long& out) {
  const std::string t = blank_trimmed(text);
  out = 0;
  if (t.empty()) return true;
  std::size_t i = (t[0] == '+' || t[0] == '-') ? 1 : 0;
  if (i == t.size() || t.size() - i > 12) return false;
  for (std::size_t k = i; k < t.size(); ++k)
    if (!std::isdigit((unsigned char)t[k])) return false;
  out = std::strtol(t.c_str(), nullptr, 10);
  return true;
}

// A finite real below 1e100 (IGES writes exponents with E or D); empty text is 0.
bool parse_real(const std::string& text) {
  std::string t = blank_trimmed(text);
  if (t.empty()) return true;
  for (char& c : t)
    if (c == 'D' || c == 'd') c = 'E';
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  // Below OpenCASCADE's infinity (2e100, Precision::Infinite).
  return end == t.c_str() + t.size() && std::fabs(v) < 1e100 && t.find_first_of("xXnNiI") == std::string::npos;
}

// Pass 1: the sections and their line numbers.
void split_sections(IgesFile& f, const std::string& bytes) {
  static const char kOrder[] = "SGDPT";
  std::size_t counts[5] = {0, 0, 0, 0, 0};
  std::string t_line;
  int section = 0;
  std::size_t at = 0, line_no = 0;
  while (at < bytes.size()) {
    std::size_t nl = bytes.find('\n', at);
    if (nl == std::string::npos) nl = bytes.size();
    std::string line = bytes.substr(at, nl - at);
    at = nl + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t\x1a") == std::string::npos) {
      if (bytes.find_first_not_of(" \t\r\n\x1a", at) == std::string::npos) break;  // trailing blank lines
      refuse(f, "line " + std::to_string(line_no) + " is blank (an IGES line has 80 columns)");
    }
    if (line.size() < 80)
      refuse(f, "line " + std::to_string(line_no) + " has " + std::to_string(line.size()) + " columns, not 80");
    if (line.find_first_not_of(' ', 80) != std::string::npos)
      refuse(f, "line " + std::to_string(line_no) + " has text past column 80 (" + std::to_string(line.size()) + " columns): lines run together");
    // IGES is text: a control byte (a NUL inside a number ended it there for OpenCASCADE,
    // which read a different curve without a word).
    for (std::size_t k = 0; k < line.size(); ++k)
      if ((unsigned char)line[k] < 0x20 || line[k] == 0x7F)
        refuse(f, "line " + std::to_string(line_no) + " holds the control byte " + quoted_text(line.substr(k, 1)) + " in column " +
                      std::to_string(k + 1));
    if (!t_line.empty()) refuse(f, "line " + std::to_string(line_no) + " follows the terminate (T) line");
    const char* letter = std::char_traits<char>::find(kOrder, 5, line[72]);
    if (!letter) refuse(f, "line " + std::to_string(line_no) + " has '" + quoted_text(line.substr(72, 1)) + "' in column 73, not a section letter (S, G, D, P, T)");
    const int s = int(letter - kOrder);
    if (s < section)
      refuse(f, "line " + std::to_string(line_no) + " of section " + std::string(1, line[72]) + " comes after section " + kOrder[section]);
    section = s;
    long seq = 0;
    if (!parse_integer(line.substr(73, 7), seq) || seq != long(counts[s] + 1))
      refuse(f, "line " + std::to_string(line_no) + " is numbered '" + quoted_text(blank_trimmed(line.substr(73, 7))) + "' where " + line[72] +
                    std::to_string(counts[s] + 1) + " belongs (a line missing, repeated or damaged)");
    ++counts[s];
    if (s == 2) {
      if (f.d.empty()) f.d_first = line_no;
      f.d.push_back(line);
    } else if (s == 3) {
      if (f.p.empty()) f.p_first = line_no;
      f.p.push_back(line);
    } else if (s == 4) {
      t_line = line;
    }
  }
  if (t_line.empty()) refuse(f, "no terminate (T) line: the file is cut short");
  for (int s = 0; s < 4; ++s) {
    long declared = 0;
    if (t_line[std::size_t(8 * s)] != kOrder[s] || !parse_integer(t_line.substr(std::size_t(8 * s + 1), 7), declared) ||
        declared != long(counts[s]))
      refuse(f, std::string("the terminate line counts '") + quoted_text(blank_trimmed(t_line.substr(std::size_t(8 * s), 8))) + "' where the file has " +
                    kOrder[s] + std::to_string(counts[s]) + " lines");
  }
  if (f.d.size() % 2) refuse(f, "the directory section has " + std::to_string(f.d.size()) + " lines, not two an entry");
}

// The values of one entry's parameter data (columns 1-64 of its P lines joined).
std::vector<std::string> split_parameters(const IgesFile& f, const std::string& data, char param, char record, std::size_t de) {
  std::vector<std::string> values;
  std::size_t i = 0;
  for (;;) {
    while (i < data.size() && data[i] == ' ') ++i;
    std::string value;
    std::size_t d = i;
    while (d < data.size() && std::isdigit((unsigned char)data[d])) ++d;
    if (d > i && d < data.size() && (data[d] == 'H' || data[d] == 'h')) {  // nHtext
      const unsigned long n = std::strtoul(data.substr(i, d - i).c_str(), nullptr, 10);
      if (n > data.size() - d - 1) refuse(f, "the parameter data of entry D" + std::to_string(de) + " holds a string running past its lines");
      value = data.substr(d, n + 1);
      i = d + 1 + n;
      while (i < data.size() && data[i] == ' ') ++i;
    } else {
      while (i < data.size() && data[i] != param && data[i] != record) value += data[i++];
    }
    values.push_back(blank_trimmed(value));
    if (i >= data.size())
      refuse(f, "the parameter data of entry D" + std::to_string(de) + " does not end with the record delimiter '" + std::string(1, record) + "'");
    if (data[i] == record) return values;
    if (data[i] != param) refuse(f, "the parameter data of entry D" + std::to_string(de) + " has '" + quoted_text(std::string(1, data[i])) + "' where a delimiter belongs");
    ++i;
  }
}

// Pass 2: directory entries and their parameter data.
void read_entries(IgesFile& f, char param, char record) {
  const std::size_t n = f.d.size() / 2;
  f.entries.resize(n);
  auto field = [&](std::size_t e, int k, long& v) {  // field k (1-20) of entry e
    const std::string& line = f.d[2 * e + (k > 10 ? 1 : 0)];
    return parse_integer(line.substr(std::size_t(8 * ((k - 1) % 10)), 8), v);
  };
  for (std::size_t e = 0; e < n; ++e) {
    IgesEntry& entry = f.entries[e];
    entry.de_line = 2 * e + 1;
    const std::string where = "directory entry D" + std::to_string(entry.de_line) + " (line " + std::to_string(f.d_first + 2 * e) + ")";
    long v[16] = {};
    for (int k : {1, 2, 3, 4, 5, 6, 7, 8, 11, 12, 13, 14, 15})
      if (!field(e, k, v[k])) refuse(f, where + ": field " + std::to_string(k) + " is not a whole number");
    if (v[1] != v[11] || v[1] < 0 || v[1] > 9999)
      refuse(f, where + ": entity type " + std::to_string(v[1]) + " on its first line, " + std::to_string(v[11]) + " on its second");
    entry.type = v[1];
    entry.form = v[15];
    const long lines = v[14];
    if (v[2] < 1 || lines < 1 || std::size_t(v[2]) > f.p.size() || std::size_t(lines) > f.p.size() - std::size_t(v[2]) + 1)
      refuse(f, where + ": its parameter data (P" + std::to_string(v[2]) + ", " + std::to_string(lines) + " lines) is not within the " +
                    std::to_string(f.p.size()) + " P lines");
    auto pointer_ok = [&](long p) { return p > 0 && (p % 2) == 1 && std::size_t(p) < f.d.size(); };
    const struct {
      int field;
      long value;
      const char* what;
    } pointers[] = {{3, -std::abs(v[3]), "structure"}, {4, v[4], "line font"}, {5, v[5], "level"},     {6, -v[6], "view"},
                    {7, -v[7], "transformation"},      {8, -v[8], "label display"}, {13, v[13], "colour"}};
    for (const auto& ptr : pointers)  // negative: a pointer (the positive fields negated above)
      if (ptr.value < 0 && !pointer_ok(-ptr.value))
        refuse(f, where + ": its " + ptr.what + " pointer (field " + std::to_string(ptr.field) + ") " + std::to_string(std::abs(ptr.value)) +
                      " is not an entry");
    if (v[6] < 0 || v[7] < 0 || v[8] < 0) refuse(f, where + ": a negative view, transformation or label pointer");
    std::string data;
    for (long l = v[2]; l < v[2] + lines; ++l) {
      const std::string& p = f.p[std::size_t(l - 1)];
      long back = 0;
      if (!parse_integer(p.substr(65, 7), back) || back != long(entry.de_line))
        refuse(f, "P line " + std::to_string(l) + " (line " + std::to_string(f.p_first + std::size_t(l) - 1) + ") belongs to D" +
                      quoted_text(blank_trimmed(p.substr(65, 7))) + ", but " + where + " points to it");
      data += p.substr(0, 64);
    }
    std::vector<std::string> values = split_parameters(f, data, param, record, entry.de_line);
    long type = -1;
    if (!parse_integer(values[0], type) || type != entry.type)
      refuse(f, where + " is of type " + std::to_string(entry.type) + " but its parameter data starts with '" + quoted_text(values[0]) + "'");
    values.erase(values.begin());
    entry.params = std::move(values);
  }
  for (std::size_t e = 0; e < n; ++e) {
    long t = 0;
    if (field(e, 7, t) && t > 0 && f.entries[std::size_t(t - 1) / 2].type != 124)
      refuse(f, "directory entry D" + std::to_string(2 * e + 1) + "'s transformation is D" + std::to_string(t) + ", of type " +
                    std::to_string(f.entries[std::size_t(t - 1) / 2].type) + ", not 124");
  }
}

// Pass 3: one entity's parameter data against its layout.
class EntityCheck {
public:
  EntityCheck(const IgesFile& f, const IgesEntry& e) : f_(f), e_(e) {}

  [[noreturn]] void fail(const std::string& why) const {
    refuse(f_, "entity D" + std::to_string(e_.de_line) + " (type " + std::to_string(e_.type) + "): " + why);
  }
  void need(std::size_t count) const {
    if (e_.params.size() < count)
      fail("its parameter data has " + std::to_string(e_.params.size()) + " values where its counts need " + std::to_string(count));
  }
  long integer(std::size_t k) const {
    need(k + 1);
    long v = 0;
    if (!parse_integer(e_.params[k], v)) fail("value " + std::to_string(k + 1) + " '" + quoted_text(e_.params[k]) + "' is not a whole number");
    return v;
  }
  long count(std::size_t k, long at_least = 0) const {
    const long v = integer(k);
    if (v < at_least || std::size_t(v) > e_.params.size())
      fail("its count " + std::to_string(v) + " (value " + std::to_string(k + 1) + ") does not fit its " + std::to_string(e_.params.size()) + " values");
    return v;
  }
  void reals(std::size_t from, std::size_t n) const {
    need(from + n);
    for (std::size_t k = from; k < from + n; ++k)
      if (!parse_real(e_.params[k])) fail("value " + std::to_string(k + 1) + " '" + quoted_text(e_.params[k]) + "' is not a number below 1e100");
  }
  // A pointer to an entry of one of `types` (any type when empty); 0 allowed when `optional`.
  const IgesEntry* pointer(std::size_t k, std::initializer_list<long> types, bool optional = false) const {
    const long p = integer(k);
    if (p == 0 && optional) return nullptr;
    if (p <= 0 || p % 2 == 0 || std::size_t(p) >= f_.d.size())
      fail("value " + std::to_string(k + 1) + " is pointer " + std::to_string(p) + ", not an entry of the file");
    const IgesEntry& target = f_.entries[std::size_t(p - 1) / 2];
    if (types.size() && std::find(types.begin(), types.end(), target.type) == types.end())
      fail("value " + std::to_string(k + 1) + " points to D" + std::to_string(p) + ", of type " + std::to_string(target.type) +
           ", where another kind of entity belongs");
    return &target;
  }
  // How many items a list entity (502 vertices, 504 edges) holds, as its first value says.
  long list_length(const IgesEntry& list) const {
    long n = 0;
    if (list.params.empty() || !parse_integer(list.params[0], n)) fail("it points to a list without its count");
    return n;
  }
  void index_within(std::size_t k, const IgesEntry& list) const {
    const long i = integer(k), n = list_length(list);
    if (i < 1 || i > n)
      fail("value " + std::to_string(k + 1) + " is index " + std::to_string(i) + " into D" + std::to_string(list.de_line) + ", a list of " +
           std::to_string(n));
  }
  const IgesEntry& entry() const { return e_; }

private:
  const IgesFile& f_;
  const IgesEntry& e_;
};

const std::initializer_list<long> kCurves = {100, 102, 104, 106, 110, 112, 126, 130};
const std::initializer_list<long> kSurfaces = {108, 114, 118, 120, 122, 128, 140, 143, 144, 190, 192, 194, 196, 198};

// A B-spline (126 curve, 128 surface): its degrees at least 1 and at most its control points
// less one (OpenCASCADE crashed on a surface of too high a degree), its values as many as its
// counts need, knots that never decrease and positive weights (a weight changed to 0 collapsed
// the sphere's face to a sliver, read without a word).
void check_bspline(const EntityCheck& c) {
  const std::vector<std::string>& p = c.entry().params;
  const bool surface = c.entry().type == 128;
  // Upper indices K (control points K + 1) and degrees M: values 1-2 of a curve, 1-4 of a surface.
  const long uk = c.count(0), vk = surface ? c.count(1) : 0;
  const long um = c.integer(surface ? 2 : 1), vm = surface ? c.integer(3) : 1;
  const char* axes[2] = {surface ? " in u" : "", " in v"};
  for (int axis = 0; axis < (surface ? 2 : 1); ++axis) {
    const long k = axis ? vk : uk, m = axis ? vm : um;
    const std::size_t value = surface ? std::size_t(3 + axis) : 2;
    if (m < 1 || m > k)
      c.fail("its degree" + std::string(axes[axis]) + " (value " + std::to_string(value) + ") is " + std::to_string(m) + " but its " +
             std::to_string(k + 1) + " control points" + axes[axis] + " allow a degree from 1 to " + std::to_string(k));
  }
  std::vector<std::pair<std::size_t, std::size_t>> knots = {{surface ? 9 : 6, std::size_t(uk + um + 2)}};
  if (surface) knots.push_back({knots[0].first + knots[0].second, std::size_t(vk + vm + 2)});
  const std::size_t weights_at = knots.back().first + knots.back().second, weights = std::size_t(uk + 1) * std::size_t(vk + 1);
  const std::size_t needed = weights_at + 4 * weights + (surface ? 4 : 2);  // weights, points, the parameter range
  if (needed > p.size())
    c.fail("its counts and degrees need " + std::to_string(needed) + " values, its parameter data holds " + std::to_string(p.size()));
  auto value = [&](std::size_t i) {
    std::string t = blank_trimmed(p[i]);
    for (char& ch : t)
      if (ch == 'D' || ch == 'd') ch = 'E';
    return std::strtod(t.c_str(), nullptr);
  };
  for (const auto& [at, n] : knots)
    for (std::size_t i = at + 1; i < at + n; ++i)
      if (value(i) < value(i - 1)) c.fail("knot " + std::to_string(i - at + 1) + " (value " + std::to_string(i + 1) + ") is below the one before it");
  for (std::size_t i = weights_at; i < weights_at + weights; ++i)
    if (!(value(i) > 0)) c.fail("weight " + std::to_string(i - weights_at + 1) + " (value " + std::to_string(i + 1) + ") is not positive");
  // The parameter range within the knots' span, T(0) to T(N) (OpenCASCADE crashed on a curve
  // whose range ran past its knots).
  const std::size_t range_at = weights_at + 4 * weights;
  for (std::size_t axis = 0; axis < knots.size(); ++axis) {
    const auto [at, n] = knots[axis];
    const long m = axis ? vm : um;
    const double lo = value(at + std::size_t(m)), hi = value(at + n - 1 - std::size_t(m));
    const double a = value(range_at + 2 * axis), b = value(range_at + 2 * axis + 1);
    const double slack = 1e-6 * std::max({1.0, std::fabs(lo), std::fabs(hi)});
    if (!(a >= lo - slack && b <= hi + slack && a < b))
      c.fail("its parameter range" + std::string(axes[axis]) + " " + std::to_string(a) + " to " + std::to_string(b) + " (values " +
             std::to_string(range_at + 2 * axis + 1) + "-" + std::to_string(range_at + 2 * axis + 2) + ") is not within its knots' span " +
             std::to_string(lo) + " to " + std::to_string(hi));
  }
}

void check_entity(const IgesFile& f, const IgesEntry& e) {
  const EntityCheck c(f, e);
  switch (e.type) {
    case 126:
    case 128:
      c.reals(0, e.params.size());
      check_bspline(c);
      break;
    case 100: c.reals(0, 7); break;
    case 110: c.reals(0, 6); break;
    case 116: c.reals(0, 3); break;
    case 123: c.reals(0, 3); break;
    case 124: c.reals(0, 12); break;
    case 102: {
      const long n = c.count(0);
      std::initializer_list<long> parts = {100, 102, 104, 106, 110, 112, 116, 126, 130};
      for (long i = 0; i < n; ++i) c.pointer(std::size_t(1 + i), parts);
      break;
    }
    case 142:
      c.integer(0);
      c.pointer(1, kSurfaces);
      c.pointer(2, kCurves, true);
      c.pointer(3, kCurves, true);
      break;
    case 144: {
      c.pointer(0, kSurfaces);
      const long outer = c.integer(1), inner = c.count(2);
      if (outer != 0 && outer != 1) c.fail("its outer-boundary flag is " + std::to_string(outer) + ", not 0 or 1");
      c.pointer(3, {142}, outer == 0);
      for (long i = 0; i < inner; ++i) c.pointer(std::size_t(4 + i), {142});
      break;
    }
    case 186: {
      c.pointer(0, {514});
      c.integer(1);
      const long voids = c.count(2);
      for (long i = 0; i < voids; ++i) {
        c.pointer(std::size_t(3 + 2 * i), {514});
        c.integer(std::size_t(4 + 2 * i));
      }
      break;
    }
    case 190:
      c.pointer(0, {116});
      c.pointer(1, {123});
      if (e.form == 1) c.pointer(2, {123});
      break;
    case 192:
    case 194:
      c.pointer(0, {116});
      c.pointer(1, {123});
      c.reals(2, e.type == 192 ? 1 : 2);
      if (e.form == 1) c.pointer(e.type == 192 ? 3 : 4, {123});
      break;
    case 196:
      c.pointer(0, {116});
      c.reals(1, 1);
      if (e.form == 1) {
        c.pointer(2, {123});
        c.pointer(3, {123});
      }
      break;
    case 502: {
      const long n = c.count(0, 1);
      c.reals(1, 3 * std::size_t(n));
      break;
    }
    case 504: {
      const long n = c.count(0, 1);
      for (long i = 0; i < n; ++i) {
        const std::size_t b = std::size_t(1 + 5 * i);
        c.pointer(b, kCurves);
        c.index_within(b + 2, *c.pointer(b + 1, {502}));
        c.index_within(b + 4, *c.pointer(b + 3, {502}));
      }
      break;
    }
    case 508: {
      const long n = c.count(0, 1);
      std::size_t at = 1;
      for (long i = 0; i < n; ++i) {
        const long kind = c.integer(at);
        if (kind != 0 && kind != 1) c.fail("edge " + std::to_string(i + 1) + " has type " + std::to_string(kind) + ", not 0 (edge) or 1 (vertex)");
        c.index_within(at + 2, *c.pointer(at + 1, {kind == 0 ? 504L : 502L}));
        c.integer(at + 3);
        const long curves = c.count(at + 4);
        for (long k = 0; k < curves; ++k) {
          c.integer(at + 5 + 2 * std::size_t(k));
          c.pointer(at + 6 + 2 * std::size_t(k), kCurves);
        }
        at += 5 + 2 * std::size_t(curves);
      }
      break;
    }
    case 510: {
      c.pointer(0, kSurfaces);
      const long loops = c.count(1, 1);
      c.integer(2);
      for (long i = 0; i < loops; ++i) c.pointer(std::size_t(3 + i), {508});
      break;
    }
    case 514: {
      const long faces = c.count(0, 1);
      for (long i = 0; i < faces; ++i) {
        c.pointer(std::size_t(1 + 2 * i), {510});
        c.integer(std::size_t(2 + 2 * i));
      }
      break;
    }
    default: break;
  }
}

} // namespace

void check_iges_structure(const std::string& name, const std::string& bytes) {
  IgesFile f;
  f.name = name;
  split_sections(f, bytes);
  const std::vector<std::string> global = parse_iges_global(name, bytes);
  const char param = global.size() > 0 && !global[0].empty() ? global[0][0] : ',';
  const char record = global.size() > 1 && !global[1].empty() ? global[1][0] : ';';
  read_entries(f, param, record);
  for (const IgesEntry& e : f.entries) check_entity(f, e);
}

} // namespace hb
