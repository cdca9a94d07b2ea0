// A 3MF package (a zip archive) before Assimp opens it, and its unit:
//  1. every entry of the central directory inflated and held to its CRC-32 and sizes (Assimp's
//     unzip gives up on a damaged entry silently, and aborts on an unreadable root part), the
//     total held below 1 GB (a small archive can claim gigabytes);
//  2. the root relationship names the 3D model part, which must be in the zip;
//  3. every transform of the model holds 12 numbers (Assimp reads a shorter one into an
//     uninitialised matrix) and no component contains itself (Assimp recurses without end);
//  4. every vertex has its x, y and z, each a decimal number as the 3MF schema writes them
//     (Assimp read "0x10" as 16 and text or a missing coordinate as 0), every triangle's v1,
//     v2, v3 a whole number naming a vertex of its mesh;
//  5. the unit: the model's unit attribute, read from the zip (Assimp does not expose it).
#include "scene_file_checks.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include "string_util.h"
#include <zlib.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <sstream>
#include <vector>

namespace hb::vtk {

namespace {

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

// Assimp inflates every entry whole: an archive that claims more is refused.
constexpr std::uint64_t kMax3mfInflated = std::uint64_t(1) << 30;

// Every entry of the archive inflated and held to its CRC and sizes, by name.
std::map<std::string, std::string> three_mf_parts(const std::string& path) {
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
  return parts;
}

// The 3D model part the root relationship (_rels/.rels) names; Assimp asserts that both exist.
const std::string& three_mf_model(const std::string& path, const std::map<std::string, std::string>& parts) {
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
  return model->second;
}

// Every transform="..." of the model holds 12 finite numbers.
void check_three_mf_transforms(const std::string& path, const std::string& xml) {
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
}

// No object contains itself through its components (a depth-first walk of object id -> the
// object ids it contains).
void check_three_mf_components(const std::string& path, const std::string& xml) {
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

// The attributes of the XML tag in [begin, end) (after its name), in order. Throws for a tag
// that is not name="value" pairs or repeats a name.
std::vector<std::pair<std::string, std::string>> tag_attributes(const std::string& path, const std::string& xml, std::size_t begin,
                                                                std::size_t end, const std::string& what) {
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t p = begin;
  for (;;) {
    while (p < end && std::isspace((unsigned char)xml[p])) ++p;
    if (p >= end || xml[p] == '/') return out;
    const std::size_t name = p;
    while (p < end && xml[p] != '=' && !std::isspace((unsigned char)xml[p])) ++p;
    const std::string key = xml.substr(name, p - name);
    while (p < end && std::isspace((unsigned char)xml[p])) ++p;
    if (p >= end || xml[p] != '=') throw InvalidInput(path + ": 3MF " + what + ": attribute " + quoted_text(key, 40) + " has no value");
    ++p;
    while (p < end && std::isspace((unsigned char)xml[p])) ++p;
    if (p >= end || (xml[p] != '"' && xml[p] != '\'')) throw InvalidInput(path + ": 3MF " + what + ": attribute " + quoted_text(key, 40) + " is not quoted");
    const std::size_t close = xml.find(xml[p], p + 1);
    if (close == std::string::npos || close >= end) throw InvalidInput(path + ": 3MF " + what + ": attribute " + quoted_text(key, 40) + " is not closed");
    for (const auto& kv : out)
      if (kv.first == key) throw InvalidInput(path + ": 3MF " + what + " has the attribute " + quoted_text(key, 40) + " twice");
    out.emplace_back(key, xml.substr(p + 1, close - p - 1));
    p = close + 1;
  }
}

// A decimal number as the 3MF schema's ST_Number: [+-]digits[.digits][e[+-]digits], finite.
bool strict_number(const std::string& t) {
  std::size_t i = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < t.size() && std::isdigit((unsigned char)t[i])) ++i, ++digits;
  if (i < t.size() && t[i] == '.') {
    ++i;
    while (i < t.size() && std::isdigit((unsigned char)t[i])) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t exponent = 0;
    while (i < t.size() && std::isdigit((unsigned char)t[i])) ++i, ++exponent;
    if (exponent == 0) return false;
  }
  return i == t.size() && std::isfinite(std::strtod(t.c_str(), nullptr));
}

// Every <vertex> of every mesh has x, y and z as strict numbers; every <triangle> has v1, v2
// and v3 as whole numbers below its mesh's vertex count.
void check_three_mf_vertices(const std::string& path, const std::string& xml) {
  std::string object = "?";
  std::uint64_t vertices = 0, triangles = 0;
  auto is_tag = [&](std::size_t p, const char* name) {
    const std::size_t n = std::strlen(name);
    return xml.compare(p + 1, n, name) == 0 && p + 1 + n < xml.size() &&
           (std::isspace((unsigned char)xml[p + 1 + n]) || xml[p + 1 + n] == '/' || xml[p + 1 + n] == '>');
  };
  // The end of the tag at p: its '>' outside quoted values.
  auto tag_end = [&](std::size_t p) {
    char quote = 0;
    for (std::size_t i = p + 1; i < xml.size(); ++i) {
      if (quote) {
        if (xml[i] == quote) quote = 0;
      } else if (xml[i] == '"' || xml[i] == '\'') {
        quote = xml[i];
      } else if (xml[i] == '>') {
        return i;
      }
    }
    return std::string::npos;
  };
  for (std::size_t p = xml.find('<'); p != std::string::npos; p = xml.find('<', p + 1)) {
    const char* tag = is_tag(p, "object") ? "object" : is_tag(p, "mesh") ? "mesh" : is_tag(p, "vertex") ? "vertex"
                    : is_tag(p, "triangle") ? "triangle" : nullptr;
    if (!tag) continue;
    const std::size_t end = tag_end(p);
    if (end == std::string::npos) throw InvalidInput(path + ": a 3MF <" + tag + "> tag is not closed");
    if (is_tag(p, "object")) {
      for (const auto& [k, v] : tag_attributes(path, xml, p + 7, end, "object"))
        if (k == "id") object = quoted_text(v, 40);
    } else if (is_tag(p, "mesh")) {
      vertices = triangles = 0;
    } else if (is_tag(p, "vertex")) {
      const std::string what = "object " + object + " vertex " + std::to_string(vertices);
      const auto attributes = tag_attributes(path, xml, p + 7, end, what);
      for (const char* axis : {"x", "y", "z"}) {
        const auto it = std::find_if(attributes.begin(), attributes.end(), [&](const auto& kv) { return kv.first == axis; });
        if (it == attributes.end()) throw InvalidInput(path + ": 3MF " + what + " has no " + axis + " attribute");
        if (!strict_number(it->second))
          throw InvalidInput(path + ": 3MF " + what + ": " + axis + "=\"" + quoted_text(it->second, 40) + "\" is not a finite decimal number");
      }
      ++vertices;
    } else if (is_tag(p, "triangle")) {
      const std::string what = "object " + object + " triangle " + std::to_string(triangles);
      const auto attributes = tag_attributes(path, xml, p + 9, end, what);
      for (const char* corner : {"v1", "v2", "v3"}) {
        const auto it = std::find_if(attributes.begin(), attributes.end(), [&](const auto& kv) { return kv.first == corner; });
        if (it == attributes.end()) throw InvalidInput(path + ": 3MF " + what + " has no " + corner + " attribute");
        const std::string& v = it->second;
        if (v.empty() || v.size() > 12 || v.find_first_not_of("0123456789") != std::string::npos)
          throw InvalidInput(path + ": 3MF " + what + ": " + corner + "=\"" + quoted_text(v, 40) + "\" is not a whole number");
        if (std::stoull(v) >= vertices)
          throw InvalidInput(path + ": 3MF " + what + ": " + corner + "=\"" + v + "\" is beyond the " + std::to_string(vertices) +
                             " vertices of its mesh");
      }
      ++triangles;
    }
  }
}

} // namespace

void check_3mf(const std::string& path) {
  const std::map<std::string, std::string> parts = three_mf_parts(path);
  const std::string& xml = three_mf_model(path, parts);
  check_three_mf_transforms(path, xml);
  check_three_mf_components(path, xml);
  check_three_mf_vertices(path, xml);
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

} // namespace hb::vtk
