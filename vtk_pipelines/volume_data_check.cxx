// A volume's data held to its header (volume_data_check.h):
//  1. the header's size against the voxel limit, before any voxel is read;
//  2. the data decoded (raw, gzip or zlib inflated, text parsed) and counted up to what the
//     header declares, plus one byte where one block must be exactly that long;
//  3. a shortfall names the header's layout and what the data holds.
#include "volume_data_check.h"
#include "errors.h"
#include "formats/quoted_text.h"
#include "string_util.h"
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>
#include <zlib.h>

namespace hb::vtk {

namespace {

namespace fs = std::filesystem;

std::string describe(const VolumeLayout& l) {
  std::ostringstream o;
  o << l.sizes[0] << " x " << l.sizes[1] << " x " << l.sizes[2];
  if (l.sizes[3] > 1) o << " x " << l.sizes[3];
  o << " voxels";
  if (l.components > 1) o << " of " << l.components << " values";
  o << " of " << l.bytes_per_element << " bytes";
  return o.str();
}

// Decoded bytes available in `file` from byte `offset` in `encoding`, counted up to `want`
// (stops there). Damaged compressed streams and non-numbers in text data are errors.
std::uint64_t decoded_bytes(const std::string& name, const std::string& file, std::uint64_t offset, const std::string& encoding,
                            std::uint64_t want, unsigned bytes_per_element) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InvalidInput(name + ": the data file " + quoted_text(file, 300) + " is missing or not a regular file");
  const std::uint64_t size = fs::file_size(file, ec);
  if (ec) throw IoError(name + ": cannot read the data file " + quoted_text(file, 300));
  if (encoding == "raw") return size > offset ? size - offset : 0;
  std::ifstream in(file, std::ios::binary);
  in.seekg(std::streamoff(std::min(offset, size)));
  if (encoding == "text") {
    std::uint64_t values = 0;
    for (std::string w; values * bytes_per_element < want && in >> w;) {
      char* end = nullptr;
      std::strtod(w.c_str(), &end);
      if (end == w.c_str() || *end)
        throw InvalidInput(name + ": the text-encoded data holds " + quoted_text(w) +
                           ", not a number (binary data with a text encoding?)");
      ++values;
    }
    return values * bytes_per_element;
  }
  // gzip (NRRD) or zlib (MetaImage): inflate, counting the output.
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) throw InvalidInput(name + ": zlib could not start");
  std::vector<unsigned char> input(1 << 16), output(1 << 18);
  std::uint64_t total = 0;
  int rc = Z_OK;
  while (total < want && rc != Z_STREAM_END) {
    if (z.avail_in == 0) {
      in.read(reinterpret_cast<char*>(input.data()), std::streamsize(input.size()));
      z.next_in = input.data();
      z.avail_in = unsigned(in.gcount());
      if (z.avail_in == 0) break;  // the stream is cut short
    }
    z.next_out = output.data();
    z.avail_out = unsigned(output.size());
    rc = inflate(&z, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) {
      const std::string why = z.msg ? z.msg : "error " + std::to_string(rc);
      inflateEnd(&z);
      throw InvalidInput(name + ": the compressed voxel data in " + quoted_text(file, 300) + " is damaged (zlib: " + why + ")");
    }
    total += output.size() - z.avail_out;
  }
  inflateEnd(&z);
  return total;
}

} // namespace

void check_size(const std::string& path, const int* extent, std::size_t max_voxels) {
  std::size_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const long n = long(extent[2 * a + 1]) - long(extent[2 * a]) + 1;
    if (n <= 0) throw InvalidInput(path + ": the volume is empty (dimension " + std::to_string(a) + " is " + std::to_string(n) + ")");
    if (voxels > max_voxels / std::size_t(n) + 1) voxels = max_voxels + 1;
    else voxels *= std::size_t(n);
  }
  if (voxels > max_voxels)
    throw InvalidInput(path + ": the volume's header claims " + std::to_string(extent[1] - extent[0] + 1) + " x " +
                       std::to_string(extent[3] - extent[2] + 1) + " x " + std::to_string(extent[5] - extent[4] + 1) +
                       " voxels, more than the " + std::to_string(max_voxels) + " accepted");
}


