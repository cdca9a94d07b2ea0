// Piece files.
//  1. Plain text: one id per line; '#' comments and blank lines skipped; strict integers.
//  2. PLY: parse the header (format, elements, properties), skip the other elements, read
//     each face's corner list (at least 3 corners, each a declared vertex) and the piece
//     property (ASCII or binary, either byte order), and expand a k-gon to k - 2 triangle
//     ids; the elements must account for every byte of the file (a shifted byte otherwise
//     reads as other pieces).
//  3. Writing: text, or an ASCII PLY with the mesh, `int piece` and a colour per piece.
#include "decomposition/piece_file.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>

namespace hb {
namespace {

std::vector<std::uint32_t> read_text(const std::string& path, std::ifstream& in) {
  std::vector<std::uint32_t> ids;
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto last = line.find_last_not_of(" \t\r");
    const std::string token = line.substr(first, last - first + 1);
    if (token.empty() || token.find_first_not_of("0123456789") != std::string::npos || token.size() > 9)
      throw InvalidInput(path + ":" + std::to_string(number) + ": expected a non-negative piece id, got '" +
                         quoted_text(token, 40) + "'");
    ids.push_back(std::uint32_t(std::stoul(token)));
  }
  if (in.bad()) throw IoError(path + ": read error");
  return ids;
}

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

PlyType ply_type(const std::string& path, const std::string& name) {
  if (name == "char" || name == "int8") return PlyType::Int8;
  if (name == "uchar" || name == "uint8") return PlyType::UInt8;
  if (name == "short" || name == "int16") return PlyType::Int16;
  if (name == "ushort" || name == "uint16") return PlyType::UInt16;
  if (name == "int" || name == "int32") return PlyType::Int32;
  if (name == "uint" || name == "uint32") return PlyType::UInt32;
  if (name == "float" || name == "float32") return PlyType::Float32;
  if (name == "double" || name == "float64") return PlyType::Float64;
  throw InvalidInput(path + ": unknown PLY property type '" + quoted_text(name, 40) + "'");
}

int type_size(PlyType t) {
  switch (t) {
  case PlyType::Int8: case PlyType::UInt8: return 1;
  case PlyType::Int16: case PlyType::UInt16: return 2;
  case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
  default: return 8;
  }
}

struct PlyProperty {
  std::string name;
  PlyType type;
  bool list = false;
  PlyType count_type = PlyType::UInt8;
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

class PlyReader {
public:
  PlyReader(const std::string& path, std::istream& in, int format) : path_(path), in_(in), format_(format) {}

