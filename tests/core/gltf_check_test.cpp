// The glTF checks (formats/gltf_check.h) on a tetrahedron written here (corners 10 to 11, so
// that zeros read by a shifted offset fall outside its bounds): a data: URI buffer of four float
// positions and twelve unsigned-short indices, then one fault at a time of the
// kinds Assimp read as another mesh without a word.
#include "formats/gltf_check.h"
#include "errors.h"
#include <gtest/gtest.h>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace {

std::string base64(const std::string& bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t n = std::uint32_t((unsigned char)bytes[i]) << 16;
    if (i + 1 < bytes.size()) n |= std::uint32_t((unsigned char)bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) n |= std::uint32_t((unsigned char)bytes[i + 2]);
    out += abc[(n >> 18) & 63];
    out += abc[(n >> 12) & 63];
    out += i + 1 < bytes.size() ? abc[(n >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? abc[n & 63] : '=';
  }
  return out;
}

// The faults a test applies to the tetrahedron.
struct Tetra {
  std::vector<std::uint16_t> indices{0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  std::string position_type = "\"componentType\":5126,\"type\":\"VEC3\"";
  std::string position_extra;  // e.g. a byteOffset
  std::string view_extra;      // e.g. a byteStride on the positions' view
  std::string min = "[10,10,10]", max = "[11,11,11]";

  std::string json() const {
    const float p[12] = {10, 10, 10, 11, 10, 10, 10, 11, 10, 10, 10, 11};
    std::string data(48 + 2 * indices.size(), '\0');
    std::memcpy(data.data(), p, 48);
    std::memcpy(data.data() + 48, indices.data(), 2 * indices.size());
    data.resize((data.size() + 3) / 4 * 4 + 16, '\0');  // room past the end, as real buffers have
    return "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" + std::to_string(data.size()) +
           ",\"uri\":\"data:application/octet-stream;base64," + base64(data) + "\"}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":" +
           std::to_string(data.size()) + view_extra + "},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":" + std::to_string(2 * indices.size()) +
           "}],\"accessors\":[{\"bufferView\":0," + position_type + ",\"count\":4,\"min\":" + min + ",\"max\":" + max + position_extra +
           "},{\"bufferView\":1,\"componentType\":5123,\"type\":\"SCALAR\",\"count\":" + std::to_string(indices.size()) +
           "}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],\"nodes\":[{\"mesh\":0}],"
           "\"scenes\":[{\"nodes\":[0]}]}";
  }
};

std::string refusal(const Tetra& t) {
  try {
    hb::check_gltf_json("t.gltf", t.json(), {}, [](const std::string&) -> std::string_view { return {}; });
  } catch (const hb::InvalidInput& e) {
    return e.what();
  }
  return "accepted";
}

TEST(GltfCheckTest, TheUndamagedTetrahedronIsAccepted) { EXPECT_EQ(refusal(Tetra()), "accepted"); }

TEST(GltfCheckTest, IndexPastTheVerticesIsRefusedNamingTheAccessorAndElement) {
  Tetra t;
  t.indices[7] = 4;
  const std::string why = refusal(t);
  EXPECT_NE(why.find("t.gltf: glTF meshes[0].primitives[0].indices (accessors[1]) element 7 is 4, beyond the 4 vertices of POSITION"),
            std::string::npos)
      << why;
  t.indices.pop_back();  // 11 indices: not whole triangles
  EXPECT_NE(refusal(t).find("holds 11 indices for triangles"), std::string::npos) << refusal(t);
}

TEST(GltfCheckTest, PositionOfAnotherTypeOrComponentIsRefused) {
  Tetra t;
  t.position_type = "\"componentType\":5125,\"type\":\"VEC3\"";
  EXPECT_NE(refusal(t).find("attributes.POSITION (accessors[0]) is VEC3 of UNSIGNED_INT, not VEC3 of FLOAT"), std::string::npos)
      << refusal(t);
  t.position_type = "\"componentType\":5126,\"type\":\"VEC2\"";
  EXPECT_NE(refusal(t).find("is VEC2 of FLOAT, not VEC3 of FLOAT"), std::string::npos) << refusal(t);
}

TEST(GltfCheckTest, PositionReadAtAShiftedOffsetOrStrideIsRefused) {
  Tetra t;
  t.position_extra = ",\"byteOffset\":2";  // not on a float's boundary
  EXPECT_NE(refusal(t).find("accessors[0].byteOffset 2 (byte 2 of its buffer) is not a multiple of its 4-byte component"),
            std::string::npos)
      << refusal(t);
  t.position_extra = ",\"byteOffset\":4";  // aligned, but every coordinate shifted by one
  EXPECT_NE(refusal(t).find("outside its declared min"), std::string::npos) << refusal(t);
  t.position_extra.clear();
  t.view_extra = ",\"byteStride\":16";  // four floats apart: reads indices as coordinates
  EXPECT_NE(refusal(t).find("outside its declared min"), std::string::npos) << refusal(t);
  t.view_extra = ",\"byteStride\":8";  // shorter than an element
  EXPECT_NE(refusal(t).find("has elements of 12 bytes but bufferViews[0].byteStride is 8"), std::string::npos) << refusal(t);
  t.view_extra = ",\"byteStride\":14";
  EXPECT_NE(refusal(t).find("bufferViews[0].byteStride is 14, not a multiple of 4"), std::string::npos) << refusal(t);
}

TEST(GltfCheckTest, SparseAccessorOutsideItsAccessorIsRefused) {
  Tetra t;
  // Two substitutions whose indices (the first two indices of the mesh: 0 and 2) are fine...
  t.position_extra = ",\"sparse\":{\"count\":2,\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":0}}";
  EXPECT_EQ(refusal(t), "accepted");
  // ... then index 4 of a 4-element accessor, and more substitutions than elements.
  t.indices[1] = 4;
  EXPECT_NE(refusal(t).find("accessors[0].sparse.indices element 1 is 4, beyond the accessor's 4 elements"), std::string::npos)
      << refusal(t);
  t.position_extra = ",\"sparse\":{\"count\":9,\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":0}}";
  EXPECT_NE(refusal(t).find("accessors[0].sparse.count is 9, beyond 4"), std::string::npos) << refusal(t);
}

