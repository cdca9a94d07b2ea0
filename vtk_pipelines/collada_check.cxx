// A Collada file before Assimp opens it (Assimp trusts what it declares: a wrong count crashed
// it, a changed stride shifted the positions without a word, a node instancing itself recursed
// until the stack overflowed):
//  1. every float_array holds the count of finite numbers it declares; every <vertices> has a
//     POSITION input;
//  2. every accessor reads its array whole: offset + count x stride values, a stride that
//     holds its params (a stride or offset changed by one reads every vertex from the wrong
//     place);
//  3. every <polylist> and <triangles> holds its polygons' indices; index lists (<p>,
//     <vcount>, <v>) hold whole numbers below the file's largest array (a non-number or a huge
//     index cost gigabytes);
//  4. the node graph (nesting and <instance_node>) has no cycle, is at most kMaxColladaDepth
//     deep and expands to at most kMaxColladaInstances nodes.
#include "scene_file_checks.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace hb::vtk {

namespace {

constexpr int kMaxColladaDepth = 256;
constexpr std::uint64_t kMaxColladaInstances = 1000000;

class ColladaChecker {
public:
  ColladaChecker(const std::string& path, const std::string& xml) : path_(path), xml_(xml) {}

  void run() {
    check_arrays();
    check_vertices();
    check_accessors();
    check_polygons();
    check_index_lists();
    check_nodes();
  }

private:
  static std::string attribute(const std::string& tag, const char* name) {
    const std::string key = std::string(" ") + name + "=\"";
    const std::size_t at = tag.find(key);
    if (at == std::string::npos) return {};
    const std::size_t end = tag.find('"', at + key.size());
    return end == std::string::npos ? std::string() : tag.substr(at + key.size(), end - at - key.size());
  }
  // The opening tag at `at` (up to its '>').
  std::string tag_at(std::size_t at) const {
    const std::size_t end = xml_.find('>', at);
    return xml_.substr(at, end == std::string::npos ? std::string::npos : end - at);
  }
  std::uint64_t whole(const std::string& text, const std::string& what) const {
    if (text.empty() || text.size() > 12 || text.find_first_not_of("0123456789") != std::string::npos)
      fail("Collada " + what + " is '" + quoted_text(text) + "', not a whole number");
    return std::stoull(text);
  }
  [[noreturn]] void fail(const std::string& what) const { throw InvalidInput(path_ + ": " + what); }

  void check_arrays() {
    for (std::size_t at = xml_.find("<float_array"); at != std::string::npos; at = xml_.find("<float_array", at + 1)) {
      const std::size_t open_end = xml_.find('>', at);
      const std::size_t close = xml_.find("</float_array>", at);
      if (open_end == std::string::npos || close == std::string::npos || close < open_end) fail("a Collada float_array is not closed");
      const std::string tag = xml_.substr(at, open_end - at);
      const std::string id = quoted_text(attribute(tag, "id"), 60);
      const std::uint64_t count = whole(attribute(tag, "count"), "float_array count");
      std::uint64_t n = 0;
      const char* p = xml_.data() + open_end + 1;
      const char* end = xml_.data() + close;
      while (p < end) {
        while (p < end && std::isspace((unsigned char)*p)) ++p;
        if (p >= end) break;
        char* stop = nullptr;
        const double v = std::strtod(p, &stop);
        if (stop == p || stop > end || !std::isfinite(v) || (stop < end && !std::isspace((unsigned char)*stop)))
          fail("Collada float_array " + id + " holds a value that is not a finite number");
        p = stop;
        ++n;
      }
      if (n != count) fail("Collada float_array " + id + " declares " + std::to_string(count) + " values and holds " + std::to_string(n));
      arrays_[attribute(tag, "id")] = count;
      largest_ = std::max(largest_, count);
    }
  }

  // Every <vertices> has a POSITION input (without it Assimp sized its positions from garbage:
  // "vector::_M_fill_insert").
  void check_vertices() const {
    for (std::size_t at = xml_.find("<vertices"); at != std::string::npos; at = xml_.find("<vertices", at + 1)) {
      const std::size_t close = xml_.find("</vertices>", at);
      if (close == std::string::npos) fail("a Collada <vertices> is not closed");
      const std::string body = xml_.substr(at, close - at);
      bool position = false;
      for (std::size_t i = body.find("<input"); i != std::string::npos && !position; i = body.find("<input", i + 1))
        position = attribute(body.substr(i, body.find('>', i) - i), "semantic") == "POSITION";
      if (!position) fail("Collada <vertices id=\"" + quoted_text(attribute(tag_at(at), "id"), 60) + "\"> has no POSITION input");
    }
  }

