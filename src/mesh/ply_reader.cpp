// PLY reader (ASCII, binary little- and big-endian), a strict parser of our own (OpenMesh's
// reader allocates whatever counts a header declares and spins on a header without end).
//
//  1. Header, line by line, within the file: "ply", one "format", "comment"/"obj_info" lines,
//     "element NAME COUNT" each followed by its "property TYPE NAME" or
//     "property list COUNT_TYPE ITEM_TYPE NAME" lines, then "end_header". A file that ends
//     before end_header, an unknown keyword or type, or a count that is not a plain unsigned
//     integer is refused with its line.
//  2. Before anything is reserved, each element's count times the fewest bytes one element
//     can take (binary: its scalar sizes plus its list counts; ASCII: two characters a value)
//     must fit in the bytes after the header, so no count can trigger a huge allocation or a
//     long loop; an element with no property must have count 0.
//  3. "vertex" needs numeric x, y, z properties (any type; others are skipped); "face" needs
//     a list "vertex_indices" (or "vertex_index") of integers. Other elements are skipped.
//  4. Body: ASCII has one element a line with exactly its values (a face that declares more
//     indices than its line holds, a missing line, or lines left over are refused); binary
//     reads each value at its size and byte order, list counts checked against the bytes
//     left before they are used, negative counts refused.
#include "mesh/mesh_readers.h"
#include "mesh/mesh_validation.h"
#include "mesh/text_tokens.h"

#include "errors.h"
#include "formats/quoted_text.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <vector>

