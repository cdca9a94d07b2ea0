// A VTK XML PolyData file held to its header before VTK's reader sees it (the reader trusts
// the header: a count that disagreed with an array crashed it, a damaged block header had it
// allocate gigabytes, a cell naming a point past the end crashed what read the cells):
//  1. the XML: each section once, each array once in its section, Points one array, each cell
//     section (Verts, Lines, Polys, Strips) a connectivity and an offsets array;
//  2. every array's data: appended raw (its byte count, or compressed blocks that inflate to
//     their sizes, within the file) or inline ascii (numbers only), as long as the piece's
//     NumberOfPoints and cell counts make it;
//  3. the cells: offsets of an integer type, one per cell, never decreasing, the last the
//     connectivity's length; connectivity of an integer type naming points of the piece.
// Base64 and big-endian files are left to VTK (in its child process).
#include "polydata_files.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <zlib.h>
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <vector>

namespace hb::vtk {

namespace {

std::string vtp_attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return {};
  const std::size_t end = tag.find('"', at + key.size());
  return end == std::string::npos ? std::string() : tag.substr(at + key.size(), end - at - key.size());
}

unsigned vtp_type_size(const std::string& t) {
  if (t == "Int8" || t == "UInt8" || t == "Char") return 1;
  if (t == "Int16" || t == "UInt16") return 2;
  if (t == "Int32" || t == "UInt32" || t == "Float32") return 4;
  if (t == "Int64" || t == "UInt64" || t == "Float64") return 8;
  return 0;  // String and others: not checked against a count
}

bool integer_type(const std::string& t) { return t.find("Int") != std::string::npos; }

class VtpCheck {
public:
  VtpCheck(const std::string& path, const std::string& bytes) : path_(path), bytes_(bytes) {}

  void run() {
    const std::size_t appended = bytes_.find("<AppendedData");
    header_ = bytes_.substr(0, appended);
    if (appended != std::string::npos && !locate_appended(appended)) return;
    const std::size_t vtkfile = header_.find("<VTKFile");
    if (vtkfile == std::string::npos) fail("not a VTK XML file (no VTKFile element)");
    const std::string root = header_.substr(vtkfile, header_.find('>', vtkfile) - vtkfile);
    if (vtp_attribute(root, "byte_order") == "BigEndian") return;  // left to VTK (never written here)
    const std::string header_type = vtp_attribute(root, "header_type");
    if (!header_type.empty() && header_type != "UInt32" && header_type != "UInt64")
      fail("header_type \"" + quoted_text(header_type) + "\" is not UInt32 or UInt64");
    h_ = header_type == "UInt64" ? 8 : 4;
    compressed_ = !vtp_attribute(root, "compressor").empty();
    walk_tags();
  }

private:
  [[noreturn]] void fail(const std::string& why) const { throw InvalidInput(path_ + ": " + why); }

  // The '_' that starts raw appended data; false for base64 (left to VTK).
  bool locate_appended(std::size_t appended) {
    const std::size_t appended_end = bytes_.find('>', appended);
    if (appended_end == std::string::npos) fail("the AppendedData element is not closed");
    if (vtp_attribute(bytes_.substr(appended, appended_end - appended), "encoding") != "raw") return false;
    const std::size_t underscore = bytes_.find('_', appended);
    if (underscore == std::string::npos) fail("the AppendedData section has no '_' before its data");
    if (bytes_.find_first_not_of(" \t\r\n", appended_end + 1) != underscore)
      fail("something other than white space between the AppendedData tag and its '_' (a damaged or repeated tag)");
    data_ = underscore + 1;
    return true;
  }

  std::uint64_t count(const std::string& tag, const std::string& name) const {
    const std::string v = vtp_attribute(tag, name);
    if (v.empty()) return 0;
    if (v.size() > 15 || v.find_first_not_of("0123456789") != std::string::npos)
      fail(name + "=\"" + quoted_text(v) + "\" is not a count");
    return std::stoull(v);
  }