  double read(PlyType t) {
    if (format_ == 0) {
      double v;
      if (!(in_ >> v)) throw InvalidInput(path_ + ": truncated or malformed PLY body");
      return v;
    }
    unsigned char bytes[8];
    const int n = type_size(t);
    if (!in_.read(reinterpret_cast<char*>(bytes), n)) throw IoError(path_ + ": truncated PLY body");
    if (format_ == 2) std::reverse(bytes, bytes + n);
    switch (t) {
    case PlyType::Int8: { std::int8_t v; std::memcpy(&v, bytes, 1); return v; }
    case PlyType::UInt8: return bytes[0];
    case PlyType::Int16: { std::int16_t v; std::memcpy(&v, bytes, 2); return v; }
    case PlyType::UInt16: { std::uint16_t v; std::memcpy(&v, bytes, 2); return v; }
    case PlyType::Int32: { std::int32_t v; std::memcpy(&v, bytes, 4); return v; }
    case PlyType::UInt32: { std::uint32_t v; std::memcpy(&v, bytes, 4); return v; }
    case PlyType::Float32: { float v; std::memcpy(&v, bytes, 4); return v; }
    default: { double v; std::memcpy(&v, bytes, 8); return v; }
    }
  }

private:
  const std::string& path_;
  std::istream& in_;
  int format_;  // 0 ascii, 1 little endian, 2 big endian
};

// Reads past the element's `count` rows (binary rows of fixed size: one seek).
void skip_element(const std::string& path, std::ifstream& in, PlyReader& reader, const PlyElement& e, int format) {
  const bool fixed = format != 0 && std::none_of(e.properties.begin(), e.properties.end(), [](const PlyProperty& p) { return p.list; });
  if (fixed) {
    std::uint64_t row = 0;
    for (const PlyProperty& p : e.properties) row += std::uint64_t(type_size(p.type));
    const std::streampos here = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streamoff left = in.tellg() - here;
    in.seekg(here);
    if (here < 0 || left < 0 || (row > 0 && e.count > std::uint64_t(left) / row))
      throw InvalidInput(path + ": the " + e.name + " element claims " + std::to_string(e.count) + " rows of " + std::to_string(row) +
                         " bytes but only " + std::to_string(std::max<std::streamoff>(left, 0)) + " bytes follow");
    in.seekg(std::streamoff(row * e.count), std::ios::cur);
    return;
  }
  for (std::size_t i = 0; i < e.count; ++i)
    for (const PlyProperty& p : e.properties) {
      const double n = p.list ? reader.read(p.count_type) : 1;
      if (!(n >= 0.0 && n < 1e6)) throw InvalidInput(path + ": " + e.name + " " + std::to_string(i) + ": bad list size");
      for (std::size_t k = 0; k < std::size_t(n); ++k) reader.read(p.type);
    }
}

// The face element: a piece id per face, k - 2 triangle ids for a k-gon. Every face has at
// least 3 corners, each a vertex below `vertices` (when the file has a vertex element).
std::vector<std::uint32_t> read_faces(const std::string& path, std::ifstream& in, PlyReader& reader, const PlyElement& e, int format,
                                      std::size_t vertices) {
  int piece_property = -1, corners_property = -1;
  for (const char* name : {"piece", "label", "segment", "part", "region"}) {
    for (std::size_t k = 0; k < e.properties.size() && piece_property < 0; ++k)
      if (!e.properties[k].list && e.properties[k].name == name) piece_property = int(k);
    if (piece_property >= 0) break;
  }
  for (std::size_t k = 0; k < e.properties.size(); ++k)
    if (e.properties[k].list && corners_property < 0) corners_property = int(k);
  if (piece_property < 0)
    throw InvalidInput(path + ": the face element has no piece property (piece, label, segment, part, region)");
  // Every face takes at least one byte (two in ASCII): a count beyond what is left of the
  // file is a damaged header, refused before anything is allocated for it.
  const std::streampos here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff left = in.tellg() - here;
  in.seekg(here);
  if (here < 0 || left < 0 || e.count > std::size_t(left) / (format == 0 ? 2 : 1))
    throw InvalidInput(path + ": the face element claims " + std::to_string(e.count) + " faces but only " +
                       std::to_string(std::max<std::streamoff>(left, 0)) + " bytes follow: truncated or a damaged header");
  std::vector<std::uint32_t> ids;
  ids.reserve(e.count);
  for (std::size_t i = 0; i < e.count; ++i) {
    std::size_t corners = 3;
    double id = 0.0;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const PlyProperty& p = e.properties[k];
      if (!p.list) {
        const double v = reader.read(p.type);
        if (int(k) == piece_property) id = v;
        continue;
      }
      const double n = reader.read(p.count_type);
      if (!(n >= 0.0 && n < 1e6)) throw InvalidInput(path + ": face " + std::to_string(i) + ": bad list size");
      if (int(k) == corners_property) {
        corners = std::size_t(n);
        if (corners < 3) throw InvalidInput(path + ": face " + std::to_string(i) + " has " + std::to_string(corners) + " corners, not a polygon");
      }
      for (std::size_t c = 0; c < std::size_t(n); ++c) {
        const double v = reader.read(p.type);
        if (int(k) == corners_property && (!(v >= 0.0) || v >= double(vertices) || v != double(std::uint64_t(v)))) {
          std::ostringstream value;
          value.precision(10);
          value << v;
          throw InvalidInput(path + ": face " + std::to_string(i) + " corner " + std::to_string(c) + " is " + value.str() +
                             ", not a vertex of the " + std::to_string(vertices) + " the file declares");
        }
      }
    }
    if (!(id >= 0.0 && id < 4294967295.0) || id != double(std::uint32_t(id)))
      throw InvalidInput(path + ": face " + std::to_string(i) + ": piece id must be a non-negative integer");
    for (std::size_t c = 2; c < std::max<std::size_t>(corners, 3); ++c) ids.push_back(std::uint32_t(id));
  }
  return ids;
}

std::vector<std::uint32_t> read_ply(const std::string& path, std::ifstream& in) {
  std::string line;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) throw InvalidInput(path + ": not a PLY file (no 'ply' magic)");
  int format = -1;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      std::string f;
      ls >> f;
      format = f == "ascii" ? 0 : f == "binary_little_endian" ? 1 : f == "binary_big_endian" ? 2 : -1;
      if (format < 0) throw InvalidInput(path + ": unknown PLY format '" + quoted_text(f, 40) + "'");
    } else if (word == "element") {
      PlyElement e;
      std::string count_text, rest;
      ls >> e.name >> count_text;
      const bool digits = !count_text.empty() && count_text.size() <= 18 &&
                          std::all_of(count_text.begin(), count_text.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
      if (e.name.empty() || !digits || (ls >> rest))
        throw InvalidInput(path + ": bad element line '" + quoted_text(line, 60) + "' (expected 'element NAME COUNT', COUNT a whole number)");
      e.count = std::size_t(std::stoull(count_text));
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw InvalidInput(path + ": property before any element");
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string ct, it;
        ls >> ct >> it;
        p.list = true;
        p.count_type = ply_type(path, ct);
        p.type = ply_type(path, it);
      } else {
        p.type = ply_type(path, type);
      }
      ls >> p.name;
      elements.back().properties.push_back(p);
    } else if (word == "end_header") {
      ended = true;
      break;
    }
  }
  if (!ended || format < 0) throw InvalidInput(path + ": PLY header without format or end_header");
  PlyReader reader(path, in, format);
  std::vector<std::uint32_t> ids;
  bool have_faces = false;
  std::size_t vertices = 0;
  bool have_vertices = false;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") vertices = e.count, have_vertices = true;
    if (e.name != "face" || have_faces) {
      skip_element(path, in, reader, e, format);
      continue;
    }
    ids = read_faces(path, in, reader, e, format, have_vertices ? vertices : std::size_t(-1));
    have_faces = true;
  }
  if (!have_faces) throw InvalidInput(path + ": PLY file has no face element");
  // Every byte accounted for: bytes left over (or missing, above) mean the header's counts
  // and the data disagree, and what was read is not what was written.
  if (format == 0) in >> std::ws;
  const std::streampos here = in.tellg();
  in.seekg(0, std::ios::end);
  const std::streamoff left = in.tellg() - here;
  if (here >= 0 && left > 0)
    throw InvalidInput(path + ": " + std::to_string(left) + (format == 0 ? " bytes of text follow" : " bytes follow") +
                       " the last PLY element: the header's counts and sizes do not add up to the file (a damaged header or shifted data)");
  return ids;
}

