// glTF checked field by field (see gltf_check.h): the container, then the JSON's buffers,
// buffer views, accessors, meshes and node graph, each index in range and each length within
// what backs it.
#include "formats/gltf_check.h"
#include "errors.h"
#include <nlohmann/json.hpp>
#include <cstring>
#include <vector>

namespace hb {

namespace {

using nlohmann::json;

std::uint32_t le32(const std::string& b, std::size_t at) {
  const auto* p = reinterpret_cast<const unsigned char*>(b.data() + at);
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

class GltfChecker {
public:
  GltfChecker(const std::string& name, const json& doc) : name_(name), doc_(doc) {}

  // An array member (absent: empty), each element an object.
  const json& array(const json& parent, const char* key, const std::string& where) {
    static const json empty = json::array();
    if (!parent.is_object() || !parent.contains(key)) return empty;
    const json& a = parent.at(key);
    if (!a.is_array()) fail(where + "." + key + " is not an array");
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!a[i].is_object()) fail(where + "." + key + "[" + std::to_string(i) + "] is not an object");
    return a;
  }
  // A whole number member in [lo, hi]; `fallback` when absent (required: fallback < 0).
  std::uint64_t number(const json& o, const char* key, const std::string& where, long long fallback, std::uint64_t hi) {
    if (!o.contains(key)) {
      if (fallback < 0) fail(where + " has no " + key);
      return std::uint64_t(fallback);
    }
    const json& v = o.at(key);
    if (!v.is_number_integer() && !v.is_number_unsigned()) fail(where + "." + key + " is not a whole number");
    if (v.is_number_integer() && v.get<long long>() < 0) fail(where + "." + key + " is negative");
    const std::uint64_t n = v.get<std::uint64_t>();
    if (n > hi) fail(where + "." + key + " is " + std::to_string(n) + ", beyond " + std::to_string(hi));
    return n;
  }
  [[noreturn]] void fail(const std::string& what) const { throw InvalidInput(name_ + ": glTF " + what); }

  const std::string& name_;
  const json& doc_;
};

// Bytes of a "data:...;base64,XXXX" URI once decoded.
std::uint64_t data_uri_bytes(const std::string& uri) {
  const std::size_t comma = uri.find(',');
  if (comma == std::string::npos) return 0;
  if (uri.substr(0, comma).find(";base64") == std::string::npos) return uri.size() - comma - 1;
  std::uint64_t n = uri.size() - comma - 1;
  std::uint64_t pad = 0;
  for (std::size_t i = uri.size(); i > comma + 1 && uri[i - 1] == '=' && pad < 2; --i) ++pad;
  return n / 4 * 3 - pad;
}

unsigned component_bytes(std::uint64_t type) {
  switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
  }
}

unsigned type_components(const std::string& t) {
  if (t == "SCALAR") return 1;
  if (t == "VEC2") return 2;
  if (t == "VEC3") return 3;
  if (t == "VEC4") return 4;
  if (t == "MAT2") return 4;
  if (t == "MAT3") return 9;
  if (t == "MAT4") return 16;
  return 0;
}

} // namespace

std::string check_glb(const std::string& name, const std::string& b, std::uint64_t& bin_bytes) {
  bin_bytes = 0;
  if (b.size() < 20) throw InvalidInput(name + ": " + std::to_string(b.size()) + " bytes: too short for a GLB file");
  if (b.compare(0, 4, "glTF") != 0) throw InvalidInput(name + ": not a GLB file (no \"glTF\" magic)");
  if (le32(b, 4) != 2) throw InvalidInput(name + ": GLB version " + std::to_string(le32(b, 4)) + ", not 2");
  const std::uint32_t length = le32(b, 8);
  if (length != b.size())
    throw InvalidInput(name + ": the GLB header gives a length of " + std::to_string(length) + " bytes, the file has " +
                       std::to_string(b.size()) + " (truncated or padded)");
  std::string text;
  std::size_t at = 12;
  int chunk = 0;
  while (at < b.size()) {
    if (b.size() - at < 8) throw InvalidInput(name + ": GLB chunk " + std::to_string(chunk) + " header is cut short");
    const std::uint32_t n = le32(b, at), type = le32(b, at + 4);
    if (n > b.size() - at - 8)
      throw InvalidInput(name + ": GLB chunk " + std::to_string(chunk) + " claims " + std::to_string(n) + " bytes, only " +
                         std::to_string(b.size() - at - 8) + " follow");
    if (chunk == 0) {
      if (type != 0x4E4F534Au) throw InvalidInput(name + ": the first GLB chunk is not JSON");
      text = b.substr(at + 8, n);
    } else if (type == 0x004E4942u) {
      if (chunk != 1) throw InvalidInput(name + ": a second GLB BIN chunk");
      bin_bytes = n;
    }  // other chunk types are ignored, as the specification says
    at += 8 + std::size_t(n);
    ++chunk;
    if (chunk > 1024) throw InvalidInput(name + ": more than 1024 GLB chunks");
  }
  if (chunk == 0) throw InvalidInput(name + ": the GLB file has no chunk");
  return text;
}