  // An accessor reads offset + count x stride values of its array, stride at least its params:
  // exactly the array (every exporter writes it so), so a changed stride, offset or count is a
  // disagreement, not another mesh.
  void check_accessors() const {
    for (std::size_t at = xml_.find("<accessor"); at != std::string::npos; at = xml_.find("<accessor", at + 1)) {
      const std::string tag = tag_at(at);
      const std::uint64_t count = whole(attribute(tag, "count"), "accessor count");
      const std::string stride_text = attribute(tag, "stride"), offset_text = attribute(tag, "offset");
      const std::uint64_t stride = stride_text.empty() ? 1 : whole(stride_text, "accessor stride");
      const std::uint64_t offset = offset_text.empty() ? 0 : whole(offset_text, "accessor offset");
      std::string source = attribute(tag, "source");
      if (!source.empty() && source[0] == '#') source.erase(0, 1);
      const std::string name = quoted_text(source, 60);
      if (stride == 0) fail("Collada accessor of " + name + " has a stride of 0");
      // Its params: the <param> tags before </accessor>.
      const std::size_t close = xml_.find("</accessor>", at);
      std::uint64_t params = 0;
      if (close != std::string::npos && tag.back() != '/')
        for (std::size_t q = xml_.find("<param", at); q != std::string::npos && q < close; q = xml_.find("<param", q + 1)) ++params;
      if (params > stride)
        fail("Collada accessor of " + name + " names " + std::to_string(params) + " params but has a stride of " + std::to_string(stride));
      const auto it = arrays_.find(source);
      if (it == arrays_.end()) continue;
      if (offset + count * stride != it->second)
        fail("Collada accessor of " + name + " reads " + std::to_string(count) + " x " + std::to_string(stride) + " values from offset " +
             std::to_string(offset) + " of an array of " + std::to_string(it->second) +
             (offset + count * stride > it->second ? " (past its end)" : " (leaving values unread: a changed stride, offset or count)"));
    }
  }

  // Each <polylist> (and <triangles>) holds its count of polygons: one <vcount> of `count`
  // sizes and one <p> of sum(vcount) x inputs indices (a polylist without its vcount crashed
  // Assimp).
  void check_polygons() const {
    for (const char* kind : {"polylist", "triangles"}) {
      const std::string open = std::string("<") + kind, close = std::string("</") + kind + ">";
      for (std::size_t at = xml_.find(open); at != std::string::npos; at = xml_.find(open, at + 1)) {
        if (at + open.size() < xml_.size() && !std::isspace((unsigned char)xml_[at + open.size()]) && xml_[at + open.size()] != '>') continue;
        const std::size_t end = xml_.find(close, at);
        if (end == std::string::npos) fail("a Collada <" + std::string(kind) + "> is not closed");
        check_polygon_list(kind, xml_.substr(at, end - at));
      }
    }
  }

  void check_polygon_list(const std::string& kind, const std::string& body) const {
    const std::uint64_t count = whole(attribute(body.substr(0, body.find('>')), "count"), kind + " count");
    std::uint64_t stride = 0;
    for (std::size_t i = body.find("<input"); i != std::string::npos; i = body.find("<input", i + 1)) {
      const std::string offset = attribute(body.substr(i, body.find('>', i) - i), "offset");
      stride = std::max(stride, (offset.empty() ? 0 : whole(offset, "input offset")) + 1);
    }
    auto numbers_in = [&](const std::string& tag) -> std::vector<std::uint64_t> {
      const std::size_t first = body.find("<" + tag + ">");
      if (first == std::string::npos) return {};
      if (body.find("<" + tag + ">", first + 1) != std::string::npos) fail("a Collada <" + kind + "> holds two <" + tag + "> lists");
      const std::size_t last = body.find("</" + tag + ">", first);
      std::istringstream words(body.substr(first + tag.size() + 2, last == std::string::npos ? std::string::npos : last - first - tag.size() - 2));
      std::vector<std::uint64_t> v;
      for (std::string w; words >> w;) v.push_back(whole(w, "index in <" + tag + ">"));
      return v;
    };
    std::uint64_t corners = 3 * count;
    if (kind == "polylist") {
      const std::vector<std::uint64_t> vcount = numbers_in("vcount");
      if (vcount.size() != count)
        fail("a Collada <polylist> of " + std::to_string(count) + " polygons has " + std::to_string(vcount.size()) + " sizes in its <vcount>");
      corners = 0;
      for (std::uint64_t n : vcount) corners += n;
    }
    const std::size_t p_count = numbers_in("p").size();
    if (p_count != corners * std::max<std::uint64_t>(stride, 1))
      fail("a Collada <" + kind + "> of " + std::to_string(count) + " polygons (" + std::to_string(corners) + " corners x " +
           std::to_string(stride) + " inputs) holds " + std::to_string(p_count) + " indices in its <p>");
  }