bool has_extension(const std::string& path, const std::string& ext) {
  if (path.size() < ext.size()) return false;
  std::string tail = path.substr(path.size() - ext.size());
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return tail == ext;
}

} // namespace

std::vector<std::uint32_t> read_piece_file(const std::string& path, std::size_t triangle_count) {
  if (path.empty()) throw InvalidInput("no piece file given (choose one: a text file of one piece id per triangle, or .ply)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open piece file");
  std::vector<std::uint32_t> ids = has_extension(path, ".ply") ? read_ply(path, in) : read_text(path, in);
  if (ids.empty()) throw InvalidInput(path + ": no piece ids");
  if (ids.size() != triangle_count)
    throw InvalidInput(path + ": has " + std::to_string(ids.size()) + " piece ids, the mesh has " +
                       std::to_string(triangle_count) + " triangles");
  return ids;
}

void write_piece_file(const std::string& path, const TriangleMesh& mesh, const std::vector<std::uint32_t>& ids) {
  if (ids.size() != mesh.triangle_count())
    throw InvalidInput("write_piece_file: " + std::to_string(ids.size()) + " ids for " +
                       std::to_string(mesh.triangle_count()) + " triangles");
  std::ofstream out(path, std::ios::binary);
  if (!out) throw IoError(path + ": cannot open for writing");
  if (has_extension(path, ".ply")) {
    out << "ply\nformat ascii 1.0\ncomment hapticbox pieces: face property 'piece'\n"
        << "element vertex " << mesh.vertex_count() << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face " << mesh.triangle_count()
        << "\nproperty list uchar int vertex_indices\nproperty int piece\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    out.precision(9);
    for (const Vec3& p : mesh.positions) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      const std::uint32_t h = ids[t] * 2654435761u;
      out << "3 " << tri[0] << ' ' << tri[1] << ' ' << tri[2] << ' ' << ids[t] << ' ' << (64 + (h & 0xbf)) << ' '
          << (64 + ((h >> 8) & 0xbf)) << ' ' << (64 + ((h >> 16) & 0xbf)) << '\n';
    }
  } else {
    out << "# hapticbox pieces: one id per triangle, in triangle order\n";
    for (std::uint32_t id : ids) out << id << '\n';
  }
  if (!out) throw IoError(path + ": write failed");
}

} // namespace hb