TEST(GltfCheckTest, GlbBinChunkIsTheDataOfBufferZero) {
  // A GLB whose BIN chunk holds the data, one index out of range.
  Tetra t;
  t.indices[0] = 9;
  std::string json = t.json();
  const std::size_t uri = json.find(",\"uri\"");
  json.erase(uri, json.find('}', uri) - uri);
  std::string bin(48 + 24 + 16, '\0');
  const float p[12] = {10, 10, 10, 11, 10, 10, 10, 11, 10, 10, 10, 11};
  std::memcpy(bin.data(), p, 48);
  std::memcpy(bin.data() + 48, t.indices.data(), 24);
  while (json.size() % 4) json += ' ';
  auto le = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string glb = "glTF" + le(2) + le(std::uint32_t(12 + 8 + json.size() + 8 + bin.size())) + le(std::uint32_t(json.size())) +
                          "JSON" + json + le(std::uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
  std::string_view chunk;
  const std::string text = hb::check_glb("t.glb", glb, chunk);
  EXPECT_EQ(chunk.size(), bin.size());
  try {
    hb::check_gltf_json("t.glb", text, chunk, [](const std::string&) -> std::string_view { return {}; });
    ADD_FAILURE() << "accepted";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("element 0 is 9, beyond the 4 vertices"), std::string::npos) << e.what();
  }
}

TEST(GltfCheckTest, ExternalBufferLongerOrShorterThanDeclaredIsRefused) {
  std::string json = Tetra().json();
  const std::size_t uri = json.find("data:");
  json.replace(uri, json.find('"', uri) - uri, "t.bin");
  auto check = [&](std::size_t bytes) -> std::string {
    const std::string file(bytes, '\0');
    try {
      hb::check_gltf_json("t.gltf", json, {}, [&](const std::string&) -> std::string_view { return file; });
    } catch (const hb::InvalidInput& e) {
      return e.what();
    }
    return "accepted";
  };
  // 88 bytes declared (48 of positions, 24 of indices, 16 more): zeros put every vertex at 0,
  // outside the declared bounds, so only the length checks are looked at here.
  EXPECT_EQ(check(90).find("declares"), std::string::npos) << check(90);  // 2 bytes of padding: read on
  EXPECT_NE(check(100).find("(more than its length and padding: data inserted or a length changed)"), std::string::npos) << check(100);
  EXPECT_NE(check(80).find("buffers[0] declares 88 bytes, its data holds 80"), std::string::npos) << check(80);
}

} // namespace
