// Volume headers checked field by field (see volume_headers.h). Each parser reads only what
// the format defines, refuses what a reader library would misread (a size beyond the data, an
// element type it would guess, a data-file pattern that never ends), and returns where the
// voxels are so that the caller can hold the data to the header.
#include "formats/volume_headers.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>

namespace hb {

namespace {

constexpr std::uint64_t kMaxAxis = std::uint64_t(1) << 31;
constexpr std::uint64_t kMaxDataFiles = 65536;

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower((unsigned char)c));
  return s;
}

std::string trim(std::string s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const std::size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

// A whole number written in full: an optional sign, at most 15 digits (so differences of two
// never overflow), no trailing text. Anything else is not a number here (the caller names it).
bool parse_integer(const std::string& w, long long& out) {
  const std::size_t i = (!w.empty() && (w[0] == '-' || w[0] == '+')) ? 1 : 0;
  if (i == w.size() || w.size() - i > 15) return false;
  for (std::size_t k = i; k < w.size(); ++k)
    if (!std::isdigit((unsigned char)w[k])) return false;
  long long v = 0;
  for (std::size_t k = i; k < w.size(); ++k) v = v * 10 + (w[k] - '0');
  out = w[0] == '-' ? -v : v;
  return true;
}

std::string quoted(const std::string& s) { return "'" + quoted_text(s, 80) + "'"; }

// Sizes: each a whole number from 1 to 2^31, the product at most 2^40 (a terabyte of voxels
// is beyond any reader; the caller's own voxel limit is lower).
std::uint64_t product(const std::string& name, const std::vector<std::uint64_t>& sizes) {
  std::uint64_t n = 1;
  for (std::uint64_t s : sizes) {
    if (s > (std::uint64_t(1) << 40) / n) {
      std::string list;
      for (std::uint64_t x : sizes) list += (list.empty() ? "" : " x ") + std::to_string(x);
      throw InvalidInput(name + ": the header claims " + list + " voxels, more than 2^40: refused before reading");
    }
    n *= s;
  }
  return n;
}

std::vector<std::uint64_t> parse_sizes(const std::string& name, const std::string& field, const std::string& value,
                                       std::size_t count) {
  const std::vector<std::string> w = words(value);
  if (w.size() != count)
    throw InvalidInput(name + ": " + field + " must hold " + std::to_string(count) + " sizes, not " + quoted(value));
  std::vector<std::uint64_t> out;
  for (const std::string& x : w) {
    long long v = 0;
    if (!parse_integer(x, v) || v < 1 || std::uint64_t(v) > kMaxAxis)
      throw InvalidInput(name + ": " + field + " holds " + quoted(x) + ": each size must be a whole number from 1 to 2^31");
    out.push_back(std::uint64_t(v));
  }
  product(name, out);
  return out;
}

// "fmt first last step": printf-style file names with one integer conversion.
std::vector<std::string> expand_pattern(const std::string& name, const std::string& field, const std::string& fmt,
                                        const std::vector<std::string>& numbers) {
  long long first = 0, last = 0, step = 0;
  if (numbers.size() < 3 || !parse_integer(numbers[0], first) || !parse_integer(numbers[1], last) ||
      !parse_integer(numbers[2], step))
    throw InvalidInput(name + ": " + field + " pattern " + quoted(fmt) + " needs whole numbers: first last step");
  if (step == 0) throw InvalidInput(name + ": " + field + " pattern " + quoted(fmt) + " has step 0 (it would never end)");
  if ((last - first) / step < 0 || (last - first) % step != 0)
    throw InvalidInput(name + ": " + field + " pattern goes from " + std::to_string(first) + " to " + std::to_string(last) +
                       " by " + std::to_string(step) + ": the step never reaches the last number");
  const std::uint64_t count = std::uint64_t((last - first) / step) + 1;
  if (count > kMaxDataFiles)
    throw InvalidInput(name + ": " + field + " pattern names " + std::to_string(count) + " files, more than " +
                       std::to_string(kMaxDataFiles));
  // Exactly one conversion %[0][width]d, width at most 9, and no other '%' but "%%".
  int conversions = 0;
  for (std::size_t i = 0; i < fmt.size(); ++i) {
    if (fmt[i] != '%') continue;
    if (i + 1 < fmt.size() && fmt[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < fmt.size() && std::isdigit((unsigned char)fmt[j]) && j - i <= 2) ++j;
    if (j >= fmt.size() || (fmt[j] != 'd' && fmt[j] != 'i' && fmt[j] != 'u')) {
      throw InvalidInput(name + ": " + field + " pattern " + quoted(fmt) + " must hold one integer conversion such as %03d");
    }
    ++conversions;
    i = j;
  }
  if (conversions != 1)
    throw InvalidInput(name + ": " + field + " pattern " + quoted(fmt) + " must hold exactly one integer conversion such as %03d");
  std::vector<std::string> files;
  for (std::uint64_t k = 0; k < count; ++k) {
    char buffer[4096];
    const int n = std::snprintf(buffer, sizeof buffer, fmt.c_str(), int(first + (long long)k * step));
    if (n < 0 || std::size_t(n) >= sizeof buffer) throw InvalidInput(name + ": " + field + " pattern gives a file name that is too long");
    files.emplace_back(buffer);
  }
  return files;
}

// Reads lines of a text header: returns the offset just past the header's last line.
struct HeaderLine {
  std::string key, value;
  std::size_t end = 0;  // offset after the line's '\n'
  int number = 0;
};

void check_text_line(const std::string& name, const std::string& line, int number) {
  for (char c : line)
    if ((unsigned char)c < 0x20 && c != '\t' && c != '\r')
      throw InvalidInput(name + ": line " + std::to_string(number) + " of the header is not text (byte " +
                         std::to_string(int((unsigned char)c)) + "): a damaged header or the data began early");
}

} // namespace

std::uint64_t VolumeLayout::voxels() const { return sizes[0] * sizes[1] * sizes[2] * sizes[3]; }
std::uint64_t VolumeLayout::expected_bytes() const { return voxels() * components * bytes_per_element; }

// ---------------------------------------------------------------------------------------------
// NIfTI

namespace {

template <class T> T read_at(const std::string& h, std::size_t at, bool swap) {
  T v;
  unsigned char b[sizeof(T)];
  std::memcpy(b, h.data() + at, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  std::memcpy(&v, b, sizeof(T));
  return v;
}

unsigned nifti_bytes(int datatype, const char*& type_name) {
  switch (datatype) {
    case 2: type_name = "uint8"; return 1;
    case 4: type_name = "int16"; return 2;
    case 8: type_name = "int32"; return 4;
    case 16: type_name = "float32"; return 4;
    case 64: type_name = "float64"; return 8;
    case 256: type_name = "int8"; return 1;
    case 512: type_name = "uint16"; return 2;
    case 768: type_name = "uint32"; return 4;
    case 1024: type_name = "int64"; return 8;
    case 1280: type_name = "uint64"; return 8;
    case 32: type_name = "complex64"; return 0;
    case 128: type_name = "RGB24"; return 0;
    case 1536: type_name = "float128"; return 0;
    case 1792: type_name = "complex128"; return 0;
    case 2048: type_name = "complex256"; return 0;
    case 2304: type_name = "RGBA32"; return 0;
    default: type_name = nullptr; return 0;
  }
}

} // namespace

VolumeLayout check_nifti_header(const std::string& name, const std::string& h) {
  if (h.size() < 348) throw InvalidInput(name + ": " + std::to_string(h.size()) + " bytes, shorter than a NIfTI header (348 bytes)");
  const std::int32_t size_native = read_at<std::int32_t>(h, 0, false);
  const std::int32_t size_swapped = read_at<std::int32_t>(h, 0, true);
  bool swap = false;
  int version = 0;
  if (size_native == 348 || size_native == 540) version = size_native == 348 ? 1 : 2;
  else if (size_swapped == 348 || size_swapped == 540) version = size_swapped == 348 ? 1 : 2, swap = true;
  else
    throw InvalidInput(name + ": not a NIfTI file (the header size field is " + std::to_string(size_native) +
                       ", not 348 or 540)");
  if (version == 2 && h.size() < 540) throw InvalidInput(name + ": the NIfTI-2 header is cut short (" + std::to_string(h.size()) + " of 540 bytes)");
  const std::string magic = version == 1 ? h.substr(344, 4) : h.substr(4, 8);
  bool single = false;
  if (version == 1) {
    if (magic == std::string("n+1\0", 4)) single = true;
    else if (magic != std::string("ni1\0", 4))
      throw InvalidInput(name + ": NIfTI magic is " + quoted(magic) + ", not \"n+1\" (single file) or \"ni1\" (header and image)");
  } else {
    if (magic.compare(0, 4, std::string("n+2\0", 4)) == 0) single = true;
    else if (magic.compare(0, 4, std::string("ni2\0", 4)) != 0)
      throw InvalidInput(name + ": NIfTI-2 magic is " + quoted(magic.substr(0, 4)) + ", not \"n+2\" or \"ni2\"");
  }
  std::int64_t dim[8];
  int datatype, bitpix;
  double pixdim[8], vox_offset, scl_slope, scl_inter;
  if (version == 1) {
    for (int i = 0; i < 8; ++i) dim[i] = read_at<std::int16_t>(h, std::size_t(40 + 2 * i), swap);
    datatype = read_at<std::int16_t>(h, 70, swap);
    bitpix = read_at<std::int16_t>(h, 72, swap);
    for (int i = 0; i < 8; ++i) pixdim[i] = read_at<float>(h, std::size_t(76 + 4 * i), swap);
    vox_offset = read_at<float>(h, 108, swap);
    scl_slope = read_at<float>(h, 112, swap);
    scl_inter = read_at<float>(h, 116, swap);
  } else {
    datatype = read_at<std::int16_t>(h, 12, swap);
    bitpix = read_at<std::int16_t>(h, 14, swap);
    for (int i = 0; i < 8; ++i) dim[i] = read_at<std::int64_t>(h, std::size_t(16 + 8 * i), swap);
    for (int i = 0; i < 8; ++i) pixdim[i] = read_at<double>(h, std::size_t(104 + 8 * i), swap);
    vox_offset = double(read_at<std::int64_t>(h, 168, swap));
    scl_slope = read_at<double>(h, 176, swap);
    scl_inter = read_at<double>(h, 184, swap);
  }
  // The value scaling (stored x scl_slope + scl_inter; slope 0: none). A slope that is not
  // finite made every voxel the same value: any iso-value or label gave the same surface.
  if (!std::isfinite(scl_slope))
    throw InvalidInput(name + ": NIfTI scl_slope (the value scaling) is " + std::to_string(scl_slope) +
                       ": it must be a finite number (0 for no scaling)");
  if (scl_slope != 0 && !std::isfinite(scl_inter))
    throw InvalidInput(name + ": NIfTI scl_inter (the value offset) is " + std::to_string(scl_inter) + ": it must be a finite number");
  if (dim[0] < 1 || dim[0] > 7)
    throw InvalidInput(name + ": NIfTI dim[0] (the number of axes) is " + std::to_string(dim[0]) + ", not 1 to 7");
  VolumeLayout layout;
  std::vector<std::uint64_t> sizes;
  for (int i = 1; i <= dim[0]; ++i) {
    if (dim[i] < 1 || std::uint64_t(dim[i]) > kMaxAxis)
      throw InvalidInput(name + ": NIfTI dim[" + std::to_string(i) + "] is " + std::to_string(dim[i]) + ", not 1 to 2^31");
    sizes.push_back(std::uint64_t(dim[i]));
  }
  product(name, sizes);
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    if (i < 3) layout.sizes[i] = sizes[i];
    else layout.sizes[3] *= sizes[i];
  }
  const char* type_name = nullptr;
  const unsigned bytes = nifti_bytes(datatype, type_name);
  if (!type_name) throw InvalidInput(name + ": NIfTI datatype " + std::to_string(datatype) + " is not a NIfTI data type");
  if (bytes == 0)
    throw InvalidInput(name + ": NIfTI datatype " + std::to_string(datatype) + " (" + type_name +
                       ") is not a scalar volume (use a real-valued type: uint8 ... float64)");
  if (bitpix != int(8 * bytes))
    throw InvalidInput(name + ": NIfTI bitpix is " + std::to_string(bitpix) + " but datatype " + type_name + " has " +
                       std::to_string(8 * bytes) + " bits");
  layout.bytes_per_element = bytes;
  for (int i = 1; i <= std::min<int>(3, int(dim[0])); ++i)
    if (!std::isfinite(pixdim[i]) || !(pixdim[i] > 0) || pixdim[i] > 1e6)
      throw InvalidInput(name + ": NIfTI pixdim[" + std::to_string(i) + "] (voxel spacing) is " + std::to_string(pixdim[i]) +
                         ": must be finite and > 0");
  const double min_offset = version == 1 ? 352 : 544;
  if (!std::isfinite(vox_offset) || vox_offset < 0 || vox_offset != std::floor(vox_offset) || vox_offset > 1e12)
    throw InvalidInput(name + ": NIfTI vox_offset is " + std::to_string(vox_offset) + ": not a whole number of bytes");
  if (single && vox_offset < min_offset)
    throw InvalidInput(name + ": NIfTI vox_offset is " + std::to_string(std::int64_t(vox_offset)) + ": the voxels of a single-file NIfTI start at byte " +
                       std::to_string(int(min_offset)) + " or later (they would overlap the header)");
  layout.data_offset = std::uint64_t(vox_offset);
  layout.encoding = "raw";
  if (!single) layout.data_files.push_back("");  // the .img beside the .hdr: the caller names it
  return layout;
}

// ---------------------------------------------------------------------------------------------
// MetaImage

namespace {

unsigned metaimage_bytes(const std::string& type) {
  static const std::map<std::string, unsigned> types = {
      {"MET_CHAR", 1},  {"MET_UCHAR", 1}, {"MET_SHORT", 2},     {"MET_USHORT", 2},     {"MET_INT", 4},
      {"MET_UINT", 4},  {"MET_LONG", 4},  {"MET_ULONG", 4},     {"MET_LONG_LONG", 8},  {"MET_ULONG_LONG", 8},
      {"MET_FLOAT", 4}, {"MET_DOUBLE", 8}};
  const auto it = types.find(type);
  return it == types.end() ? 0 : it->second;
}

bool truth(const std::string& name, const std::string& key, const std::string& v) {
  const std::string l = lower(v);
  if (l == "true" || l == "1") return true;
  if (l == "false" || l == "0") return false;
  throw InvalidInput(name + ": MetaImage " + key + " is " + quoted(v) + ", not True or False");
}

} // namespace

VolumeLayout check_metaimage_header(const std::string& name, const std::string& text) {
  std::map<std::string, std::string> keys;
  std::size_t at = 0;
  int number = 0;
  bool ended = false;
  while (at < text.size() && number < 1000) {
    std::size_t nl = text.find('\n', at);
    if (nl == std::string::npos) nl = text.size();
    std::string line = text.substr(at, nl - at);
    at = std::min(nl + 1, text.size());
    ++number;
    check_text_line(name, line, number);
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) {
      if (trim(line).empty()) continue;
      throw InvalidInput(name + ": line " + std::to_string(number) + " of the MetaImage header has no '=': " + quoted(line));
    }
    const std::string key = lower(trim(line.substr(0, eq)));
    keys[key] = trim(line.substr(eq + 1));
    if (key == "elementdatafile") {
      ended = true;
      break;
    }
  }
  if (!ended) throw InvalidInput(name + ": the MetaImage header has no ElementDataFile line (where the voxels are)");
  const std::uint64_t header_end = at;
  auto need = [&](const char* key) -> const std::string& {
    const auto it = keys.find(key);
    if (it == keys.end() || it->second.empty()) throw InvalidInput(name + ": the MetaImage header has no " + std::string(key));
    return it->second;
  };
  if (keys.count("objecttype") && lower(keys["objecttype"]) != "image")
    throw InvalidInput(name + ": MetaImage ObjectType is " + quoted(keys["objecttype"]) + ", not Image");
  long long ndims = 0;
  if (!parse_integer(need("ndims"), ndims) || ndims < 2 || ndims > 4)
    throw InvalidInput(name + ": MetaImage NDims is " + quoted(keys["ndims"]) + ", not 2, 3 or 4");
  const std::vector<std::uint64_t> sizes = parse_sizes(name, "MetaImage DimSize", need("dimsize"), std::size_t(ndims));
  VolumeLayout layout;
  for (std::size_t i = 0; i < sizes.size(); ++i) layout.sizes[i] = sizes[i];
  const std::string type = need("elementtype");
  layout.bytes_per_element = metaimage_bytes(type);
  if (layout.bytes_per_element == 0)
    throw InvalidInput(name + ": MetaImage ElementType " + quoted(type) + " is not a scalar type (MET_UCHAR ... MET_DOUBLE)");
  if (keys.count("elementnumberofchannels")) {
    long long c = 0;
    if (!parse_integer(keys["elementnumberofchannels"], c) || c < 1 || c > 4)
      throw InvalidInput(name + ": MetaImage ElementNumberOfChannels is " + quoted(keys["elementnumberofchannels"]) + ", not 1 to 4");
    layout.components = unsigned(c);
  }
  product(name, {layout.voxels(), layout.components});
  const bool binary = keys.count("binarydata") ? truth(name, "BinaryData", keys["binarydata"]) : true;
  const bool compressed = keys.count("compresseddata") ? truth(name, "CompressedData", keys["compresseddata"]) : false;
  if (compressed && !binary) throw InvalidInput(name + ": MetaImage CompressedData = True with BinaryData = False");
  layout.encoding = compressed ? "zlib" : binary ? "raw" : "text";
  if (keys.count("headersize")) {
    long long skip = 0;
    if (!parse_integer(keys["headersize"], skip) || skip < -1 || skip > (1LL << 40))
      throw InvalidInput(name + ": MetaImage HeaderSize is " + quoted(keys["headersize"]) + ", not -1 or a byte count");
    if (skip == -1) layout.data_at_end = true;
    else layout.skip = std::uint64_t(skip);
  }
  const std::string file = keys["elementdatafile"];
  const std::vector<std::string> w = words(file);
  if (w.empty()) throw InvalidInput(name + ": MetaImage ElementDataFile is empty");
  if (lower(w[0]) == "local") {
    layout.data_offset = header_end;
  } else if (lower(w[0]) == "list") {
    // One file per slice (or per 2D image with "LIST 2D"), one name a line after the header.
    const std::uint64_t slices = sizes.back();
    std::istringstream rest(text.substr(header_end));
    for (std::string x; layout.data_files.size() < kMaxDataFiles && rest >> x;) layout.data_files.push_back(x);
    if (layout.data_files.size() < slices)
      throw InvalidInput(name + ": MetaImage ElementDataFile LIST names " + std::to_string(layout.data_files.size()) +
                         " files for " + std::to_string(slices) + " slices");
    layout.data_files.resize(std::size_t(slices));
  } else if (w.size() >= 4 && file.find('%') != std::string::npos) {
    layout.data_files = expand_pattern(name, "MetaImage ElementDataFile", w[0], {w.begin() + 1, w.end()});
  } else {
    layout.data_files.push_back(file);
  }
  return layout;
}