// The first `n` bytes of a file (of its decompressed content when `gz`).
std::string file_head(const std::string& path, std::size_t n, bool gz) {
  std::string out(n, '\0');
  if (gz) {
    gzFile f = gzopen(path.c_str(), "rb");
    if (!f) throw IoError(path + ": cannot open the file");
    const int got = gzread(f, out.data(), unsigned(n));
    int err = 0;
    const std::string why = got < 0 ? gzerror(f, &err) : "";
    gzclose(f);
    if (got < 0) throw InvalidInput(path + ": the gzip stream is damaged (" + why + ")");
    out.resize(std::size_t(got));
    return out;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open the file");
  in.read(out.data(), std::streamsize(n));
  out.resize(std::size_t(in.gcount()));
  return out;
}

// Holds the data (inline or in data files beside `name`) to what the header declares.
void check_volume_data(const std::string& name, const VolumeLayout& layout, std::size_t max_voxels) {
  if (layout.voxels() * layout.components > max_voxels)
    throw InvalidInput(name + ": the volume's header claims " + describe(layout) + ", more than the " + std::to_string(max_voxels) +
                       " voxels accepted");
  const std::uint64_t want = layout.expected_bytes() + (layout.data_at_end ? 0 : layout.skip);
  const fs::path dir = fs::path(name).parent_path();
  std::uint64_t have = 0;
  // One block of binary data must be exactly as long as the header makes it: extra bytes mean
  // wrong sizes or type in the header, or data shifted by an insertion (read as garbage).
  const bool exact = layout.encoding != "text" && !layout.data_at_end && layout.data_files.size() <= 1;
  if (layout.data_files.empty()) {
    have = decoded_bytes(name, name, layout.data_offset, layout.encoding, want + (exact ? 1 : 0), layout.bytes_per_element);
  } else if (exact) {
    const std::string& f = layout.data_files.front();
    const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
    have = decoded_bytes(name, p.string(), 0, layout.encoding, want + 1, layout.bytes_per_element);
  } else {
    for (const std::string& f : layout.data_files) {
      if (have >= want) break;
      const fs::path p = fs::path(f).is_absolute() ? fs::path(f) : dir / f;
      have += decoded_bytes(name, p.string(), 0, layout.encoding, want - have, layout.bytes_per_element);
    }
  }
  if (have < want) {
    std::ostringstream msg;
    msg << name << ": the header declares " << describe(layout) << " (" << want << " bytes";
    if (layout.encoding != "raw") msg << " once decoded from " << layout.encoding;
    msg << ") but the data holds only " << have << " bytes: the volume is truncated or its header is wrong";
    throw InvalidInput(msg.str());
  }
  if (exact && have > want) {
    std::ostringstream msg;
    msg << name << ": the header declares " << describe(layout) << " (" << want << " bytes";
    if (layout.encoding != "raw") msg << " once decoded from " << layout.encoding;
    msg << ") but the data holds more: the header's sizes or type are wrong, or the data was altered";
    throw InvalidInput(msg.str());
  }
}

void check_nifti_file(const std::string& path, std::size_t max_voxels) {
  const std::string p = lower(path);
  const bool gz = ends_with(p, ".gz");
  const VolumeLayout layout = check_nifti_header(path, file_head(path, 540, gz));
  if (layout.voxels() > max_voxels)
    throw InvalidInput(path + ": the volume's header claims " + describe(layout) + ", more than the " + std::to_string(max_voxels) +
                       " voxels accepted");
  const std::uint64_t want = layout.data_offset + layout.expected_bytes();
  if (layout.data_files.empty()) {  // single file: the voxels follow the header
    const std::uint64_t have = decoded_bytes(path, path, 0, gz ? "gzip" : "raw", want + 1, 1);
    if (have < want)
      throw InvalidInput(path + ": the header declares " + describe(layout) + " from byte " + std::to_string(layout.data_offset) +
                         " (" + std::to_string(want) + " bytes) but the file holds " + std::to_string(have) +
                         (gz ? " once decompressed" : "") + ": the volume is truncated or its header is wrong");
    if (have > want)
      throw InvalidInput(path + ": the file holds more than the " + std::to_string(want) + " bytes its header declares (" + describe(layout) +
                         " from byte " + std::to_string(layout.data_offset) + "): the header's sizes or type are wrong, or the data was altered");
    return;
  }
  // A header and image pair: X.hdr with X.img (or their .gz).
  const std::string base = path.substr(0, path.size() - (gz ? 7 : 4));
  std::string img_path;
  for (const char* ext : {".img", ".img.gz", ".IMG", ".IMG.gz"})
    if (img_path.empty() && fs::exists(base + ext)) img_path = base + ext;
  if (img_path.empty()) throw InvalidInput(path + ": the NIfTI header's image file " + base + ".img is missing");
  const std::uint64_t have = decoded_bytes(path, img_path, 0, ends_with(lower(img_path), ".gz") ? "gzip" : "raw", want, 1);
  if (have < want)
    throw InvalidInput(path + ": the header declares " + describe(layout) + " (" + std::to_string(want) + " bytes with the offset) but " +
                       img_path + " holds " + std::to_string(have) + ": the volume is truncated or its header is wrong");
}

} // namespace hb::vtk
