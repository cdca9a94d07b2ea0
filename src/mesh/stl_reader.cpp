// STL reader (ASCII and binary), a strict parser of our own (OpenMesh's ASCII STL reader
// leaves a coordinate it cannot parse uninitialised).
//
//  1. Binary or ASCII: binary when the file is 84 + 50 n bytes for the n its header declares
//     (some binary files begin with "solid" too); otherwise ASCII when it begins with "solid";
//     otherwise a binary file whose size disagrees with its triangle count (refused, naming
//     both numbers). So the triangle count is always checked against the file size before
//     anything is reserved.
//  2. Binary: per triangle a normal (ignored), three float32 corners, a 16-bit attribute.
//  3. ASCII: solid NAME { facet normal x y z / outer loop / vertex x y z (3 or more) /
//     endloop / endfacet } endsolid [NAME], several solids allowed. Every keyword is checked;
//     a coordinate must be a number within float range ("inf", "nan", "abc", "1e39" are
//     refused with their line).
//  4. Corners with identical coordinates become one vertex (STL stores none), so the edge
//     analysis sees the real connectivity; -0 and +0 are the same vertex.
#include "mesh/mesh_readers.h"
#include "mesh/mesh_validation.h"
#include "mesh/text_tokens.h"

#include "errors.h"
#include "formats/quoted_text.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <unordered_map>

namespace hb::detail {
namespace {

/// Merges corners with bit-identical coordinates (after -0 -> +0) into one vertex.
class VertexWelder {
public:
  explicit VertexWelder(PolygonSoup& soup, std::size_t expected) : soup_(soup) { index_.reserve(expected); }

  std::int64_t add(float x, float y, float z) {
    const auto bits = [](float v) {
      if (v == 0.f) v = 0.f;  // -0 and +0: one vertex
      std::uint32_t b;
      std::memcpy(&b, &v, 4);
      return std::uint64_t(b);
    };
    Key k{bits(x) << 32 | bits(y), bits(z)};
    const auto [it, inserted] = index_.try_emplace(k, std::int64_t(soup_.positions.size()));
    if (inserted) soup_.positions.emplace_back(x, y, z);
    return it->second;
  }

private:
  struct Key {
    std::uint64_t xy, z;
    bool operator==(const Key& o) const { return xy == o.xy && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::uint64_t h = k.xy * 0x9E3779B97F4A7C15ull ^ (k.z + 0x632BE59BD9B4E019ull);
      h ^= h >> 29;
      return std::size_t(h * 0xBF58476D1CE4E5B9ull);
    }
  };
  PolygonSoup& soup_;
  std::unordered_map<Key, std::int64_t, KeyHash> index_;
};

PolygonSoup read_binary(const std::string& path, const std::string& bytes, std::uint32_t triangles,
                        MeshReadReport& report) {
  PolygonSoup soup;
  VertexWelder weld(soup, std::size_t(triangles) / 2 + 3);
  soup.indices.reserve(3 * std::size_t(triangles));
  soup.offsets.reserve(std::size_t(triangles) + 1);
  const char* p = bytes.data() + 84;
  for (std::uint32_t t = 0; t < triangles; ++t, p += 50) {
    float c[9];
    std::memcpy(c, p + 12, sizeof c);  // little-endian IEEE floats, as the format says
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(c[3 * k]) || !std::isfinite(c[3 * k + 1]) || !std::isfinite(c[3 * k + 2]))
        throw InvalidInput(path + ": triangle " + std::to_string(t) + " corner " + std::to_string(k) +
                           " has a non-finite (NaN or Inf) coordinate");
      soup.indices.push_back(weld.add(c[3 * k], c[3 * k + 1], c[3 * k + 2]));
    }
    soup.offsets.push_back(soup.indices.size());
  }
  report.input_vertices = soup.positions.size();
  report.input_faces = triangles;
  return soup;
}