// ---------------------------------------------------------------------------------------------
// NRRD

namespace {

unsigned nrrd_bytes(const std::string& t) {
  static const std::map<std::string, unsigned> types = {
      {"signed char", 1}, {"int8", 1}, {"int8_t", 1}, {"uchar", 1}, {"unsigned char", 1}, {"uint8", 1}, {"uint8_t", 1},
      {"short", 2}, {"short int", 2}, {"signed short", 2}, {"signed short int", 2}, {"int16", 2}, {"int16_t", 2},
      {"ushort", 2}, {"unsigned short", 2}, {"unsigned short int", 2}, {"uint16", 2}, {"uint16_t", 2},
      {"int", 4}, {"signed int", 4}, {"int32", 4}, {"int32_t", 4}, {"uint", 4}, {"unsigned int", 4}, {"uint32", 4},
      {"uint32_t", 4}, {"longlong", 8}, {"long long", 8}, {"long long int", 8}, {"signed long long", 8},
      {"signed long long int", 8}, {"int64", 8}, {"int64_t", 8}, {"ulonglong", 8}, {"unsigned long long", 8},
      {"unsigned long long int", 8}, {"uint64", 8}, {"uint64_t", 8}, {"float", 4}, {"double", 8}};
  const auto it = types.find(lower(t));
  return it == types.end() ? 0 : it->second;
}

} // namespace

