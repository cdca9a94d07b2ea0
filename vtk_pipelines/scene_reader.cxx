// Scenes through Assimp:
//  1. Assimp reads the file with triangulation, node transforms baked into the vertices
//     (PreTransformVertices), identical vertices joined, points and lines dropped;
//  2. every mesh's triangles go into one core mesh;
//  3. the unit: glTF metres (its specification), Collada metres (Assimp applies <unit meter>),
//     FBX from the UnitScaleFactor metadata (centimetres per unit), 3MF from the model's unit
//     attribute, read here from the zip (Assimp does not expose it).
#include "scene_reader.h"
#include "string_util.h"
#include "errors.h"
#include "formats/gltf_check.h"
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/DefaultLogger.hpp>
#include <assimp/config.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <zlib.h>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <regex>
#include <sstream>

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;

std::uint32_t le32(const unsigned char* p) { return p[0] | (p[1] << 8) | (p[2] << 16) | (std::uint32_t(p[3]) << 24); }
std::uint16_t le16(const unsigned char* p) { return std::uint16_t(p[0] | (p[1] << 8)); }

// The first `limit` bytes of the zip entry `name` (stored or deflated), via the central
// directory; empty when absent.
std::string zip_entry_head(const std::string& path, const std::string& name, std::size_t limit) {
  std::ifstream in(path, std::ios::binary);
  std::string zip((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto* z = reinterpret_cast<const unsigned char*>(zip.data());
  if (zip.size() < 22) return {};
  std::size_t eocd = std::string::npos;
  for (std::size_t i = zip.size() - 22 + 1; i-- > 0 && zip.size() - i < 70000;)
    if (le32(z + i) == 0x06054b50) {
      eocd = i;
      break;
    }
  if (eocd == std::string::npos) return {};
  std::size_t at = le32(z + eocd + 16);
  const std::size_t entries = le16(z + eocd + 10);
  for (std::size_t e = 0; e < entries && at + 46 <= zip.size() && le32(z + at) == 0x02014b50; ++e) {
    const std::size_t name_len = le16(z + at + 28), extra = le16(z + at + 30), comment = le16(z + at + 32);
    const std::uint16_t method = le16(z + at + 10);
    const std::size_t packed = le32(z + at + 20), local = le32(z + at + 42);
    const std::string entry(zip.data() + at + 46, std::min(name_len, zip.size() - at - 46));
    at += 46 + name_len + extra + comment;
    if (lower(entry) != lower(name) || local + 30 > zip.size()) continue;
    const std::size_t data = local + 30 + le16(z + local + 26) + le16(z + local + 28);
    if (data + packed > zip.size()) return {};
    if (method == 0) return zip.substr(data, std::min(packed, limit));
    if (method != 8) return {};
    std::string out(limit, '\0');
    z_stream s{};
    if (inflateInit2(&s, -15) != Z_OK) return {};
    s.next_in = const_cast<Bytef*>(z + data);
    s.avail_in = uInt(packed);
    s.next_out = reinterpret_cast<Bytef*>(out.data());
    s.avail_out = uInt(limit);
    inflate(&s, Z_SYNC_FLUSH);
    out.resize(limit - s.avail_out);
    inflateEnd(&s);
    return out;
  }
  return {};
}


// A 3MF archive before Assimp opens it: the zip's declared sizes (Assimp inflates every entry
// whole: a small archive can claim gigabytes), and in the model every transform of 12 numbers
// (Assimp reads a shorter one into an uninitialised matrix) and no component that contains
// itself (Assimp recurses without end).
constexpr std::uint64_t kMax3mfInflated = std::uint64_t(1) << 30;

void check_3mf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string zip((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto* z = reinterpret_cast<const unsigned char*>(zip.data());
  std::size_t eocd = std::string::npos;
  for (std::size_t i = zip.size() >= 22 ? zip.size() - 22 + 1 : 0; i-- > 0 && zip.size() - i < 70000;)
    if (le32(z + i) == 0x06054b50) {
      eocd = i;
      break;
    }
  if (eocd == std::string::npos) throw InvalidInput(path + ": not a 3MF file (not a zip archive: no central directory)");
  std::size_t at = le32(z + eocd + 16);
  const std::size_t entries = le16(z + eocd + 10);
  std::uint64_t total = 0;
  // Every entry inflated and held to its CRC and size (Assimp's unzip gives up on a damaged
  // entry silently, and an unreadable root part is an assertion: the process aborts).
  std::map<std::string, std::string> parts;
  for (std::size_t e = 0; e < entries; ++e) {
    if (at + 46 > zip.size() || le32(z + at) != 0x02014b50)
      throw InvalidInput(path + ": the 3MF zip's central directory is damaged (entry " + std::to_string(e) + " of " +
                         std::to_string(entries) + ")");
    const std::size_t name_len = le16(z + at + 28), extra = le16(z + at + 30), comment = le16(z + at + 32);
    const std::uint16_t method = le16(z + at + 10);
    const std::uint32_t crc = le32(z + at + 16);
    const std::uint64_t packed = le32(z + at + 20), unpacked = le32(z + at + 24), local = le32(z + at + 42);
    if (at + 46 + name_len > zip.size()) throw InvalidInput(path + ": the 3MF zip's central directory is cut short");
    const std::string entry(zip.data() + at + 46, name_len);
    at += 46 + name_len + extra + comment;
    if (packed > zip.size()) throw InvalidInput(path + ": zip entry " + entry + " claims " + std::to_string(packed) + " packed bytes, more than the file");
    total += unpacked;
    if (total > kMax3mfInflated)
      throw InvalidInput(path + ": the 3MF archive inflates to more than " + std::to_string(kMax3mfInflated >> 20) +
                         " MB (entry " + entry + " alone claims " + std::to_string(unpacked >> 20) + " MB): refused");
    if (packed > 0 && unpacked / packed > 1100)
      throw InvalidInput(path + ": zip entry " + entry + " claims " + std::to_string(unpacked) + " bytes from " + std::to_string(packed) +
                         ", beyond what deflate can pack: a damaged archive or a zip bomb");
    if (entry.empty() || entry.back() == '/') continue;  // a directory
    const std::string damaged = path + ": zip entry " + entry + " is damaged (";
    if (local + 30 > zip.size() || le32(z + local) != 0x04034b50)
      throw InvalidInput(damaged + "no local header where the directory says)");
    // The local header agrees with the directory (Assimp's unzip reads the local one, and
    // aborted on a damaged CRC there); with a data descriptor (flag bit 3) its fields are 0.
    const bool descriptor = (le16(z + local + 6) & 8) != 0;
    if (le16(z + local + 8) != method || (!descriptor && (le32(z + local + 14) != crc || le32(z + local + 18) != packed ||
                                                          le32(z + local + 22) != unpacked)))
      throw InvalidInput(damaged + "its local header disagrees with the central directory on the method, CRC-32 or sizes)");
    const std::size_t data = std::size_t(local) + 30 + le16(z + local + 26) + le16(z + local + 28);
    if (data > zip.size() || packed > zip.size() - data) throw InvalidInput(damaged + "its data runs past the end of the file)");
    std::string out;
    if (method == 0) {
      if (packed != unpacked) throw InvalidInput(damaged + "stored with sizes " + std::to_string(packed) + " and " + std::to_string(unpacked) + ")");
      out = zip.substr(data, packed);
    } else if (method == 8) {
      out.assign(std::size_t(unpacked), '\0');
      z_stream st{};
      if (inflateInit2(&st, -15) != Z_OK) throw InvalidInput(damaged + "zlib would not start)");
      st.next_in = const_cast<Bytef*>(z + data);
      st.avail_in = uInt(packed);
      st.next_out = reinterpret_cast<Bytef*>(out.data());
      st.avail_out = uInt(unpacked);
      const int r = inflate(&st, Z_FINISH);
      const std::uint64_t got = unpacked - st.avail_out;
      inflateEnd(&st);
      if (r != Z_STREAM_END || got != unpacked)
        throw InvalidInput(damaged + "its deflated data does not inflate to the " + std::to_string(unpacked) + " bytes declared)");
    } else {
      throw InvalidInput(damaged + "compression method " + std::to_string(method) + ", not stored or deflated)");
    }
    if (std::uint32_t(crc32(0L, reinterpret_cast<const Bytef*>(out.data()), uInt(out.size()))) != crc)
      throw InvalidInput(damaged + "its CRC-32 does not match its contents)");
    parts[entry] = std::move(out);
  }
  // The root relationship (_rels/.rels) names the model part; Assimp asserts that both exist.
  const auto rels = parts.find("_rels/.rels");
  if (rels == parts.end()) throw InvalidInput(path + ": not a 3MF package: no _rels/.rels part in the zip");
  std::string root;
  static const std::regex relationship("<Relationship\\b[^>]*>"), target_re("\\bTarget\\s*=\\s*[\"']([^\"']*)[\"']"),
      type_re("\\bType\\s*=\\s*[\"']([^\"']*)[\"']");
  for (auto it = std::sregex_iterator(rels->second.begin(), rels->second.end(), relationship); it != std::sregex_iterator(); ++it) {
    const std::string tag = it->str();
    std::smatch t, ty;
    if (std::regex_search(tag, ty, type_re) && ty[1].str().size() >= 8 && ty[1].str().compare(ty[1].str().size() - 8, 8, "/3dmodel") == 0 &&
        std::regex_search(tag, t, target_re)) {
      root = t[1].str();
      break;
    }
  }
  if (root.empty()) throw InvalidInput(path + ": _rels/.rels names no 3D model part (no relationship of the 3dmodel type)");
  if (!root.empty() && root[0] == '/') root.erase(0, 1);
  const auto model = parts.find(root);
  if (model == parts.end()) throw InvalidInput(path + ": the 3D model part " + root + " named by _rels/.rels is not in the zip");
  const std::string& xml = model->second;
  // Every transform="..." holds 12 numbers.
  for (std::size_t p = xml.find("transform"); p != std::string::npos; p = xml.find("transform", p + 9)) {
    std::size_t q = p + 9;
    while (q < xml.size() && std::isspace((unsigned char)xml[q])) ++q;
    if (q >= xml.size() || xml[q] != '=') continue;
    ++q;
    while (q < xml.size() && std::isspace((unsigned char)xml[q])) ++q;
    if (q >= xml.size() || (xml[q] != '"' && xml[q] != '\'')) continue;
    const std::size_t end = xml.find(xml[q], q + 1);
    if (end == std::string::npos) throw InvalidInput(path + ": a 3MF transform attribute is not closed");
    std::istringstream numbers(xml.substr(q + 1, end - q - 1));
    int n = 0;
    for (std::string w; numbers >> w; ++n) {
      char* stop = nullptr;
      const double d = std::strtod(w.c_str(), &stop);
      if (*stop || !std::isfinite(d)) throw InvalidInput(path + ": a 3MF transform holds '" + w.substr(0, 20) + "', not a number");
    }
    if (n != 12) throw InvalidInput(path + ": a 3MF transform holds " + std::to_string(n) + " numbers, not 12 (a 3 x 4 matrix)");
  }
  // Components: object id -> the object ids it contains; no cycle.
  std::map<std::string, std::vector<std::string>> contains;
  std::string current;
  static const std::regex id_re("\\bid\\s*=\\s*[\"']([^\"']*)[\"']"), objectid_re("\\bobjectid\\s*=\\s*[\"']([^\"']*)[\"']");
  auto attribute = [&](std::size_t tag, std::size_t tag_end, const char* name) {
    const std::string t = xml.substr(tag, tag_end - tag);
    const std::regex& re = std::string(name) == "id" ? id_re : objectid_re;
    std::smatch m;
    return std::regex_search(t, m, re) ? m[1].str() : std::string();
  };
  for (std::size_t p = xml.find('<'); p != std::string::npos; p = xml.find('<', p + 1)) {
    const std::size_t end = xml.find('>', p);
    if (end == std::string::npos) break;
    if (end - p > 4096) continue;
    if (xml.compare(p, 7, "<object") == 0 && (std::isspace((unsigned char)xml[p + 7]))) current = attribute(p, end, "id");
    else if (xml.compare(p, 10, "<component") == 0 && std::isspace((unsigned char)xml[p + 10]))
      contains[current].push_back(attribute(p, end, "objectid"));
  }
  std::map<std::string, int> state;  // 1: on the path, 2: done
  for (const auto& [root, children] : contains) {
    if (state[root]) continue;
    std::vector<std::pair<std::string, std::size_t>> stack{{root, 0}};
    state[root] = 1;
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      const auto it = contains.find(node);
      if (it == contains.end() || next >= it->second.size()) {
        state[node] = 2;
        stack.pop_back();
        continue;
      }
      const std::string child = it->second[next++];
      if (state[child] == 1) throw InvalidInput(path + ": 3MF object " + child + " contains itself through its components");
      if (state[child] == 0) {
        state[child] = 1;
        stack.emplace_back(child, 0);
      }
    }
  }
}


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

// glTF and GLB before Assimp opens them (gltf_check.h).
void check_gltf(const std::string& path, bool binary) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint64_t bin = 0;
  const std::string text = binary ? check_glb(path, bytes, bin) : bytes;
  const fs::path dir = fs::path(path).parent_path();
  check_gltf_json(path, text, bin, [&](const std::string& uri) -> std::uint64_t {
    std::string file;  // percent-decoded
    for (std::size_t i = 0; i < uri.size(); ++i) {
      if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) && std::isxdigit((unsigned char)uri[i + 2])) {
        file += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        file += uri[i];
      }
    }
    const fs::path p = dir / file;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw InvalidInput(path + ": the glTF buffer file " + p.string() + " is missing");
    return fs::file_size(p, ec);
  });
}