/// Whitespace-separated words of a text with the line each starts on.
class Words {
public:
  explicit Words(std::string_view text) : text_(text) {}
  bool next(std::string_view& w) {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return false;
    const std::size_t b = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    w = text_.substr(b, pos_ - b);
    return true;
  }
  /// The rest of the current line (e.g. a solid's name), trimmed.
  std::string_view rest_of_line() {
    const std::size_t b = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    return LineReader::trim(text_.substr(b, pos_ - b));
  }
  std::size_t line() const { return line_; }

private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

PolygonSoup read_ascii(const std::string& path, const std::string& text, MeshReadReport& report) {
  if (text.find('\0') != std::string::npos)
    throw InvalidInput(path + ": not an ASCII STL file (contains NUL bytes) and not a binary STL of its size");
  Words words(text);
  std::string_view w;
  const auto fail = [&](const std::string& cause) -> InvalidInput {
    return InvalidInput(path + ":" + std::to_string(words.line()) + ": " + cause);
  };
  const auto word = [&](const char* what) {
    if (!words.next(w)) throw IoError(path + ":" + std::to_string(words.line()) + ": truncated: expected " + what);
    return w;
  };
  const auto expect = [&](const char* keyword) {
    if (!iequals(word(keyword), keyword))
      throw fail("expected '" + std::string(keyword) + "', found '" + quoted_text(std::string(w), 40) + "'");
  };
  const auto number = [&](const char* what) {
    word(what);
    double v = 0.0;
    if (!parse_number(w, v)) throw fail(std::string(what) + ": not a number: '" + quoted_text(std::string(w), 40) + "'");
    if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max()))
      throw fail(std::string(what) + ": '" + quoted_text(std::string(w), 40) + "' is not a finite float");
    return float(v);
  };

  PolygonSoup soup;
  VertexWelder weld(soup, 1024);
  std::size_t solids = 0;
  while (words.next(w)) {
    if (!iequals(w, "solid")) throw fail("expected 'solid', found '" + quoted_text(std::string(w), 40) + "'");
    words.rest_of_line();  // the name, if any
    ++solids;
    for (;;) {
      word("'facet' or 'endsolid'");
      if (iequals(w, "endsolid")) {
        words.rest_of_line();
        break;
      }
      if (!iequals(w, "facet")) throw fail("expected 'facet' or 'endsolid', found '" + quoted_text(std::string(w), 40) + "'");
      expect("normal");
      for (int k = 0; k < 3; ++k) number("facet normal");  // ignored: recomputed from the corners
      expect("outer");
      expect("loop");
      std::size_t corners = 0;
      for (;;) {
        word("'vertex' or 'endloop'");
        if (iequals(w, "endloop")) break;
        if (!iequals(w, "vertex")) throw fail("expected 'vertex' or 'endloop', found '" + quoted_text(std::string(w), 40) + "'");
        const float x = number("vertex x"), y = number("vertex y"), z = number("vertex z");
        soup.indices.push_back(weld.add(x, y, z));
        ++corners;
      }
      expect("endfacet");
      if (corners < 3) {
        soup.indices.resize(soup.offsets.back());
        ++soup.short_faces;
        continue;
      }
      soup.offsets.push_back(soup.indices.size());
    }
  }
  if (solids == 0) throw InvalidInput(path + ": no 'solid' in the ASCII STL file");
  report.input_vertices = soup.positions.size();
  report.input_faces = soup.face_count() + soup.short_faces;
  return soup;
}

bool starts_with_solid(const std::string& bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r' || bytes[i] == '\n')) ++i;
  return bytes.size() - i >= 5 && iequals(std::string_view(bytes).substr(i, 5), "solid") &&
         (bytes.size() - i == 5 || std::isspace(static_cast<unsigned char>(bytes[i + 5])));
}

} // namespace

PolygonSoup read_stl(const std::string& path, MeshReadReport& report) {
  const std::string bytes = read_whole_file(path);
  std::uint32_t declared = 0;
  if (bytes.size() >= 84) std::memcpy(&declared, bytes.data() + 80, 4);
  const std::uint64_t binary_size = 84 + 50 * std::uint64_t(declared);
  if (bytes.size() >= 84 && binary_size == bytes.size()) return read_binary(path, bytes, declared, report);
  if (starts_with_solid(bytes) && (bytes.size() < 84 || bytes.find('\0') == std::string::npos))
    return read_ascii(path, bytes, report);
  if (bytes.size() < 84)
    throw InvalidInput(path + ": not an STL file: " + std::to_string(bytes.size()) +
                       " bytes, shorter than a binary STL header (84), and no ASCII 'solid'");
  throw InvalidInput(path + ": binary STL declares " + std::to_string(declared) + " triangles (" +
                     std::to_string(binary_size) + " bytes) but the file has " + std::to_string(bytes.size()) +
                     " bytes");
}

} // namespace hb::detail
