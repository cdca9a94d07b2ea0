// libFuzzer target: the volume headers checked before VTK reads a volume (NIfTI, MetaImage,
// NRRD; formats/volume_headers.h). The input's first byte picks the format. Invariants: a
// rejection is an hb::InvalidInput naming the file with a cause; an accepted header gives sizes
// of at least 1 whose product and byte count cannot overflow, a known element size and
// encoding, and at most 65,536 data files.
#include "formats/volume_headers.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  const int format = data[0] % 3;
  const std::string name = format == 0 ? "fuzz.nii" : format == 1 ? "fuzz.mha" : "fuzz.nrrd";
  try {
    const hb::VolumeLayout l = format == 0   ? hb::check_nifti_header(name, bytes)
                               : format == 1 ? hb::check_metaimage_header(name, bytes)
                                             : hb::check_nrrd_header(name, bytes);
    for (std::uint64_t s : l.sizes)
      if (s < 1 || s > (std::uint64_t(1) << 40)) hb::fuzz::fail("accepted a size of " + std::to_string(s));
    if (l.voxels() > (std::uint64_t(1) << 40)) hb::fuzz::fail("accepted more than 2^40 voxels");
    if (l.bytes_per_element != 1 && l.bytes_per_element != 2 && l.bytes_per_element != 4 && l.bytes_per_element != 8)
      hb::fuzz::fail("accepted an element of " + std::to_string(l.bytes_per_element) + " bytes");
    if (l.components < 1 || l.components > 4) hb::fuzz::fail("accepted " + std::to_string(l.components) + " components");
    if (l.encoding != "raw" && l.encoding != "gzip" && l.encoding != "zlib" && l.encoding != "text")
      hb::fuzz::fail("accepted an unknown encoding " + l.encoding);
    if (l.data_files.size() > 65536) hb::fuzz::fail("accepted more than 65,536 data files");
  } catch (const hb::InvalidInput& e) {
    const std::string what = e.what();
    if (what.rfind(name + ": ", 0) != 0 || what.size() < name.size() + 4)
      hb::fuzz::fail("rejection without a message naming the file: '" + what + "'");
  }
  return 0;
}