// The unit of a 3MF model (its <model unit="..."> attribute; millimetre when absent).
std::string three_mf_unit(const std::string& path, std::string& source) {
  const std::string head = zip_entry_head(path, "3D/3dmodel.model", 4096);
  std::smatch m;
  static const std::regex unit_attr("<model[^>]*\\bunit\\s*=\\s*\"([a-zA-Z]+)\"");
  if (!head.empty() && std::regex_search(head, m, unit_attr)) {
    source = "file (3MF model unit=\"" + m[1].str() + "\")";
    const std::string u = lower(m[1].str());
    if (u == "micron") return "um";
    if (u == "millimeter") return "mm";
    if (u == "centimeter") return "cm";
    if (u == "inch") return "in";
    if (u == "foot") return "ft";
    if (u == "meter") return "m";
    throw InvalidInput(path + ": unknown 3MF unit \"" + m[1].str() + "\"");
  }
  source = head.empty() ? "default (3D/3dmodel.model not found in the zip: millimetre assumed)"
                        : "default (3MF without a unit attribute: millimetre)";
  return "mm";
}

std::string format_of(const std::string& ext) {
  if (ext == ".gltf" || ext == ".glb") return "glTF";
  if (ext == ".3mf") return "3MF";
  if (ext == ".fbx") return "FBX";
  if (ext == ".dae") return "Collada";
  return ext;
}