namespace hb::detail {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

int size_of(Type t) {
  switch (t) {
  case Type::i8:
  case Type::u8: return 1;
  case Type::i16:
  case Type::u16: return 2;
  case Type::i32:
  case Type::u32:
  case Type::f32: return 4;
  case Type::f64: return 8;
  }
  return 1;
}

bool is_integer(Type t) { return t != Type::f32 && t != Type::f64; }

bool type_of(std::string_view name, Type& t) {
  static const struct {
    const char* name;
    Type type;
  } kTypes[] = {{"char", Type::i8},    {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
                {"short", Type::i16},  {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
                {"int", Type::i32},    {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
                {"float", Type::f32},  {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};
  for (const auto& k : kTypes)
    if (name == k.name) {
      t = k.type;
      return true;
    }
  return false;
}

struct Property {
  std::string name;
  Type type = Type::f32;
  bool list = false;
  Type count_type = Type::u8;  // lists only
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  std::size_t line = 0;  // of its "element" line
};

enum class Encoding { ascii, little, big };

/// Reads binary values at a cursor, with the byte order of the file; every read is checked
/// against the end of the buffer.
class BinaryCursor {
public:
  BinaryCursor(const std::string& path, std::string_view data, bool swap) : path_(path), data_(data), swap_(swap) {}

  double read(Type t) {
    const int n = size_of(t);
    if (data_.size() - pos_ < std::size_t(n)) throw InvalidInput(path_ + ": truncated binary PLY data (at byte " +
                                                                 std::to_string(pos_) + " of the body)");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, std::size_t(n));
    pos_ += std::size_t(n);
    if (swap_)
      for (int i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    switch (t) {
    case Type::i8: return double(static_cast<std::int8_t>(b[0]));
    case Type::u8: return double(b[0]);
    case Type::i16: return double(load<std::int16_t>(b));
    case Type::u16: return double(load<std::uint16_t>(b));
    case Type::i32: return double(load<std::int32_t>(b));
    case Type::u32: return double(load<std::uint32_t>(b));
    case Type::f32: return double(load<float>(b));
    case Type::f64: return load<double>(b);
    }
    return 0.0;
  }
  std::size_t left() const { return data_.size() - pos_; }
  std::size_t position() const { return pos_; }

private:
  template <typename T> static T load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return v;
  }
  const std::string& path_;
  std::string_view data_;
  bool swap_;
  std::size_t pos_ = 0;
};

bool host_is_little_endian() {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

/// A header name (element or property) that can stand in a message: printable ASCII only
/// (a NUL in a name would cut the message that quotes it).
bool printable_name(std::string_view name) {
  for (const char c : name)
    if (c < 0x21 || c > 0x7e) return false;
  return !name.empty();
}

/// Parses the header; returns the byte offset of the body.
std::size_t parse_header(const std::string& path, const std::string& text, Encoding& encoding,
                         std::vector<Element>& elements) {
  const auto fail = [&](std::size_t line, const std::string& cause) {
    return InvalidInput(path + ":" + std::to_string(line) + ": " + cause);
  };
  // Header lines end with '\n' (a '\r' before it is tolerated); no comment stripping: PLY
  // comments are their own keyword.
  std::size_t pos = 0, line_no = 0;
  const auto next_line = [&](std::string_view& line) {
    if (pos >= text.size()) return false;
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    line = LineReader::trim(std::string_view(text).substr(pos, end - pos));
    pos = end + 1 <= text.size() ? end + 1 : text.size();
    ++line_no;
    return true;
  };
  std::string_view line, tok;
  if (!next_line(line) || line != "ply") throw InvalidInput(path + ": not a PLY file (no 'ply' on the first line)");
  bool format_seen = false, ended = false;
  while (next_line(line)) {
    Tokens t(line);
    if (!t.next(tok)) continue;  // blank header line
    if (tok == "comment" || tok == "obj_info") continue;
    if (tok == "end_header") {
      ended = true;
      break;
    }
    if (tok == "format") {
      std::string_view kind, version;
      if (!t.next(kind) || !t.next(version)) throw fail(line_no, "expected 'format KIND 1.0'");
      if (kind == "ascii") encoding = Encoding::ascii;
      else if (kind == "binary_little_endian") encoding = Encoding::little;
      else if (kind == "binary_big_endian") encoding = Encoding::big;
      else throw fail(line_no, "unknown PLY format '" + quoted_text(std::string(kind), 40) + "'");
      if (version != "1.0") throw fail(line_no, "PLY version '" + quoted_text(std::string(version), 40) + "' (expected 1.0)");
      format_seen = true;
      continue;
    }
    if (tok == "element") {
      Element e;
      std::string_view name, count;
      if (!t.next(name) || !t.next(count)) throw fail(line_no, "expected 'element NAME COUNT'");
      if (count.empty() || count[0] == '+' || count[0] == '-' || !parse_number(count, e.count))
        throw fail(line_no, "element '" + quoted_text(std::string(name), 40) + "': count '" +
                                quoted_text(std::string(count), 40) + "' is not an unsigned integer below 2^64");
      if (!printable_name(name)) throw fail(line_no, "element name with a byte that is not printable ASCII");
      e.name = std::string(name);
      e.line = line_no;
      elements.push_back(std::move(e));
      continue;
    }
    if (tok == "property") {
      if (elements.empty()) throw fail(line_no, "property before any element");
      Property p;
      std::string_view type, name;
      if (!t.next(type)) throw fail(line_no, "expected 'property TYPE NAME'");
      if (type == "list") {
        std::string_view count_type;
        if (!t.next(count_type) || !t.next(type) || !t.next(name))
          throw fail(line_no, "expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
        if (!type_of(count_type, p.count_type) || !is_integer(p.count_type))
          throw fail(line_no, "list count type '" + quoted_text(std::string(count_type), 40) + "' is not an integer type");
        p.list = true;
      } else if (!t.next(name)) {
        throw fail(line_no, "expected 'property TYPE NAME'");
      }
      if (!type_of(type, p.type)) throw fail(line_no, "unknown property type '" + quoted_text(std::string(type), 40) + "'");
      if (!printable_name(name)) throw fail(line_no, "property name with a byte that is not printable ASCII");
      p.name = std::string(name);
      elements.back().properties.push_back(std::move(p));
      continue;
    }
    throw fail(line_no, "unknown PLY header keyword '" + quoted_text(std::string(tok), 40) + "'");
  }
  if (!ended) throw InvalidInput(path + ": PLY header has no 'end_header' line (truncated or not a PLY file)");
  if (!format_seen) throw InvalidInput(path + ": PLY header has no 'format' line");
  return pos;
}

/// The fewest bytes one element can take in the body.
std::uint64_t min_bytes(const Element& e, Encoding encoding) {
  std::uint64_t bytes = 0;
  for (const Property& p : e.properties)
    bytes += encoding == Encoding::ascii ? 2 : std::uint64_t(size_of(p.list ? p.count_type : p.type));
  return bytes;
}

struct Layout {
  const Element* vertex = nullptr;
  int x = -1, y = -1, z = -1;
  const Element* face = nullptr;
  int indices = -1;
};

Layout check_layout(const std::string& path, const std::vector<Element>& elements, Encoding encoding,
                    std::uint64_t body_bytes) {
  Layout L;
  std::uint64_t need = 0;
  for (const Element& e : elements) {
    const std::uint64_t per = min_bytes(e, encoding);
    if (per == 0 && e.count > 0)
      throw InvalidInput(path + ":" + std::to_string(e.line) + ": element '" + e.name + "' has " +
                         std::to_string(e.count) + " entries but no property");
    if (per > 0 && (e.count > body_bytes / per || need + e.count * per > body_bytes))
      throw InvalidInput(path + ":" + std::to_string(e.line) + ": element '" + e.name + "' declares " +
                         std::to_string(e.count) + " entries, more than the " + std::to_string(body_bytes) +
                         " bytes after the header can hold");
    need += e.count * per;
    if (e.name == "vertex") {
      if (L.vertex) throw InvalidInput(path + ":" + std::to_string(e.line) + ": a second 'vertex' element");
      L.vertex = &e;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        int* slot = p.name == "x" ? &L.x : p.name == "y" ? &L.y : p.name == "z" ? &L.z : nullptr;
        if (slot && !p.list) *slot = int(k);
      }
      if (L.x < 0 || L.y < 0 || L.z < 0)
        throw InvalidInput(path + ":" + std::to_string(e.line) + ": the vertex element has no x, y and z properties");
    } else if (e.name == "face") {
      if (L.face) throw InvalidInput(path + ":" + std::to_string(e.line) + ": a second 'face' element");
      L.face = &e;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) L.indices = int(k);
      }
      if (L.indices < 0)
        throw InvalidInput(path + ":" + std::to_string(e.line) + ": the face element has no vertex_indices list");
      if (!is_integer(e.properties[std::size_t(L.indices)].type))
        throw InvalidInput(path + ":" + std::to_string(e.line) + ": vertex_indices are not of an integer type");
    }
  }
  if (!L.vertex) throw InvalidInput(path + ": PLY file has no 'vertex' element");
  return L;
}

/// A coordinate read as double, stored as float: refused when not finite in float.
float coordinate(const std::string& where, double v) {
  if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max()))
    throw InvalidInput(where + ": coordinate is not a finite float");
  return float(v);
}

void store_vertex(PolygonSoup& soup, const double xyz[3], const std::string& where) {
  soup.positions.emplace_back(coordinate(where, xyz[0]), coordinate(where, xyz[1]), coordinate(where, xyz[2]));
}

void end_face(PolygonSoup& soup, std::size_t corners) {
  if (corners < 3) {
    soup.indices.resize(soup.offsets.back());
    ++soup.short_faces;
  } else {
    soup.offsets.push_back(soup.indices.size());
  }
}

/// An integer value of an index or list count, checked to be integral and in int64 range.
bool as_integer(double v, std::int64_t& out) {
  if (!(v >= -9.2e18 && v <= 9.2e18) || v != std::floor(v)) return false;
  out = std::int64_t(v);
  return true;
}

void read_ascii_body(const std::string& path, std::string_view body, std::size_t first_line,
                     const std::vector<Element>& elements, const Layout& L, PolygonSoup& soup) {
  LineReader lines(body, '\0');
  std::string_view line, tok;
  const auto where = [&] { return path + ":" + std::to_string(first_line + lines.line_number() - 1); };
  for (const Element& e : elements) {
    const bool is_vertex = &e == L.vertex, is_face = &e == L.face;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      if (!lines.next(line))
        throw InvalidInput(path + ": truncated: element '" + e.name + "' declares " + std::to_string(e.count) +
                           " entries, the file holds " + std::to_string(i));
      Tokens t(line);
      double xyz[3] = {0, 0, 0};
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        double v = 0;
        if (!t.next(tok) || !parse_number(tok, v))
          throw InvalidInput(where() + ": " + e.name + " " + std::to_string(i) + ": expected a number for '" + p.name + "'");
        if (!p.list) {
          if (is_vertex && int(k) == L.x) xyz[0] = v;
          if (is_vertex && int(k) == L.y) xyz[1] = v;
          if (is_vertex && int(k) == L.z) xyz[2] = v;
          continue;
        }
        std::int64_t n = 0;
        if (!as_integer(v, n) || n < 0 || std::uint64_t(n) > line.size())
          throw InvalidInput(where() + ": " + e.name + " " + std::to_string(i) + ": list count '" +
                             quoted_text(std::string(tok), 40) + "' is negative, not an integer or longer than the line");
        const bool indices = is_face && int(k) == L.indices;
        for (std::int64_t c = 0; c < n; ++c) {
          if (!t.next(tok) || !parse_number(tok, v))
            throw InvalidInput(where() + ": " + e.name + " " + std::to_string(i) + ": expected " + std::to_string(n) +
                               " values in '" + p.name + "'");
          if (!indices) continue;
          std::int64_t idx = 0;
          if (!as_integer(v, idx))
            throw InvalidInput(where() + ": face " + std::to_string(i) + ": vertex index '" +
                               quoted_text(std::string(tok), 40) + "' is not an integer");
          soup.indices.push_back(idx);
        }
        if (indices) end_face(soup, std::size_t(n));
      }
      if (t.next(tok))
        throw InvalidInput(where() + ": " + e.name + " " + std::to_string(i) + ": more values than its properties");
      if (is_vertex) store_vertex(soup, xyz, where() + ": vertex " + std::to_string(i));
    }
  }
  if (lines.next(line)) throw InvalidInput(where() + ": data after the last declared element");
}

