// libFuzzer target: the glTF checks run before Assimp (formats/gltf_check.h). Inputs that
// start with "glTF" are GLB containers, others glTF JSON (an external buffer is zeros of its
// declared length, at most 1 MB).
// Invariants: a rejection is an hb::InvalidInput naming the file with a cause; an accepted
// GLB's JSON chunk and BIN chunk lie within the input.
#include "formats/gltf_check.h"
#include "fuzz_support.h"
#include <nlohmann/json.hpp>
#include <algorithm>
#include <map>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const bool glb = size >= 4 && bytes.compare(0, 4, "glTF") == 0;
  const std::string name = glb ? "fuzz.glb" : "fuzz.gltf";
  try {
    std::string_view bin;
    const std::string json = glb ? hb::check_glb(name, bytes, bin) : bytes;
    if (json.size() + bin.size() > size) hb::fuzz::fail("accepted chunks longer than the file");
    // An external buffer is zeros of the length the document declares for it (at most 1 MB),
    // so that the checks after the buffers' lengths are reached.
    static const std::string zeros(1 << 20, '\0');
    std::map<std::string, std::size_t> declared;
    const nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
    if (doc.is_object() && doc.contains("buffers") && doc["buffers"].is_array())
      for (const auto& b : doc["buffers"])
        if (b.is_object() && b.contains("uri") && b["uri"].is_string() && b.contains("byteLength") && b["byteLength"].is_number_unsigned())
          declared[b["uri"].get<std::string>()] = std::min<std::size_t>(b["byteLength"].get<std::size_t>(), zeros.size());
    hb::check_gltf_json(name, json, bin, [&](const std::string& uri) -> std::string_view {
      const auto it = declared.find(uri);
      return std::string_view(zeros).substr(0, it == declared.end() ? zeros.size() : it->second);
    });
  } catch (const hb::InvalidInput& e) {
    const std::string what = e.what();
    if (what.rfind(name + ": ", 0) != 0 || what.size() < name.size() + 4)
      hb::fuzz::fail("rejection without a message naming the file: '" + what + "'");
  }
  return 0;
}
