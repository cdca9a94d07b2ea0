// Everyday scene files before Assimp opens them (Assimp trusts what a file declares: a wrong
// count crashed it, a cut array gave another mesh without a word):
//  1. glTF and GLB: the JSON, its accessors and buffers (formats/gltf_check.h), external
//     buffer files present;
//  2. ASCII FBX: every array holds the values it declares, polygon indices name vertices;
//  (Collada: collada_check.cxx; 3MF: three_mf_package.cxx.)
#include "scene_file_checks.h"
#include "errors.h"
#include "formats/gltf_check.h"
#include "formats/quoted_text.h"
#include "mesh/mapped_file.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace hb::vtk {

// An ASCII FBX file before Assimp opens it: every array ("Name: *N { a: v,v,... }") holds the N
// values it declares (Assimp reads what is there: a cut or repeated stretch of indices gave a
// different mesh without a word), and the polygon indices refer to existing vertices.
void check_fbx(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string t((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (t.compare(0, 18, "Kaydara FBX Binary") == 0) return;  // binary: Assimp's parser checks its record lengths
  std::uint64_t vertices = 0;
  bool have_vertices = false;
  for (std::size_t p = t.find('*'); p != std::string::npos; p = t.find('*', p + 1)) {
    std::size_t q = p + 1;
    if (q >= t.size() || !std::isdigit((unsigned char)t[q])) continue;
    std::uint64_t declared = 0;
    while (q < t.size() && std::isdigit((unsigned char)t[q])) {
      declared = declared * 10 + std::uint64_t(t[q] - '0');
      if (declared > (std::uint64_t(1) << 40)) throw InvalidInput(path + ": an FBX array declares an absurd length");
      ++q;
    }
    while (q < t.size() && std::isspace((unsigned char)t[q])) ++q;
    if (q >= t.size() || t[q] != '{') continue;
    // The array's name: the word before ':' on this line.
    const std::size_t line = t.rfind('\n', p);
    std::string name = t.substr(line == std::string::npos ? 0 : line + 1, p - (line == std::string::npos ? 0 : line + 1));
    name.erase(0, name.find_first_not_of(" \t"));
    name = name.substr(0, name.find(':'));
    const std::size_t close = t.find('}', q);
    if (close == std::string::npos) throw InvalidInput(path + ": the FBX array " + name + " is not closed");
    std::size_t a = t.find("a:", q);
    if (a == std::string::npos || a > close) {
      if (declared != 0) throw InvalidInput(path + ": the FBX array " + name + " declares " + std::to_string(declared) + " values and holds none");
      continue;
    }
    std::uint64_t count = 0;
    bool in_value = false, polygon_indices = name == "PolygonVertexIndex";
    long long value = 0;
    bool negative = false;
    auto end_value = [&] {
      if (!in_value) return;
      ++count;
      if (polygon_indices && have_vertices) {
        const long long index = negative ? value - 1 : value;  // a polygon's last index i is stored as -(i + 1)
        if (index < 0 || std::uint64_t(index) >= vertices)
          throw InvalidInput(path + ": FBX PolygonVertexIndex value " + std::to_string(negative ? -value : value) + " refers to vertex " +
                             std::to_string(index) + " of " + std::to_string(vertices));
      }
      in_value = false;
      value = 0;
      negative = false;
    };
    for (std::size_t k = a + 2; k < close; ++k) {
      const char ch = t[k];
      if (ch == ',') {
        if (!in_value) throw InvalidInput(path + ": the FBX array " + name + " has an empty value");
        end_value();
      } else if (!std::isspace((unsigned char)ch)) {
        if (!in_value) in_value = true;
        if (polygon_indices) {
          if (ch == '-' && value == 0 && !negative) negative = true;
          else if (std::isdigit((unsigned char)ch) && value < (1LL << 40)) value = value * 10 + (ch - '0');
          else if (!std::isdigit((unsigned char)ch)) throw InvalidInput(path + ": FBX PolygonVertexIndex holds '" + std::string(1, ch) + "', not a whole number");
        }
      }
    }
    end_value();
    if (count != declared)
      throw InvalidInput(path + ": the FBX array " + name + " declares " + std::to_string(declared) + " values but holds " + std::to_string(count));
    if (name == "Vertices") {
      if (declared % 3 != 0) throw InvalidInput(path + ": the FBX array Vertices holds " + std::to_string(declared) + " numbers, not a multiple of 3");
      vertices = declared / 3;
      have_vertices = true;
    }
    p = close;
  }
}

// glTF and GLB before Assimp opens them (gltf_check.h); external buffer files are mapped, not
// copied.
void check_gltf(const std::string& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string_view bin;
  const std::string text = binary ? check_glb(path, bytes, bin) : bytes;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::vector<std::unique_ptr<hb::detail::MappedFile>> files;
  check_gltf_json(path, text, bin, [&](const std::string& uri) -> std::string_view {
    std::string file;  // percent-decoded
    for (std::size_t i = 0; i < uri.size(); ++i) {
      if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) && std::isxdigit((unsigned char)uri[i + 2])) {
        file += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        file += uri[i];
      }
    }
    const std::filesystem::path p = dir / file;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      throw InvalidInput(path + ": the glTF buffer file " + quoted_text(p.string(), 300) + " is missing");
    if (std::filesystem::file_size(p, ec) == 0) return {};
    files.push_back(std::make_unique<hb::detail::MappedFile>(p.string()));
    return files.back()->text();
  });
}

} // namespace hb::vtk