std::string extension(const std::string& path) { return lower(fs::path(path).extension().string()); }

} // namespace

SceneModel read_scene(const std::string& path) {
  if (!fs::exists(path)) throw IoError(path + ": no such file");
  if (!std::ifstream(path).good()) throw IoError(path + ": cannot open the file");
  if (fs::file_size(path) == 0) throw IoError(path + ": the file is empty");
  const std::string ext = extension(path);
  SceneModel model;
  model.format = format_of(ext);
  if (ext == ".glb" || ext == ".gltf") check_gltf(path, ext == ".glb");
  if (ext == ".3mf") check_3mf(path);
  if (ext == ".dae") check_collada(path);
  if (ext == ".fbx") check_fbx(path);
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                     aiProcess_PreTransformVertices | aiProcess_SortByPType |
                                                     aiProcess_ValidateDataStructure);
  if (!scene) throw InvalidInput(path + ": Assimp: " + std::string(importer.GetErrorString()));
  std::size_t meshes = 0;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    ++meshes;
    const std::uint32_t base = std::uint32_t(model.mesh.positions.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw InvalidInput(path + ": mesh " + std::to_string(m) + " vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
      model.mesh.positions.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      const Triangle t{base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      model.mesh.triangles.push_back(t);
    }
  }
  if (model.mesh.triangles.empty()) throw InvalidInput(path + ": no triangles in the scene (" + std::to_string(scene->mNumMeshes) + " meshes)");
  model.mesh.compute_vertex_normals();

  std::string source = "file";
  if (ext == ".gltf" || ext == ".glb") {
    model.unit = "m";
    source = "file (glTF is in metres by its specification)";
  } else if (ext == ".dae") {
    model.unit = "m";
    source = "file (Collada <unit meter>, applied by Assimp: metres)";
  } else if (ext == ".fbx") {
    double cm_per_unit = 1.0;
    bool found = false;
    if (scene->mMetaData) {
      found = scene->mMetaData->Get("UnitScaleFactor", cm_per_unit);
      if (!found) {
        float f = 1.f;
        found = scene->mMetaData->Get("UnitScaleFactor", f);
        cm_per_unit = f;
      }
    }
    if (!(cm_per_unit > 0) || !std::isfinite(cm_per_unit)) cm_per_unit = 1.0;
    const double mm = 10.0 * cm_per_unit;
    model.unit = std::abs(mm - 1) < 1e-9 ? "mm" : std::abs(mm - 10) < 1e-9 ? "cm" : std::abs(mm - 1000) < 1e-6 ? "m" : std::abs(mm - 25.4) < 1e-6 ? "in" : "";
    if (model.unit.empty()) {
      // An unusual factor: keep it exactly by scaling here and calling the result millimetres.
      for (Vec3& p : model.mesh.positions) p *= float(mm);
      model.unit = "mm";
    }
    source = found ? "file (FBX UnitScaleFactor " + std::to_string(cm_per_unit) + " cm per unit)" : "default (FBX without UnitScaleFactor: centimetres)";
  } else if (ext == ".3mf") {
    model.unit = three_mf_unit(path, source);
  }
  model.facts["meshes"] = meshes;
  model.facts["file_unit"] = model.unit;
  model.facts["file_unit_read_from"] = source;
  model.facts["triangles"] = model.mesh.triangle_count();
  return model;
}

