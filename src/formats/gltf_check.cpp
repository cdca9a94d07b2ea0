// glTF checked field by field (see gltf_check.h):
//  1. the container (GLB chunks);
//  2. the JSON's buffers (their bytes: the BIN chunk, a decoded data: URI or a file), buffer
//     views within their buffers, accessors within their views (aligned, strides that hold an
//     element), sparse accessors within their accessor;
//  3. meshes: every primitive's attributes name accessors, POSITION is VEC3 of FLOAT (unless
//     KHR_mesh_quantization is used) with its values finite and within its declared min and max
//     (a shifted offset or stride reads other bytes, which rarely stay inside the bounds),
//     indices are unsigned SCALARs naming existing vertices;
//  4. the node graph: children in range, one parent each, no cycle, depth bounded.
#include "formats/gltf_check.h"
#include "errors.h"
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <vector>

namespace hb {

namespace {

using nlohmann::json;

std::uint32_t le32(const char* b) {
  const auto* p = reinterpret_cast<const unsigned char*>(b);
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}
std::uint32_t le32(const std::string& b, std::size_t at) { return le32(b.data() + at); }

// The bytes of a "data:...;base64,XXXX" URI (or the text after the comma without ";base64").
std::string data_uri_bytes(const std::string& uri) {
  const std::size_t comma = uri.find(',');
  if (comma == std::string::npos) return {};
  if (uri.substr(0, comma).find(";base64") == std::string::npos) return uri.substr(comma + 1);
  std::string out;
  out.reserve((uri.size() - comma) / 4 * 3);
  std::uint32_t acc = 0;
  int bits = 0;
  for (std::size_t i = comma + 1; i < uri.size(); ++i) {
    const char c = uri[i];
    int v = -1;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+' || c == '-') v = 62;
    else if (c == '/' || c == '_') v = 63;
    if (v < 0) continue;  // padding, line breaks
    acc = (acc << 6) | std::uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += char((acc >> bits) & 0xFF);
    }
  }
  return out;
}

unsigned component_bytes(std::uint64_t type) {
  switch (type) {
    case 5120: case 5121: return 1;
    case 5122: case 5123: return 2;
    case 5125: case 5126: return 4;
    default: return 0;
  }
}

std::string component_name(std::uint64_t type) {
  switch (type) {
    case 5120: return "BYTE";
    case 5121: return "UNSIGNED_BYTE";
    case 5122: return "SHORT";
    case 5123: return "UNSIGNED_SHORT";
    case 5125: return "UNSIGNED_INT";
    case 5126: return "FLOAT";
    default: return std::to_string(type);
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

struct View {
  std::size_t buffer = 0;
  std::uint64_t offset = 0, length = 0, stride = 0;
};

struct Accessor {
  std::uint64_t component_type = 0, count = 0, offset = 0;
  unsigned component = 0, components = 0;
  std::string type;
  long long view = -1;  // -1: no buffer view (zeros)
  bool sparse = false;
  const json* object = nullptr;
};

class GltfChecker {
public:
  GltfChecker(const std::string& name, const json& doc, std::string_view bin,
              const std::function<std::string_view(const std::string&)>& external)
      : name_(name), doc_(doc), bin_(bin), external_(external) {
    // KHR_mesh_quantization stores positions as integers: their type is then the file's choice.
    for (const char* key : {"extensionsUsed", "extensionsRequired"})
      if (doc.is_object() && doc.contains(key) && doc.at(key).is_array())
        for (const json& e : doc.at(key))
          if (e == "KHR_mesh_quantization") quantized_ = true;
  }

  void run() {
    check_buffers();
    check_views();
    check_accessors();
    check_meshes();
    check_nodes();
  }

private:
  static constexpr std::uint64_t kBig = std::uint64_t(1) << 40;

  // An array member (absent: empty), each element an object.
  const json& array(const json& parent, const char* key, const std::string& where) const {
    static const json empty = json::array();
    if (!parent.is_object() || !parent.contains(key)) return empty;
    const json& a = parent.at(key);
    if (!a.is_array()) fail(where + "." + key + " is not an array");
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!a[i].is_object()) fail(where + "." + key + "[" + std::to_string(i) + "] is not an object");
    return a;
  }
  // A whole number member in [lo, hi]; `fallback` when absent (required: fallback < 0).
  std::uint64_t number(const json& o, const char* key, const std::string& where, long long fallback, std::uint64_t hi) const {
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
  // An index into a list of `size` (an element of "what", e.g. "accessor").
  std::size_t index(const json& o, const char* key, const std::string& where, std::size_t size, const char* what) const {
    if (size == 0) {
      if (!o.contains(key)) fail(where + " has no " + key);
      fail(where + "." + key + " refers to a " + what + " but there is none");
    }
    return std::size_t(number(o, key, where, -1, size - 1));
  }
  [[noreturn]] void fail(const std::string& what) const { throw InvalidInput(name_ + ": glTF " + what); }

  void check_buffers() {
    const json& buffers = array(doc_, "buffers", "");
    for (std::size_t i = 0; i < buffers.size(); ++i) {
      const std::string w = "buffers[" + std::to_string(i) + "]";
      const std::uint64_t n = number(buffers[i], "byteLength", w, -1, kBig);
      std::string_view have;
      if (!buffers[i].contains("uri")) {
        if (i != 0) fail(w + " has no uri (only buffer 0 of a GLB may use the BIN chunk)");
        have = bin_;
      } else {
        if (!buffers[i].at("uri").is_string()) fail(w + ".uri is not a string");
        const std::string uri = buffers[i].at("uri").get<std::string>();
        if (uri.rfind("data:", 0) == 0) {
          decoded_.push_back(data_uri_bytes(uri));
          have = decoded_.back();
        } else {
          have = external_(uri);
        }
      }
      if (have.size() < n) fail(w + " declares " + std::to_string(n) + " bytes, its data holds " + std::to_string(have.size()));
      // More than the declared length and the padding to 4 bytes: bytes inserted, or a length
      // changed (the views then read shifted data).
      if (have.size() > n + 3)
        fail(w + " declares " + std::to_string(n) + " bytes, its data holds " + std::to_string(have.size()) +
             " (more than its length and padding: data inserted or a length changed)");
      buffers_.push_back(have.substr(0, std::size_t(n)));
    }
  }

  void check_views() {
    const json& views = array(doc_, "bufferViews", "");
    for (std::size_t i = 0; i < views.size(); ++i) {
      const std::string w = "bufferViews[" + std::to_string(i) + "]";
      View v;
      v.buffer = index(views[i], "buffer", w, buffers_.size(), "buffer");
      v.offset = number(views[i], "byteOffset", w, 0, kBig);
      v.length = number(views[i], "byteLength", w, -1, kBig);
      if (v.offset + v.length > buffers_[v.buffer].size())
        fail(w + " spans bytes " + std::to_string(v.offset) + " to " + std::to_string(v.offset + v.length) + " of a " +
             std::to_string(buffers_[v.buffer].size()) + "-byte buffer");
      v.stride = number(views[i], "byteStride", w, 0, 252);
      if (views[i].contains("byteStride") && (v.stride < 4 || v.stride % 4 != 0))
        fail(w + ".byteStride is " + std::to_string(v.stride) + ", not a multiple of 4 from 4 to 252");
      views_.push_back(v);
    }
  }

  // An accessor's `count` elements of `element` bytes read from `view` at `offset` with `stride`
  // stay within the view, each aligned to its component.
  void check_span(const std::string& w, std::size_t view, std::uint64_t offset, std::uint64_t count, unsigned component,
                  std::uint64_t element, std::uint64_t stride) const {
    const View& v = views_[view];
    if ((v.offset + offset) % component != 0)
      fail(w + ".byteOffset " + std::to_string(offset) + " (byte " + std::to_string(v.offset + offset) +
           " of its buffer) is not a multiple of its " + std::to_string(component) + "-byte component");
    if (stride < element)
      fail(w + " has elements of " + std::to_string(element) + " bytes but bufferViews[" + std::to_string(view) + "].byteStride is " +
           std::to_string(stride));
    if (offset + stride * (count - 1) + element > v.length)
      fail(w + " reads " + std::to_string(count) + " elements from byte " + std::to_string(offset) + " of a " +
           std::to_string(v.length) + "-byte buffer view (it runs past its end)");
  }

  void check_accessors() {
    const json& accessors = array(doc_, "accessors", "");
    for (std::size_t i = 0; i < accessors.size(); ++i) {
      const std::string w = "accessors[" + std::to_string(i) + "]";
      const json& a = accessors[i];
      Accessor acc;
      acc.object = &a;
      acc.component_type = number(a, "componentType", w, -1, 1u << 16);
      acc.component = component_bytes(acc.component_type);
      if (acc.component == 0) fail(w + ".componentType " + std::to_string(acc.component_type) + " is not a glTF component type");
      if (!a.contains("type") || !a.at("type").is_string()) fail(w + ".type is missing");
      acc.type = a.at("type").get<std::string>();
      acc.components = type_components(acc.type);
      if (acc.components == 0) fail(w + ".type is not SCALAR, VEC2-4 or MAT2-4");
      acc.count = number(a, "count", w, -1, std::uint64_t(1) << 32);
      if (acc.count == 0) fail(w + ".count is 0");
      if (a.contains("sparse")) check_sparse(w, acc);
      if (a.contains("bufferView")) {
        acc.view = (long long)index(a, "bufferView", w, views_.size(), "buffer view");
        acc.offset = number(a, "byteOffset", w, 0, kBig);
        const std::uint64_t element = std::uint64_t(acc.component) * acc.components;
        const View& v = views_[std::size_t(acc.view)];
        check_span(w, std::size_t(acc.view), acc.offset, acc.count, acc.component, element, v.stride ? v.stride : element);
      }
      accessors_.push_back(acc);
    }
  }

  // A sparse accessor: `count` substitutions, their indices (unsigned, increasing, below the
  // accessor's count) and values within their buffer views.
  void check_sparse(const std::string& w, Accessor& acc) {
    const json& s = acc.object->at("sparse");
    const std::string ws = w + ".sparse";
    if (!s.is_object()) fail(ws + " is not an object");
    acc.sparse = true;
    const std::uint64_t n = number(s, "count", ws, -1, acc.count);
    if (n == 0) fail(ws + ".count is 0");
    for (const char* part : {"indices", "values"}) {
      const std::string wp = ws + "." + part;
      if (!s.contains(part) || !s.at(part).is_object()) fail(wp + " is missing");
      const json& o = s.at(part);
      const std::size_t view = index(o, "bufferView", wp, views_.size(), "buffer view");
      const std::uint64_t offset = number(o, "byteOffset", wp, 0, kBig);
      std::uint64_t type = acc.component_type;
      unsigned components = acc.components;
      if (std::string(part) == "indices") {
        type = number(o, "componentType", wp, -1, 1u << 16);
        if (type != 5121 && type != 5123 && type != 5125)
          fail(wp + ".componentType is " + component_name(type) + ", not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
        components = 1;
      }
      const unsigned cb = component_bytes(type);
      check_span(wp, view, offset, n, cb, std::uint64_t(cb) * components, std::uint64_t(cb) * components);
      if (std::string(part) != "indices") continue;
      std::uint64_t last = 0;
      for (std::uint64_t k = 0; k < n; ++k) {
        const std::uint64_t at = read_unsigned(view, offset + k * cb, cb);
        if (at >= acc.count || (k > 0 && at <= last))
          fail(wp + " element " + std::to_string(k) + " is " + std::to_string(at) +
               (at >= acc.count ? ", beyond the accessor's " + std::to_string(acc.count) + " elements" : ", not above the one before"));
        last = at;
      }
    }
  }

  std::uint64_t read_unsigned(std::size_t view, std::uint64_t at, unsigned bytes) const {
    const char* p = buffers_[views_[view].buffer].data() + views_[view].offset + at;
    const auto* u = reinterpret_cast<const unsigned char*>(p);
    if (bytes == 1) return u[0];
    if (bytes == 2) return std::uint64_t(u[0]) | std::uint64_t(u[1]) << 8;
    return le32(p);
  }
  float read_float(std::size_t view, std::uint64_t at) const {
    const std::uint32_t bits = std::uint32_t(read_unsigned(view, at, 4));
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }

  void check_meshes() {
    const json& meshes = array(doc_, "meshes", "");
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const std::string w = "meshes[" + std::to_string(m) + "]";
      const json& prims = array(meshes[m], "primitives", w);
      for (std::size_t p = 0; p < prims.size(); ++p) check_primitive(w + ".primitives[" + std::to_string(p) + "]", prims[p]);
    }
    meshes_ = meshes.size();
  }

  void check_primitive(const std::string& wp, const json& prim) {
    if (!prim.contains("attributes") || !prim.at("attributes").is_object()) fail(wp + " has no attributes");
    for (const auto& [key, value] : prim.at("attributes").items()) {
      if (!value.is_number_unsigned() || value.get<std::uint64_t>() >= accessors_.size())
        fail(wp + ".attributes." + key + " is not the index of an accessor");
    }
    const std::uint64_t mode = number(prim, "mode", wp, 4, 6);
    const json& attributes = prim.at("attributes");
    std::uint64_t vertices = 0;
    const bool have_positions = attributes.contains("POSITION");
    if (have_positions) {
      const std::size_t a = attributes.at("POSITION").get<std::size_t>();
      const Accessor& acc = accessors_[a];
      const std::string wa = wp + ".attributes.POSITION (accessors[" + std::to_string(a) + "])";
      if (!quantized_ && (acc.type != "VEC3" || acc.component_type != 5126))
        fail(wa + " is " + acc.type + " of " + component_name(acc.component_type) + ", not VEC3 of FLOAT");
      if (!quantized_) check_position_values(wa, acc);
      vertices = acc.count;
    }
    if (!prim.contains("indices")) return;
    const std::size_t i = index(prim, "indices", wp, accessors_.size(), "accessor");
    const Accessor& acc = accessors_[i];
    const std::string wi = wp + ".indices (accessors[" + std::to_string(i) + "])";
    if (acc.type != "SCALAR" || (acc.component_type != 5121 && acc.component_type != 5123 && acc.component_type != 5125))
      fail(wi + " is " + acc.type + " of " + component_name(acc.component_type) +
           ", not SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    if (mode == 4 && acc.count % 3 != 0)
      fail(wi + " holds " + std::to_string(acc.count) + " indices for triangles, not a multiple of 3");
    if (!have_positions || acc.view < 0) return;
    const View& v = views_[std::size_t(acc.view)];
    const std::uint64_t stride = v.stride ? v.stride : acc.component;
    for (std::uint64_t k = 0; k < acc.count; ++k) {
      const std::uint64_t at = read_unsigned(std::size_t(acc.view), acc.offset + k * stride, acc.component);
      if (at >= vertices)
        fail(wi + " element " + std::to_string(k) + " is " + std::to_string(at) + ", beyond the " + std::to_string(vertices) +
             " vertices of POSITION");
    }
  }

  // Every coordinate finite and, where the accessor declares them (glTF requires them for
  // POSITION), within min and max up to rounding.
  void check_position_values(const std::string& wa, const Accessor& acc) const {
    if (acc.view < 0 || acc.sparse) return;
    double lo[3], hi[3];
    bool bounded = true;
    for (const char* key : {"min", "max"}) {
      const json& o = *acc.object;
      if (!o.contains(key)) {
        bounded = false;
        continue;
      }
      const json& b = o.at(key);
      if (!b.is_array() || b.size() != 3) fail(wa + "." + key + " is not 3 numbers");
      for (int c = 0; c < 3; ++c) {
        if (!b[std::size_t(c)].is_number() || !std::isfinite(b[std::size_t(c)].get<double>()))
          fail(wa + "." + key + "[" + std::to_string(c) + "] is not a finite number");
        (std::string(key) == "min" ? lo : hi)[c] = b[std::size_t(c)].get<double>();
      }
    }
    const View& v = views_[std::size_t(acc.view)];
    const std::uint64_t stride = v.stride ? v.stride : 12;
    double slack[3] = {0, 0, 0};
    if (bounded)
      for (int c = 0; c < 3; ++c) {
        if (lo[c] > hi[c]) fail(wa + " declares min " + std::to_string(lo[c]) + " above max " + std::to_string(hi[c]) + " in axis " + std::to_string(c));
        slack[c] = 1e-5 * std::max({hi[c] - lo[c], std::abs(lo[c]), std::abs(hi[c])}) + 1e-30;
      }
    static const char axis[] = "xyz";
    for (std::uint64_t k = 0; k < acc.count; ++k)
      for (int c = 0; c < 3; ++c) {
        const double x = read_float(std::size_t(acc.view), acc.offset + k * stride + 4 * std::uint64_t(c));
        if (!std::isfinite(x)) fail(wa + " element " + std::to_string(k) + " has a NaN or infinite " + axis[c]);
        if (bounded && (x < lo[c] - slack[c] || x > hi[c] + slack[c]))
          fail(wa + " element " + std::to_string(k) + " has " + axis[c] + " = " + std::to_string(x) + ", outside its declared min " +
               std::to_string(lo[c]) + " and max " + std::to_string(hi[c]) + " (a wrong offset, stride or type reads other bytes)");
      }
  }

  void check_nodes() const {
    const json& nodes = array(doc_, "nodes", "");
    std::vector<int> parent(nodes.size(), -1);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const std::string w = "nodes[" + std::to_string(i) + "]";
      if (nodes[i].contains("mesh")) index(nodes[i], "mesh", w, meshes_, "mesh");
      if (nodes[i].contains("matrix")) {
        const json& mx = nodes[i].at("matrix");
        if (!mx.is_array() || mx.size() != 16) fail(w + ".matrix is not 16 numbers");
        for (const json& x : mx)
          if (!x.is_number()) fail(w + ".matrix holds a non-number");
      }
      if (!nodes[i].contains("children")) continue;
      const json& ch = nodes[i].at("children");
      if (!ch.is_array()) fail(w + ".children is not an array");
      for (const json& k : ch) {
        if (!k.is_number_unsigned() || k.get<std::uint64_t>() >= nodes.size()) fail(w + ".children holds a node index out of range");
        const std::size_t child = k.get<std::size_t>();
        if (child == i) fail(w + " is its own child");
        if (parent[child] >= 0) fail("nodes[" + std::to_string(child) + "] has two parents (a node graph must be a tree)");
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
        if (path.size() > nodes.size()) fail("nodes[" + std::to_string(i) + "] is in a cycle of children");
        at = std::size_t(parent[at]);
      }
      int d = depth[at] < 0 ? 0 : depth[at];
      depth[at] = d;
      for (auto it = path.rbegin(); it != path.rend(); ++it) depth[*it] = ++d;
      if (d > kMaxGltfDepth) fail("nodes are nested " + std::to_string(d) + " deep, more than " + std::to_string(kMaxGltfDepth));
    }
    const json& scenes = array(doc_, "scenes", "");
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      if (!scenes[s].contains("nodes")) continue;
      const json& roots = scenes[s].at("nodes");
      if (!roots.is_array()) fail("scenes[" + std::to_string(s) + "].nodes is not an array");
      for (const json& r : roots)
        if (!r.is_number_unsigned() || r.get<std::uint64_t>() >= nodes.size())
          fail("scenes[" + std::to_string(s) + "].nodes holds a node index out of range");
    }
  }

  const std::string& name_;
  const json& doc_;
  std::string_view bin_;
  const std::function<std::string_view(const std::string&)>& external_;
  std::deque<std::string> decoded_;  // data: URIs, decoded (a deque: views into it stay valid)
  std::vector<std::string_view> buffers_;
  std::vector<View> views_;
  std::vector<Accessor> accessors_;
  std::size_t meshes_ = 0;
  bool quantized_ = false;
};

} // namespace

std::string check_glb(const std::string& name, const std::string& b, std::string_view& bin) {
  bin = {};
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
      bin = std::string_view(b).substr(at + 8, n);
    }  // other chunk types are ignored, as the specification says
    at += 8 + std::size_t(n);
    ++chunk;
    if (chunk > 1024) throw InvalidInput(name + ": more than 1024 GLB chunks");
  }
  if (chunk == 0) throw InvalidInput(name + ": the GLB file has no chunk");
  return text;
}

void check_gltf_json(const std::string& name, const std::string& text, std::string_view bin,
                     const std::function<std::string_view(const std::string& uri)>& external_data) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    throw InvalidInput(name + ": the glTF JSON does not parse (" + std::string(e.what()) + ")");
  }
  if (!doc.is_object()) throw InvalidInput(name + ": the glTF JSON is not an object");
  const json& asset = doc.contains("asset") ? doc.at("asset") : json();
  if (!asset.is_object() || !asset.contains("version") || !asset.at("version").is_string() ||
      asset.at("version").get<std::string>().rfind("2.", 0) != 0)
    throw InvalidInput(name + ": glTF asset.version is missing or not 2.x (only glTF 2.0 is read)");
  GltfChecker(name, doc, bin, external_data).run();
}

} // namespace hb