  std::uint64_t word(std::uint64_t at) const {
    if (at + h_ > bytes_.size()) fail("an array header at byte " + std::to_string(at) + " runs past the end of the file");
    std::uint64_t v = 0;
    std::memcpy(&v, bytes_.data() + at, h_);  // little endian, as this machine
    return v;
  }

  void walk_tags() {
    for (std::size_t at = header_.find('<'); at != std::string::npos; at = header_.find('<', at + 1)) {
      const std::size_t end = header_.find('>', at);
      if (end == std::string::npos) break;
      const std::string tag = header_.substr(at, end - at);
      const std::string name = tag.substr(1, tag.find_first_of(" />\n\t", 2) - 1);  // "/Points" for a closing tag
      if (name == "Piece") {
        points_ = count(tag, "NumberOfPoints");
        for (const char* kind : {"Verts", "Lines", "Strips", "Polys"}) cells_of_[kind] = count(tag, std::string("NumberOfPolys").replace(8, 5, kind));
        cells_ = cells_of_["Verts"] + cells_of_["Lines"] + cells_of_["Strips"] + cells_of_["Polys"];
      } else if (name == "PointData" || name == "CellData" || name == "Points" || name == "Polys" || name == "Verts" ||
                 name == "Lines" || name == "Strips" || name == "FieldData") {
        if (arrays_of_.count(name) && name != "FieldData") fail("the " + name + " section appears twice");
        arrays_of_[name];
        section_ = name;
        // A section closed where it opens holds nothing: the piece must have nothing of it.
        if (tag.back() == '/' && ((name == "Points" && points_ > 0) || cells_of_[name] > 0))
          fail("the " + name + " section is empty but the piece declares " + std::to_string(name == "Points" ? points_ : cells_of_[name]) +
               (name == "Points" ? " points" : " cells of it"));
      } else if (name == "/Points" || name == "/Polys" || name == "/Verts" || name == "/Lines" || name == "/Strips") {
        end_section(name.substr(1));
      }
      if (name != "DataArray" && name != "Array") continue;
      if (section_ != "FieldData" && !arrays_of_[section_].insert(vtp_attribute(tag, "Name")).second)
        fail("array " + quoted_text(vtp_attribute(tag, "Name"), 60) + " appears twice in the " + section_ + " section");
      check_array(tag, end);
    }
  }

  // A section's arrays once it closes; a cell section's cells.
  void end_section(const std::string& name) {
    const std::set<std::string>& a = arrays_of_[name];
    if (name == "Points" && a.size() != 1) fail("the Points section holds " + std::to_string(a.size()) + " arrays, not 1");
    if (name == "Points") return;
    if (a.size() != 2 || !a.count("connectivity") || !a.count("offsets"))
      fail("the " + name + " section does not hold exactly a connectivity and an offsets array");
    const auto& offsets = values_[name + "/offsets"];
    const auto& connectivity = values_[name + "/connectivity"];
    if (!decoded_[name + "/offsets"] || !decoded_[name + "/connectivity"]) return;  // base64 or a type not read here
    const std::uint64_t cells = cells_of_[name];
    if (offsets.size() != cells)
      fail("the " + name + " offsets hold " + std::to_string(offsets.size()) + " values for the piece's " + std::to_string(cells) + " cells");
    std::int64_t last = 0;
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      if (offsets[i] < last)
        fail("the " + name + " offsets decrease at cell " + std::to_string(i) + " (" + std::to_string(offsets[i]) + " after " + std::to_string(last) + ")");
      last = offsets[i];
    }
    if (std::uint64_t(last) != connectivity.size())
      fail("the " + name + " offsets end at " + std::to_string(last) + " but the connectivity holds " + std::to_string(connectivity.size()) + " values");
    for (std::size_t i = 0; i < connectivity.size(); ++i)
      if (connectivity[i] < 0 || std::uint64_t(connectivity[i]) >= points_)
        fail("the " + name + " connectivity names point " + std::to_string(connectivity[i]) + " (value " + std::to_string(i) + ") of the piece's " +
             std::to_string(points_));
  }