VolumeLayout check_nrrd_header(const std::string& name, const std::string& text) {
  if (text.compare(0, 7, "NRRD000") != 0 || text.size() < 8 || text[7] < '1' || text[7] > '5')
    throw InvalidInput(name + ": not a NRRD file (no NRRD0001 to NRRD0005 magic on the first line)");
  std::map<std::string, std::string> keys;
  std::size_t at = text.find('\n');
  if (at == std::string::npos) throw InvalidInput(name + ": the NRRD header has nothing after its magic");
  ++at;
  int number = 1;
  bool blank = false;
  std::vector<std::string> list_files;
  while (at < text.size()) {
    std::size_t nl = text.find('\n', at);
    if (nl == std::string::npos) nl = text.size();
    std::string line = text.substr(at, nl - at);
    at = std::min(nl + 1, text.size());
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) {
      blank = true;
      break;
    }
    check_text_line(name, line, number);
    if (line[0] == '#') continue;
    if (line.find(":=") != std::string::npos) continue;  // key/value comments
    const std::size_t colon = line.find(": ");
    if (colon == std::string::npos)
      throw InvalidInput(name + ": line " + std::to_string(number) + " of the NRRD header is not \"field: value\": " + quoted(line));
    std::string key = lower(trim(line.substr(0, colon)));
    if (key == "datafile") key = "data file";
    if (key == "lineskip") key = "line skip";
    if (key == "byteskip") key = "byte skip";
    if (key == "centerings") key = "centers";
    if (keys.count(key)) throw InvalidInput(name + ": the NRRD header gives field " + quoted(key) + " twice");
    keys[key] = trim(line.substr(colon + 2));
    if (key == "data file" && lower(words(keys[key]).empty() ? "" : words(keys[key])[0]) == "list") {
      // The files follow, one a line, to the end of the header file: each a name, not bytes
      // (a single-file NRRD whose header names a LIST has its voxels read as names).
      std::istringstream rest(text.substr(at));
      int line_number = number;
      for (std::string x; list_files.size() < kMaxDataFiles && std::getline(rest, x);) {
        ++line_number;
        if (!x.empty() && x.back() == '\r') x.pop_back();
        const bool text_line = std::none_of(x.begin(), x.end(), [](char c) { return (unsigned char)c < 0x20 && c != '\t'; });
        if (!text_line || x.size() > 4096)
          throw InvalidInput(name + ": line " + std::to_string(line_number) + ", after \"data file: LIST\", is not a file name: " + quoted(x) +
                             " (a LIST names one data file a line to the end of a detached header; this file holds other bytes there)");
        if (!trim(x).empty()) list_files.push_back(trim(x));
      }
      at = text.size();
      break;
    }
  }
  auto need = [&](const char* key) -> const std::string& {
    const auto it = keys.find(key);
    if (it == keys.end() || it->second.empty()) throw InvalidInput(name + ": the NRRD header has no '" + std::string(key) + ":' field");
    return it->second;
  };
  VolumeLayout layout;
  layout.bytes_per_element = nrrd_bytes(need("type"));
  if (layout.bytes_per_element == 0) throw InvalidInput(name + ": NRRD type " + quoted(keys["type"]) + " is not a scalar type");
  long long dimension = 0;
  if (!parse_integer(need("dimension"), dimension) || dimension < 1 || dimension > 4)
    throw InvalidInput(name + ": NRRD dimension is " + quoted(keys["dimension"]) + ", not 1 to 4");
  const std::vector<std::uint64_t> sizes = parse_sizes(name, "NRRD sizes", need("sizes"), std::size_t(dimension));
  if (dimension == 4) {
    layout.components = unsigned(std::min<std::uint64_t>(sizes[0], 1u << 16));
    if (sizes[0] > 4) throw InvalidInput(name + ": a 4-dimensional NRRD needs 1 to 4 values a voxel on its first axis, not " + std::to_string(sizes[0]));
    for (int i = 0; i < 3; ++i) layout.sizes[std::size_t(i)] = sizes[std::size_t(i + 1)];
  } else {
    for (std::size_t i = 0; i < sizes.size(); ++i) layout.sizes[i] = sizes[i];
  }
  const std::string encoding = lower(need("encoding"));
  if (encoding == "raw") layout.encoding = "raw";
  else if (encoding == "gzip" || encoding == "gz") layout.encoding = "gzip";
  else if (encoding == "text" || encoding == "txt" || encoding == "ascii") layout.encoding = "text";
  else throw InvalidInput(name + ": NRRD encoding " + quoted(keys["encoding"]) + " is not supported (raw, gzip or text)");
  if (layout.bytes_per_element > 1 && layout.encoding != "text") {
    if (!keys.count("endian")) throw InvalidInput(name + ": the NRRD header has no 'endian:' field (needed for " + keys["type"] + ")");
    const std::string e = lower(keys["endian"]);
    if (e != "little" && e != "big") throw InvalidInput(name + ": NRRD endian is " + quoted(keys["endian"]) + ", not little or big");
  }
  if (keys.count("line skip")) {
    long long skip = 0;
    if (!parse_integer(keys["line skip"], skip) || skip != 0)
      throw InvalidInput(name + ": NRRD line skip " + quoted(keys["line skip"]) + " is not supported (only 0)");
  }
  if (keys.count("byte skip")) {
    long long skip = 0;
    if (!parse_integer(keys["byte skip"], skip) || skip < -1 || skip > (1LL << 40))
      throw InvalidInput(name + ": NRRD byte skip is " + quoted(keys["byte skip"]) + ", not -1 or a byte count");
    if (skip == -1) {
      if (layout.encoding != "raw") throw InvalidInput(name + ": NRRD byte skip -1 needs raw encoding");
      layout.data_at_end = true;
    } else {
      layout.skip = std::uint64_t(skip);
    }
  }
  if (keys.count("data file")) {
    const std::vector<std::string> w = words(keys["data file"]);
    if (w.empty()) throw InvalidInput(name + ": NRRD data file is empty");
    if (lower(w[0]) == "list") {
      layout.data_files = list_files;
      if (layout.data_files.empty()) throw InvalidInput(name + ": NRRD data file LIST names no file");
    } else if (w.size() >= 4) {
      if (w.size() > 5) throw InvalidInput(name + ": NRRD data file " + quoted(keys["data file"]) + " is not \"pattern first last step [axis]\"");
      layout.data_files = expand_pattern(name, "NRRD data file", w[0], {w.begin() + 1, w.begin() + 4});
    } else if (w.size() == 1) {
      layout.data_files.push_back(keys["data file"]);
    } else {
      throw InvalidInput(name + ": NRRD data file " + quoted(keys["data file"]) + " is neither a file name nor \"pattern first last step\"");
    }
  } else {
    if (!blank) throw InvalidInput(name + ": the NRRD header does not end (no blank line before the data) and names no data file");
    layout.data_offset = at;
  }
  return layout;
}

} // namespace hb