void write_scene(const TriangleMesh& mesh, const std::string& path) {
  const std::string ext = extension(path);
  std::string id;
  double scale = 1.0;  // mm to the format's unit as read_scene reads it
  if (ext == ".gltf") id = "gltf2", scale = 0.001;
  else if (ext == ".glb") id = "glb2", scale = 0.001;
  else if (ext == ".dae") id = "collada", scale = 0.001;
  else if (ext == ".3mf") id = "3mf", scale = 1.0;
  else if (ext == ".fbx") id = "fbxa", scale = 0.1;  // ASCII: Assimp 5.2 cannot read its own binary FBX
  else throw InvalidInput(path + ": write_scene writes .gltf .glb .3mf .dae .fbx");

  auto scene = std::make_unique<aiScene>();
  scene->mRootNode = new aiNode();
  scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};
  scene->mNumMaterials = 1;
  scene->mMeshes = new aiMesh*[1]{new aiMesh()};
  scene->mNumMeshes = 1;
  // The mesh hangs from a child of the root: Assimp's 3MF exporter writes the root's children.
  auto* node = new aiNode("mesh");
  node->mParent = scene->mRootNode;
  node->mMeshes = new unsigned[1]{0};
  node->mNumMeshes = 1;
  scene->mRootNode->mChildren = new aiNode*[1]{node};
  scene->mRootNode->mNumChildren = 1;
  aiMesh* m = scene->mMeshes[0];
  m->mMaterialIndex = 0;
  m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  m->mNumVertices = unsigned(mesh.vertex_count());
  m->mVertices = new aiVector3D[mesh.vertex_count()];
  m->mNormals = new aiVector3D[mesh.vertex_count()];
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Vec3 p = mesh.positions[v] * float(scale);
    m->mVertices[v] = aiVector3D(p.x(), p.y(), p.z());
    const Vec3 n = v < mesh.normals.size() ? mesh.normals[v] : Vec3::UnitZ();
    m->mNormals[v] = aiVector3D(n.x(), n.y(), n.z());
  }
  m->mNumFaces = unsigned(mesh.triangle_count());
  m->mFaces = new aiFace[mesh.triangle_count()];
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    m->mFaces[t].mNumIndices = 3;
    m->mFaces[t].mIndices = new unsigned[3]{mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]};
  }
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), id, path) != AI_SUCCESS)
    throw IoError(path + ": Assimp could not write it: " + std::string(exporter.GetErrorString()));
}

} // namespace hb::vtk