void check_gltf_json(const std::string& name, const std::string& text, std::uint64_t bin_bytes,
                     const std::function<std::uint64_t(const std::string& uri)>& external_bytes) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    throw InvalidInput(name + ": the glTF JSON does not parse (" + std::string(e.what()) + ")");
  }
  if (!doc.is_object()) throw InvalidInput(name + ": the glTF JSON is not an object");
  GltfChecker c(name, doc);
  const json& asset = doc.contains("asset") ? doc.at("asset") : json();
  if (!asset.is_object() || !asset.contains("version") || !asset.at("version").is_string() ||
      asset.at("version").get<std::string>().rfind("2.", 0) != 0)
    c.fail("asset.version is missing or not 2.x (only glTF 2.0 is read)");
  const std::uint64_t big = std::uint64_t(1) << 40;
  // Buffers and what backs them.
  const json& buffers = c.array(doc, "buffers", "");
  std::vector<std::uint64_t> buffer_length;
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    const std::string w = "buffers[" + std::to_string(i) + "]";
    const std::uint64_t n = c.number(buffers[i], "byteLength", w, -1, big);
    std::uint64_t have = 0;
    if (!buffers[i].contains("uri")) {
      if (i != 0) c.fail(w + " has no uri (only buffer 0 of a GLB may use the BIN chunk)");
      have = bin_bytes;
    } else {
      if (!buffers[i].at("uri").is_string()) c.fail(w + ".uri is not a string");
      const std::string uri = buffers[i].at("uri").get<std::string>();
      have = uri.rfind("data:", 0) == 0 ? data_uri_bytes(uri) : external_bytes(uri);
    }
    if (have < n)
      c.fail(w + " declares " + std::to_string(n) + " bytes, its data holds " + std::to_string(have));
    buffer_length.push_back(n);
  }
  // Buffer views within their buffers.
  const json& views = c.array(doc, "bufferViews", "");
  std::vector<std::uint64_t> view_length, view_stride;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const std::string w = "bufferViews[" + std::to_string(i) + "]";
    const std::uint64_t b = c.number(views[i], "buffer", w, -1, buffers.empty() ? 0 : buffers.size() - 1);
    if (buffers.empty()) c.fail(w + " refers to a buffer but there is none");
    const std::uint64_t off = c.number(views[i], "byteOffset", w, 0, big), n = c.number(views[i], "byteLength", w, -1, big);
    if (off + n > buffer_length[b])
      c.fail(w + " spans bytes " + std::to_string(off) + " to " + std::to_string(off + n) + " of a " +
             std::to_string(buffer_length[b]) + "-byte buffer");
    view_length.push_back(n);
    view_stride.push_back(c.number(views[i], "byteStride", w, 0, 252));
  }
  // Accessors within their views.
  const json& accessors = c.array(doc, "accessors", "");
  for (std::size_t i = 0; i < accessors.size(); ++i) {
    const std::string w = "accessors[" + std::to_string(i) + "]";
    const json& a = accessors[i];
    const unsigned cb = component_bytes(c.number(a, "componentType", w, -1, 1u << 16));
    if (cb == 0) c.fail(w + ".componentType is not a glTF component type");
    if (!a.contains("type") || !a.at("type").is_string()) c.fail(w + ".type is missing");
    const unsigned comps = type_components(a.at("type").get<std::string>());
    if (comps == 0) c.fail(w + ".type is not SCALAR, VEC2-4 or MAT2-4");
    const std::uint64_t count = c.number(a, "count", w, -1, std::uint64_t(1) << 32);
    if (count == 0) c.fail(w + ".count is 0");
    if (!a.contains("bufferView")) continue;  // all zeros (or sparse): nothing to read
    const std::uint64_t v = c.number(a, "bufferView", w, -1, views.empty() ? 0 : views.size() - 1);
    if (views.empty()) c.fail(w + " refers to a buffer view but there is none");
    const std::uint64_t off = c.number(a, "byteOffset", w, 0, big);
    const std::uint64_t element = std::uint64_t(cb) * comps;
    const std::uint64_t stride = view_stride[v] ? view_stride[v] : element;
    if (off + stride * (count - 1) + element > view_length[v])
      c.fail(w + " reads " + std::to_string(count) + " elements from byte " + std::to_string(off) + " of a " +
             std::to_string(view_length[v]) + "-byte buffer view (it runs past its end)");
  }
  // Meshes' primitives refer to accessors that exist.
  const json& meshes = c.array(doc, "meshes", "");
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const std::string w = "meshes[" + std::to_string(m) + "]";
    const json& prims = c.array(meshes[m], "primitives", w);
    for (std::size_t p = 0; p < prims.size(); ++p) {
      const std::string wp = w + ".primitives[" + std::to_string(p) + "]";
      if (prims[p].contains("indices")) c.number(prims[p], "indices", wp, -1, accessors.empty() ? 0 : accessors.size() - 1);
      if (prims[p].contains("indices") && accessors.empty()) c.fail(wp + ".indices refers to no accessor");
      if (!prims[p].contains("attributes") || !prims[p].at("attributes").is_object()) c.fail(wp + " has no attributes");
      for (const auto& [key, value] : prims[p].at("attributes").items()) {
        if (!value.is_number_unsigned() || value.get<std::uint64_t>() >= accessors.size())
          c.fail(wp + ".attributes." + key + " is not the index of an accessor");
      }
    }
  }
  // The node graph: children in range, one parent each, no cycle, depth bounded.
  const json& nodes = c.array(doc, "nodes", "");
  std::vector<int> parent(nodes.size(), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const std::string w = "nodes[" + std::to_string(i) + "]";
    if (nodes[i].contains("mesh")) {
      c.number(nodes[i], "mesh", w, -1, meshes.empty() ? 0 : meshes.size() - 1);
      if (meshes.empty()) c.fail(w + ".mesh refers to no mesh");
    }
    if (nodes[i].contains("matrix")) {
      const json& mx = nodes[i].at("matrix");
      if (!mx.is_array() || mx.size() != 16) c.fail(w + ".matrix is not 16 numbers");
      for (const json& x : mx)
        if (!x.is_number()) c.fail(w + ".matrix holds a non-number");
    }
    if (!nodes[i].contains("children")) continue;
    const json& ch = nodes[i].at("children");
    if (!ch.is_array()) c.fail(w + ".children is not an array");
    for (const json& k : ch) {
      if (!k.is_number_unsigned() || k.get<std::uint64_t>() >= nodes.size()) c.fail(w + ".children holds a node index out of range");
      const std::size_t child = k.get<std::size_t>();
      if (child == i) c.fail(w + " is its own child");
      if (parent[child] >= 0) c.fail("nodes[" + std::to_string(child) + "] has two parents (a node graph must be a tree)");
      parent[child] = int(i);
    }
  }
  // With one parent each, a cycle shows as a walk up that never reaches a root; depth too.
  std::vector<int> depth(nodes.size(), -1);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    std::vector<std::size_t> path;
    std::size_t at = i;
    while (depth[at] < 0 && parent[at] >= 0) {
      path.push_back(at);
      if (path.size() > nodes.size()) c.fail("nodes[" + std::to_string(i) + "] is in a cycle of children");
      at = std::size_t(parent[at]);
    }
    int d = depth[at] < 0 ? 0 : depth[at];
    depth[at] = d;
    for (auto it = path.rbegin(); it != path.rend(); ++it) depth[*it] = ++d;
    if (d > kMaxGltfDepth)
      c.fail("nodes are nested " + std::to_string(d) + " deep, more than " + std::to_string(kMaxGltfDepth));
  }
  const json& scenes = c.array(doc, "scenes", "");
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    if (!scenes[s].contains("nodes")) continue;
    const json& roots = scenes[s].at("nodes");
    if (!roots.is_array()) c.fail("scenes[" + std::to_string(s) + "].nodes is not an array");
    for (const json& r : roots)
      if (!r.is_number_unsigned() || r.get<std::uint64_t>() >= nodes.size())
        c.fail("scenes[" + std::to_string(s) + "].nodes holds a node index out of range");
  }
}

} // namespace hb
