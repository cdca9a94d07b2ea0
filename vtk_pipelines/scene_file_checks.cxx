// Everyday scene files before Assimp opens them (Assimp trusts what a file declares: a wrong
// count crashed it, a cut array gave another mesh without a word):
//  1. glTF and GLB: the JSON, its accessors and buffers (formats/gltf_check.h), external
//     buffer files present;
//  2. ASCII FBX: every array holds the values it declares, polygon indices name vertices;
//  3. Collada: every float_array holds its count of finite numbers, accessors read within
//     their arrays, polygon lists hold their polygons' indices, indices below the largest array.
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

// A Collada file before Assimp opens it: every float_array holds the count of finite numbers
// it declares (a wrong count crashed Assimp), every accessor reads within its array, and index
// lists (<p>, <vcount>, <v>) hold whole numbers below the file's largest array (a non-number or
// a huge index cost gigabytes).
void check_collada(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto attribute = [](const std::string& tag, const char* name) -> std::string {
    const std::string key = std::string(" ") + name + "=\"";
    const std::size_t at = tag.find(key);
    if (at == std::string::npos) return {};
    const std::size_t end = tag.find('"', at + key.size());
    return end == std::string::npos ? std::string() : tag.substr(at + key.size(), end - at - key.size());
  };
  auto whole = [&](const std::string& text, const std::string& what) -> std::uint64_t {
    if (text.empty() || text.size() > 12 || text.find_first_not_of("0123456789") != std::string::npos) {
      std::string shown = text.substr(0, 20);
      for (char& c : shown)
        if (!std::isprint((unsigned char)c)) c = '?';
      throw InvalidInput(path + ": Collada " + what + " is '" + shown + "', not a whole number");
    }
    return std::stoull(text);
  };
  std::map<std::string, std::uint64_t> arrays;  // id -> values
  std::uint64_t largest = 0;
  for (std::size_t at = xml.find("<float_array"); at != std::string::npos; at = xml.find("<float_array", at + 1)) {
    const std::size_t open_end = xml.find('>', at);
    const std::size_t close = xml.find("</float_array>", at);
    if (open_end == std::string::npos || close == std::string::npos || close < open_end)
      throw InvalidInput(path + ": a Collada float_array is not closed");
    const std::string tag = xml.substr(at, open_end - at);
    const std::uint64_t count = whole(attribute(tag, "count"), "float_array count");
    std::uint64_t n = 0;
    const char* p = xml.data() + open_end + 1;
    const char* end = xml.data() + close;
    while (p < end) {
      while (p < end && std::isspace((unsigned char)*p)) ++p;
      if (p >= end) break;
      char* stop = nullptr;
      const double v = std::strtod(p, &stop);
      if (stop == p || stop > end || !std::isfinite(v) || (stop < end && !std::isspace((unsigned char)*stop)))
        throw InvalidInput(path + ": Collada float_array " + attribute(tag, "id") + " holds a value that is not a finite number");
      p = stop;
      ++n;
    }
    if (n != count)
      throw InvalidInput(path + ": Collada float_array " + attribute(tag, "id") + " declares " + std::to_string(count) + " values and holds " +
                         std::to_string(n));
    arrays[attribute(tag, "id")] = count;
    largest = std::max(largest, count);
  }
  for (std::size_t at = xml.find("<accessor"); at != std::string::npos; at = xml.find("<accessor", at + 1)) {
    const std::string tag = xml.substr(at, xml.find('>', at) - at);
    const std::uint64_t count = whole(attribute(tag, "count"), "accessor count");
    const std::string stride_text = attribute(tag, "stride");
    const std::uint64_t stride = stride_text.empty() ? 1 : whole(stride_text, "accessor stride");
    std::string source = attribute(tag, "source");
    if (!source.empty() && source[0] == '#') source.erase(0, 1);
    const auto it = arrays.find(source);
    if (it != arrays.end() && (stride == 0 || count * stride > it->second))
      throw InvalidInput(path + ": Collada accessor of " + source + " reads " + std::to_string(count) + " x " + std::to_string(stride) +
                         " values from an array of " + std::to_string(it->second));
  }
  // Each <polylist> (and <triangles>) holds its count of polygons: one <vcount> of `count`
  // sizes and one <p> of sum(vcount) x inputs indices (a polylist without its vcount crashed
  // Assimp).
  for (const char* kind : {"polylist", "triangles"}) {
    const std::string open = std::string("<") + kind, close = std::string("</") + kind + ">";
    for (std::size_t at = xml.find(open); at != std::string::npos; at = xml.find(open, at + 1)) {
      if (at + open.size() < xml.size() && !std::isspace((unsigned char)xml[at + open.size()]) && xml[at + open.size()] != '>') continue;
      const std::size_t end = xml.find(close, at);
      if (end == std::string::npos) throw InvalidInput(path + ": a Collada <" + kind + "> is not closed");
      const std::string body = xml.substr(at, end - at);
      const std::uint64_t count = whole(attribute(body.substr(0, body.find('>')), "count"), std::string(kind) + " count");
      std::uint64_t stride = 0;
      for (std::size_t i = body.find("<input"); i != std::string::npos; i = body.find("<input", i + 1)) {
        const std::string offset = attribute(body.substr(i, body.find('>', i) - i), "offset");
        stride = std::max(stride, (offset.empty() ? 0 : whole(offset, "input offset")) + 1);
      }
      auto numbers_in = [&](const std::string& tag) -> std::vector<std::uint64_t> {
        const std::size_t first = body.find("<" + tag + ">");
        if (first == std::string::npos) return {};
        if (body.find("<" + tag + ">", first + 1) != std::string::npos)
          throw InvalidInput(path + ": a Collada <" + kind + "> holds two <" + tag + "> lists");
        const std::size_t last = body.find("</" + tag + ">", first);
        std::istringstream words(body.substr(first + tag.size() + 2, last == std::string::npos ? std::string::npos : last - first - tag.size() - 2));
        std::vector<std::uint64_t> v;
        for (std::string w; words >> w;) v.push_back(whole(w, "index in <" + tag + ">"));
        return v;
      };
      std::uint64_t corners = 3 * count;
      if (std::string(kind) == "polylist") {
        const std::vector<std::uint64_t> vcount = numbers_in("vcount");
        if (vcount.size() != count)
          throw InvalidInput(path + ": a Collada <polylist> of " + std::to_string(count) + " polygons has " + std::to_string(vcount.size()) +
                             " sizes in its <vcount>");
        corners = 0;
        for (std::uint64_t n : vcount) corners += n;
      }
      const std::size_t p_count = numbers_in("p").size();
      if (p_count != corners * std::max<std::uint64_t>(stride, 1))
        throw InvalidInput(path + ": a Collada <" + kind + "> of " + std::to_string(count) + " polygons (" + std::to_string(corners) +
                           " corners x " + std::to_string(stride) + " inputs) holds " + std::to_string(p_count) + " indices in its <p>");
    }
  }
  for (const char* list : {"<p>", "<vcount>", "<v>"}) {
    const std::string close = std::string("</") + (list + 1);
    for (std::size_t at = xml.find(list); at != std::string::npos; at = xml.find(list, at + 1)) {
      const std::size_t end = xml.find(close, at);
      if (end == std::string::npos) throw InvalidInput(path + ": a Collada " + std::string(list) + " list is not closed");
      std::istringstream words(xml.substr(at + std::strlen(list), end - at - std::strlen(list)));
      for (std::string w; words >> w;)
        if (whole(w, std::string("index in ") + list) > largest)
          throw InvalidInput(path + ": Collada index " + w + " in a " + list + " list is beyond every array of the file");
    }
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