  void check_array(const std::string& tag, std::size_t tag_end) {
    const std::string array = quoted_text(vtp_attribute(tag, "Name"), 60), type = vtp_attribute(tag, "type");
    const std::string format = vtp_attribute(tag, "format");
    const bool cells = section_ == "Polys" || section_ == "Verts" || section_ == "Lines" || section_ == "Strips";
    if (cells && !integer_type(type)) fail("the " + section_ + " array " + array + " is of type " + quoted_text(type) + ", not an integer type");
    std::string raw_bytes;  // the decoded bytes (binary formats)
    std::vector<std::int64_t>* keep = cells ? &values_[section_ + "/" + vtp_attribute(tag, "Name")] : nullptr;
    std::uint64_t raw = 0;
    const unsigned size = vtp_type_size(type);
    if (format == "appended") {
      if (data_ == 0) return;  // base64 appended data: left to VTK
      raw = appended_array(tag, array, keep ? &raw_bytes : nullptr);
    } else if (format == "ascii") {
      raw = ascii_array(tag_end, array, keep) * size;
      if (keep) decoded_[section_ + "/" + vtp_attribute(tag, "Name")] = true;
    } else {
      return;  // binary (base64 inline): left to VTK
    }
    if (keep && format == "appended" && size > 0) {
      keep->resize(raw_bytes.size() / size);
      for (std::size_t i = 0; i < keep->size(); ++i) (*keep)[i] = integer_at(raw_bytes.data() + i * size, type);
      decoded_[section_ + "/" + vtp_attribute(tag, "Name")] = true;
    }
    const std::string components_text = vtp_attribute(tag, "NumberOfComponents");
    const std::uint64_t components = components_text.empty() ? 1 : count(tag, "NumberOfComponents");
    std::uint64_t tuples = 0;
    if (section_ == "Points" || section_ == "PointData") tuples = points_;
    else if (section_ == "CellData") tuples = cells_;
    else return;  // connectivity and offsets: their lengths follow from the data (end_section)
    if (size > 0 && raw != tuples * components * size)
      fail("array " + array + " holds " + std::to_string(raw) + " bytes, the piece's " + std::to_string(tuples) +
           (section_ == "CellData" ? " cells" : " points") + " need " + std::to_string(tuples * components * size) +
           ": the counts disagree with the arrays");
  }

  static std::int64_t integer_at(const char* p, const std::string& type) {
    auto get = [&](auto v) {
      std::memcpy(&v, p, sizeof v);
      return v;
    };
    if (type == "Int8") return get(std::int8_t());
    if (type == "UInt8") return get(std::uint8_t());
    if (type == "Int16") return get(std::int16_t());
    if (type == "UInt16") return get(std::uint16_t());
    if (type == "Int32") return get(std::int32_t());
    if (type == "UInt32") return get(std::uint32_t());
    if (type == "Int64") return get(std::int64_t());
    const std::uint64_t u = get(std::uint64_t());
    return u > std::uint64_t(INT64_MAX) ? -1 : std::int64_t(u);
  }

  // An inline ascii array's values (numbers only); integers kept in `keep`. Returns the count.
  std::uint64_t ascii_array(std::size_t tag_end, const std::string& array, std::vector<std::int64_t>* keep) const {
    if (header_[tag_end - 1] == '/') return 0;
    const std::size_t close = header_.find("</DataArray>", tag_end);
    if (close == std::string::npos) fail("the array " + array + " is not closed");
    const char* p = header_.data() + tag_end + 1;
    const char* end = header_.data() + close;
    std::uint64_t n = 0;
    while (p < end) {
      while (p < end && std::isspace((unsigned char)*p)) ++p;
      if (p >= end) break;
      char* stop = nullptr;
      const double v = std::strtod(p, &stop);
      if (stop == p || stop > end || (stop < end && !std::isspace((unsigned char)*stop)))
        fail("the ascii array " + array + " holds '" + quoted_text(std::string(p, std::size_t(std::find_if(p, end, [](char c) { return std::isspace((unsigned char)c); }) - p))) +
             "', not a number");
      if (keep) keep->push_back(v == double(std::int64_t(v)) ? std::int64_t(v) : -1);
      p = stop;
      ++n;
    }
    return n;
  }