  void check_index_lists() const {
    for (const char* list : {"<p>", "<vcount>", "<v>"}) {
      const std::string close = std::string("</") + (list + 1);
      for (std::size_t at = xml_.find(list); at != std::string::npos; at = xml_.find(list, at + 1)) {
        const std::size_t end = xml_.find(close, at);
        if (end == std::string::npos) fail("a Collada " + std::string(list) + " list is not closed");
        std::istringstream words(xml_.substr(at + std::strlen(list), end - at - std::strlen(list)));
        for (std::string w; words >> w;)
          if (whole(w, std::string("index in ") + list) > largest_)
            fail("Collada index " + w + " in a " + list + " list is beyond every array of the file");
      }
    }
  }

  // The node graph: an edge from each node to the nodes nested in it and to those it
  // instances (<instance_node url="#id">). No cycle, bounded depth and expansion.
  void check_nodes() const {
    std::vector<std::string> names;            // node index -> its id (or its position)
    std::map<std::string, std::size_t> by_id;  // id -> node index
    std::vector<std::vector<std::size_t>> nested;
    std::vector<std::vector<std::string>> instanced;
    std::vector<std::size_t> open;  // the nodes enclosing the parse position
    for (std::size_t at = xml_.find('<'); at != std::string::npos; at = xml_.find('<', at + 1)) {
      const bool node = xml_.compare(at, 5, "<node") == 0 && at + 5 < xml_.size() &&
                        (std::isspace((unsigned char)xml_[at + 5]) || xml_[at + 5] == '>' || xml_[at + 5] == '/');
      if (node) {
        const std::string tag = tag_at(at);
        const std::string id = attribute(tag, "id");
        const std::size_t n = names.size();
        names.push_back(id.empty() ? "at byte " + std::to_string(at) : quoted_text(id, 60));
        if (!id.empty()) by_id.emplace(id, n);
        nested.emplace_back();
        instanced.emplace_back();
        if (!open.empty()) nested[open.back()].push_back(n);
        if (tag.empty() || tag.back() != '/') open.push_back(n);
        if (open.size() > std::size_t(kMaxColladaDepth))
          fail("Collada nodes are nested more than " + std::to_string(kMaxColladaDepth) + " deep (node " + names[n] + ")");
      } else if (xml_.compare(at, 7, "</node>") == 0) {
        if (!open.empty()) open.pop_back();
      } else if (xml_.compare(at, 14, "<instance_node") == 0 && !open.empty()) {
        std::string url = attribute(tag_at(at), "url");
        if (!url.empty() && url[0] == '#') url.erase(0, 1);
        instanced[open.back()].push_back(url);
      }
    }
    std::vector<std::vector<std::size_t>> edges = nested;
    for (std::size_t n = 0; n < names.size(); ++n)
      for (const std::string& url : instanced[n])
        if (const auto it = by_id.find(url); it != by_id.end()) edges[n].push_back(it->second);
    walk_nodes(names, edges);
  }

  // Depth-first over the node graph (iterative: a file chooses the depth): a cycle, the depth
  // and the number of node instances the graph expands to.
  void walk_nodes(const std::vector<std::string>& names, const std::vector<std::vector<std::size_t>>& edges) const {
    const std::size_t n = names.size();
    std::vector<int> state(n, 0);          // 1: on the path, 2: done
    std::vector<std::uint64_t> depth(n, 1), instances(n, 1);
    for (std::size_t root = 0; root < n; ++root) {
      if (state[root]) continue;
      std::vector<std::pair<std::size_t, std::size_t>> stack{{root, 0}};
      state[root] = 1;
      while (!stack.empty()) {
        auto& [node, next] = stack.back();
        if (next < edges[node].size()) {
          const std::size_t child = edges[node][next++];
          if (state[child] == 1) fail("Collada node " + names[child] + " contains itself (through nesting or <instance_node>)");
          if (state[child] == 0) {
            state[child] = 1;
            stack.emplace_back(child, 0);
          }
          continue;
        }
        for (std::size_t child : edges[node]) {
          depth[node] = std::max(depth[node], depth[child] + 1);
          instances[node] = std::min(kMaxColladaInstances + 1, instances[node] + instances[child]);
        }
        if (depth[node] > std::uint64_t(kMaxColladaDepth))
          fail("Collada node " + names[node] + " reaches " + std::to_string(kMaxColladaDepth) + " levels of nodes through <instance_node>");
        if (instances[node] > kMaxColladaInstances)
          fail("Collada node " + names[node] + " expands to more than " + std::to_string(kMaxColladaInstances) +
               " node instances through <instance_node>");
        state[node] = 2;
        stack.pop_back();
      }
    }
  }

  const std::string& path_;
  const std::string& xml_;
  std::map<std::string, std::uint64_t> arrays_;  // id -> values
  std::uint64_t largest_ = 0;
};

} // namespace

void check_collada(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ColladaChecker(path, xml).run();
}

} // namespace hb::vtk
