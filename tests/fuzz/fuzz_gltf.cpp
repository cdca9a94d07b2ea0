// libFuzzer target: the glTF checks run before Assimp (formats/gltf_check.h). Inputs that
// start with "glTF" are GLB containers, others glTF JSON (external buffers are 1 MB of zeros).
// Invariants: a rejection is an hb::InvalidInput naming the file with a cause; an accepted
// GLB's JSON chunk and BIN chunk lie within the input.
#include "formats/gltf_check.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const bool glb = size >= 4 && bytes.compare(0, 4, "glTF") == 0;
  const std::string name = glb ? "fuzz.glb" : "fuzz.gltf";
  try {
    std::string_view bin;
    const std::string json = glb ? hb::check_glb(name, bytes, bin) : bytes;
    if (json.size() + bin.size() > size) hb::fuzz::fail("accepted chunks longer than the file");
    static const std::string external(1 << 20, '\0');
    hb::check_gltf_json(name, json, bin, [](const std::string&) -> std::string_view { return external; });
  } catch (const hb::InvalidInput& e) {
    const std::string what = e.what();
    if (what.rfind(name + ": ", 0) != 0 || what.size() < name.size() + 4)
      hb::fuzz::fail("rejection without a message naming the file: '" + what + "'");
  }
  return 0;
}