  // An appended array's decoded bytes (counted; kept in `keep` when asked).
  std::uint64_t appended_array(const std::string& tag, const std::string& array, std::string* keep) const {
    const std::uint64_t offset = count(tag, "offset");
    const std::uint64_t at_data = data_ + offset;
    if (at_data >= bytes_.size())
      fail("array " + array + " starts at offset " + std::to_string(offset) + ", past the end of the file");
    if (!compressed_) {
      const std::uint64_t raw = word(at_data);
      if (at_data + h_ + raw > bytes_.size())
        fail("array " + array + " claims " + std::to_string(raw) + " bytes, past the end of the file");
      if (keep) keep->assign(bytes_, std::size_t(at_data + h_), std::size_t(raw));
      return raw;
    }
    const std::uint64_t blocks = word(at_data), block = word(at_data + h_), last = word(at_data + 2 * h_);
    if (blocks > (bytes_.size() - at_data) / h_)
      fail("array " + array + " claims " + std::to_string(blocks) + " compressed blocks, more than the file holds");
    std::uint64_t packed = 0;
    for (std::uint64_t b = 0; b < blocks; ++b) packed += word(at_data + (3 + b) * h_);
    if (at_data + (3 + blocks) * h_ + packed > bytes_.size())
      fail("array " + array + " claims " + std::to_string(packed) + " compressed bytes, past the end of the file");
    if (blocks > 0 && (block == 0 || last > block)) fail("array " + array + " has a damaged block header");
    const std::uint64_t raw = blocks == 0 ? 0 : (blocks - 1) * block + (last ? last : block);
    if (raw > 1100 * packed + 1024)
      fail("array " + array + " claims " + std::to_string(raw) + " bytes from " + std::to_string(packed) +
           " compressed: beyond deflate's reach (a damaged header)");
    // Every block inflates to exactly its size: VTK's reader went on after a zlib error with
    // whatever it had (a connectivity of garbage crashed it).
    std::uint64_t from = at_data + (3 + blocks) * h_;
    std::vector<unsigned char> out(std::size_t(std::min<std::uint64_t>(block, raw)) + 1);
    for (std::uint64_t b = 0; b < blocks; ++b) {
      const std::uint64_t size = b + 1 == blocks && last ? last : block, in = word(at_data + (3 + b) * h_);
      uLongf got = uLongf(out.size());
      const int r = uncompress(out.data(), &got, reinterpret_cast<const Bytef*>(bytes_.data() + from), uLong(in));
      if (r != Z_OK || got != size)
        fail("array " + array + ": compressed block " + std::to_string(b) + " of " + std::to_string(blocks) +
             (r != Z_OK ? " does not inflate (damaged data)" : " inflates to " + std::to_string(got) + " bytes, not " + std::to_string(size)));
      if (keep) keep->append(reinterpret_cast<const char*>(out.data()), std::size_t(got));
      from += in;
    }
    return raw;
  }

  const std::string& path_;
  const std::string& bytes_;
  std::string header_;
  std::size_t data_ = 0;  // where raw appended data starts (0: none)
  unsigned h_ = 4;
  bool compressed_ = false;
  std::uint64_t points_ = 0, cells_ = 0;
  std::map<std::string, std::uint64_t> cells_of_;
  std::string section_;
  // Each section's arrays once by name; Points holds one, each cell section connectivity and
  // offsets (a repeated array line crashed VTK's reader).
  std::map<std::string, std::set<std::string>> arrays_of_;
  std::map<std::string, std::vector<std::int64_t>> values_;  // "Polys/offsets" -> values
  std::map<std::string, bool> decoded_;
};

} // namespace

void check_vtp_appended_data(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the file");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  VtpCheck(path, bytes).run();
}

} // namespace hb::vtk
