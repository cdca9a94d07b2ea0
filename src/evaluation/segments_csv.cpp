// Segments CSV: a header line, then six numbers a row; every error names the line.
#include "evaluation/segments_csv.h"
#include "errors.h"
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace hb {

bool parse_finite_float(std::string_view tok, float& value) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+'
  if (b == e || *b == '+') return false;
  // Spelled-out specials are refused before from_chars, which accepts them.
  for (const char* p = b; p != e; ++p)
    if (*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I') return false;
  double v = 0.0;
  const auto r = std::from_chars(b, e, v, std::chars_format::general);
  if (r.ptr != e) return false;
  if (r.ec == std::errc::result_out_of_range) {
    // Out of double's range: an underflow (negative exponent, a short mantissa) is zero;
    // anything else is an overflow.
    const std::string_view body(b, std::size_t(e - b));
    const std::size_t exp = body.find_first_of("eE");
    if (exp == std::string_view::npos || exp > 300 || exp + 1 >= body.size() || body[exp + 1] != '-') return false;
    value = body[0] == '-' ? -0.f : 0.f;
    return true;
  }
  if (r.ec != std::errc() || !(std::fabs(v) <= double(std::numeric_limits<float>::max()))) return false;
  value = float(v);
  return true;
}

std::vector<Segment> parse_segments_csv(std::string_view text, const std::string& name) {
  std::vector<Segment> out;
  bool header_seen = false;
  CsvLines lines(text);
  std::string_view line;
  const auto where = [&] { return name + ":" + std::to_string(lines.number()) + ": "; };
  while (lines.next(line)) {
    if (!header_seen) {
      header_seen = true;
      std::string compact;
      for (char c : line)
        if (c != ' ' && c != '\t') compact += c;
      if (compact != "sx,sy,sz,ex,ey,ez") throw InvalidInput(where() + "expected the header sx,sy,sz,ex,ey,ez");
      continue;
    }
    float v[6];
    int k = 0;
    std::size_t cell_start = 0;
    for (;;) {
      const std::size_t comma = line.find(',', cell_start);
      std::string_view cell = line.substr(cell_start, comma == std::string_view::npos ? std::string_view::npos
                                                                                      : comma - cell_start);
      while (!cell.empty() && (cell.front() == ' ' || cell.front() == '\t')) cell.remove_prefix(1);
      while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\t')) cell.remove_suffix(1);
      if (k >= 6) throw InvalidInput(where() + "more than 6 values");
      if (!parse_finite_float(cell, v[k]))
        throw InvalidInput(where() + "value " + std::to_string(k + 1) + " is not a finite number: '" +
                           std::string(cell.substr(0, 40)) + "'");
      ++k;
      if (comma == std::string_view::npos) break;
      cell_start = comma + 1;
    }
    if (k != 6) throw InvalidInput(where() + "expected 6 values, got " + std::to_string(k));
    for (int c = 0; c < 6; ++c)
      if (std::fabs(v[c]) > kMaxSegmentCoordinate)
        throw InvalidInput(where() + "value " + std::to_string(c + 1) + " is beyond the supported range (|x| <= 4e15)");
    out.push_back({Vec3(v[0], v[1], v[2]), Vec3(v[3], v[4], v[5])});
  }
  if (!header_seen) throw InvalidInput(name + ": empty segments file (expected the header sx,sy,sz,ex,ey,ez)");
  return out;
}

std::string read_text_file(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a folder, not a " + what + " file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open " + what + " file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(path + ": read error in " + what + " file");
  return text.str();
}

std::vector<Segment> read_segments_csv(const std::string& path) {
  return parse_segments_csv(read_text_file(path, "segments"), path);
}

} // namespace hb