void read_binary_body(const std::string& path, std::string_view body, bool swap,
                      const std::vector<Element>& elements, const Layout& L, PolygonSoup& soup) {
  BinaryCursor in(path, body, swap);
  for (const Element& e : elements) {
    const bool is_vertex = &e == L.vertex, is_face = &e == L.face;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      double xyz[3] = {0, 0, 0};
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (!p.list) {
          const double v = in.read(p.type);
          if (is_vertex && int(k) == L.x) xyz[0] = v;
          if (is_vertex && int(k) == L.y) xyz[1] = v;
          if (is_vertex && int(k) == L.z) xyz[2] = v;
          continue;
        }
        std::int64_t n = 0;
        as_integer(in.read(p.count_type), n);  // integer types: always integral
        if (n < 0 || std::uint64_t(n) > in.left() / std::uint64_t(size_of(p.type)))
          throw InvalidInput(path + ": " + e.name + " " + std::to_string(i) + ": list count " + std::to_string(n) +
                             " is negative or runs past the end of the file");
        const bool indices = is_face && int(k) == L.indices;
        for (std::int64_t c = 0; c < n; ++c) {
          const double v = in.read(p.type);
          if (indices) soup.indices.push_back(std::int64_t(v));  // integer types: exact in double
        }
        if (indices) end_face(soup, std::size_t(n));
      }
      if (is_vertex) store_vertex(soup, xyz, path + ": vertex " + std::to_string(i));
    }
  }
  if (in.left() > 0)
    throw InvalidInput(path + ": " + std::to_string(in.left()) + " bytes after the last declared element");
}

} // namespace

PolygonSoup read_ply(const std::string& path, MeshReadReport& report) {
  const std::string text = read_whole_file(path);
  Encoding encoding = Encoding::ascii;
  std::vector<Element> elements;
  const std::size_t body_start = parse_header(path, text, encoding, elements);
  const std::uint64_t body_bytes = text.size() - body_start;
  const Layout L = check_layout(path, elements, encoding, body_bytes);

  PolygonSoup soup;
  soup.positions.reserve(std::size_t(L.vertex->count));
  if (L.face) soup.offsets.reserve(std::size_t(L.face->count) + 1);
  const std::string_view body = std::string_view(text).substr(body_start);
  if (encoding == Encoding::ascii) {
    std::size_t header_lines = 0;
    for (std::size_t i = 0; i < body_start; ++i) header_lines += text[i] == '\n';
    read_ascii_body(path, body, header_lines + 1, elements, L, soup);
  } else {
    read_binary_body(path, body, (encoding == Encoding::little) != host_is_little_endian(), elements, L, soup);
  }
  report.input_vertices = soup.positions.size();
  report.input_faces = soup.face_count() + soup.short_faces;
  return soup;
}

} // namespace hb::detail
