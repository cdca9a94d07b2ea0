// libFuzzer target: the segments CSV (`query --segments`). Invariants: a rejection is an
// hb::InvalidInput naming the file and a line; an accepted file gives finite segments within
// kMaxSegmentCoordinate, one per data row.
#include "evaluation/segments_csv.h"
#include "fuzz_support.h"

#include <cmath>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string name = "fuzz.csv";
  try {
    const std::vector<hb::Segment> segments = hb::parse_segments_csv(text, name);
    std::size_t newlines = 0;
    for (char c : text) newlines += c == '\n';
    if (segments.size() > newlines) hb::fuzz::fail("more segments than lines");
    for (const hb::Segment& s : segments)
      if (!(s.start.cwiseAbs().maxCoeff() <= hb::kMaxSegmentCoordinate) ||
          !(s.end.cwiseAbs().maxCoeff() <= hb::kMaxSegmentCoordinate))
        hb::fuzz::fail("accepted a coordinate that is not finite or out of range");
  } catch (const hb::InvalidInput& e) {
    const std::string what = e.what();
    if (what.rfind(name + ":", 0) != 0 || what.size() < name.size() + 4)
      hb::fuzz::fail("rejection without a message naming the file: '" + what + "'");
  }
  return 0;
}
