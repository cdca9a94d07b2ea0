// libFuzzer target: the CAD checks run before OpenCASCADE (formats/step_check.h,
// formats/iges_check.h, formats/iges_global.h). Inputs that start with "ISO-10303-21" are STEP
// files, others IGES. Invariants: a rejection is an hb::InvalidInput naming the file with a
// cause (no NUL in it: quoted file text is escaped); an accepted IGES file declares a length
// unit within the table's range.
#include "formats/iges_check.h"
#include "formats/iges_global.h"
#include "formats/step_check.h"
#include "fuzz_support.h"
#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const bool step = bytes.compare(0, 12, "ISO-10303-21") == 0;
  const std::string name = step ? "fuzz.step" : "fuzz.igs";
  try {
    if (step) {
      hb::check_step_references(name, bytes);
    } else {
      const double mm = hb::iges_mm_per_unit(name, bytes);
      if (!(mm >= 2.54e-5 && mm <= 1.609344e6)) hb::fuzz::fail("an IGES unit outside the table");
      hb::check_iges_structure(name, bytes);
    }
  } catch (const hb::InvalidInput& e) {
    const std::string what = e.what();
    if (what.rfind(name + ": ", 0) != 0 || what.size() < name.size() + 4 || std::strlen(e.what()) != what.size())
      hb::fuzz::fail("rejection without a whole message naming the file: '" + what + "'");
  }
  return 0;
}
