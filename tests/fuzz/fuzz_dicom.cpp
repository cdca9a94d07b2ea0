// libFuzzer target: the DICOM check run before VTK's DICOM parser (formats/dicom_header.h).
// Invariants: a rejection is an hb::InvalidInput naming the file with a cause; an accepted
// file has Rows, Columns and a pixel format whose bytes its pixel data holds exactly, one
// sample a pixel, and the geometry tags of a slice.
#include "formats/dicom_header.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string name = "fuzz.dcm";
  try {
    const hb::DicomHeader h = hb::check_dicom_header(name, bytes);
    const std::uint64_t needed = std::uint64_t(h.rows) * h.columns * (h.bits_allocated / 8);
    if (h.rows == 0 || h.columns == 0 || needed == 0) hb::fuzz::fail("accepted an empty image");
    if (h.pixel_bytes != needed && h.pixel_bytes != needed + 1) hb::fuzz::fail("accepted pixel data of the wrong length");
    if (h.pixel_bytes > size) hb::fuzz::fail("accepted pixel data longer than the file");
    if (h.samples_per_pixel != 1 || !h.has_position || !h.has_orientation || !h.has_spacing || h.photometric.empty())
      hb::fuzz::fail("accepted a slice without its required tags");
  } catch (const hb::InvalidInput& e) {
    const std::string what = e.what();
    if (what.rfind(name + ": ", 0) != 0 || what.size() < name.size() + 4)
      hb::fuzz::fail("rejection without a message naming the file: '" + what + "'");
  }
  return 0;
}
