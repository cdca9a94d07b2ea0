// Scene and piece files that were read as another model with no word: each written valid here
// (a sphere through Assimp's exporter, a 3MF of a tetrahedron, a piece .vtp), given one fault,
// and refused through load_model (the path the CLI and the window take) with a message naming
// the file and the field; node graphs that crashed Assimp are refused before it runs.
#include "errors.h"
#include "mesh/generators.h"
#include "model_loader.h"
#include "polydata_files.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkPolyData.h>  // piece_polydata()'s result, passed as vtkPolyData*
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#ifdef HB_HAVE_ASSIMP
#include "scene_reader.h"
#include "stored_zip.h"
#endif

namespace {

namespace fs = std::filesystem;

class HostileScenesTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_hostile_scenes_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }
  static std::string write(const std::string& name, const std::string& bytes) {
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  static std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  }
  // load_model must throw hb::InvalidInput starting with `file` + ": ", holding `cause`.
  static void expect_refused(const std::string& file, const std::string& cause) {
    try {
      hb::vtk::load_model(file);
      ADD_FAILURE() << file << ": loaded";
    } catch (const hb::InvalidInput& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << m;
      EXPECT_NE(m.find(cause), std::string::npos) << "expected '" << cause << "' in: " << m;
    }
  }
  static fs::path dir_;
};
fs::path HostileScenesTest::dir_;

#ifdef HB_HAVE_ASSIMP
// A GLB split into its JSON and BIN chunks, and put back together.
struct Glb {
  nlohmann::json json;
  std::string bin;
  explicit Glb(const std::string& bytes) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 12, 4);
    json = nlohmann::json::parse(bytes.substr(20, n));
    std::uint32_t m = 0;
    std::memcpy(&m, bytes.data() + 20 + n, 4);
    bin = bytes.substr(28 + n, m);
  }
  std::string bytes() const {
    std::string text = json.dump();
    while (text.size() % 4) text += ' ';
    auto le = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    return "glTF" + le(2) + le(std::uint32_t(28 + text.size() + bin.size())) + le(std::uint32_t(text.size())) + "JSON" + text +
           le(std::uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
  }
  nlohmann::json& accessor(const char* role) {
    const nlohmann::json& prim = json["meshes"][0]["primitives"][0];
    const std::size_t a = std::string(role) == "indices" ? prim["indices"].get<std::size_t>() : prim["attributes"][role].get<std::size_t>();
    return json["accessors"][a];
  }
};

TEST_F(HostileScenesTest, GlbIndexPastTheVerticesIsRefusedNamingTheAccessorAndElement) {
  hb::vtk::write_scene(hb::make_sphere(10.f, 2), path("s.glb"));
  Glb glb(slurp(path("s.glb")));
  EXPECT_NO_THROW(hb::vtk::load_model(write("same.glb", glb.bytes())));
  const nlohmann::json indices = glb.accessor("indices");
  const std::size_t vertices = glb.accessor("POSITION")["count"].get<std::size_t>();
  const nlohmann::json& view = glb.json["bufferViews"][indices["bufferView"].get<std::size_t>()];
  const std::size_t at = view.value("byteOffset", std::size_t(0)) + indices.value("byteOffset", std::size_t(0)) + 3 * 4;
  ASSERT_EQ(indices["componentType"], 5125) << "Assimp wrote other indices";
  const std::uint32_t beyond = std::uint32_t(vertices + 5);
  std::memcpy(glb.bin.data() + at, &beyond, 4);  // element 3: the second triangle's first corner
  expect_refused(write("index.glb", glb.bytes()), "element 3 is " + std::to_string(beyond) + ", beyond the " +
                                                      std::to_string(vertices) + " vertices of POSITION");
}

TEST_F(HostileScenesTest, GlbPositionOfAnotherTypeOrAtAnotherStrideIsRefused) {
  hb::vtk::write_scene(hb::make_sphere(10.f, 2), path("s.glb"));
  const std::string good = slurp(path("s.glb"));
  Glb type(good);
  type.accessor("POSITION")["componentType"] = 5125;  // a cube came back 7.7e-38 thick
  expect_refused(write("type.glb", type.bytes()), "is VEC3 of UNSIGNED_INT, not VEC3 of FLOAT");
  Glb vec(good);
  vec.accessor("POSITION")["type"] = "VEC2";
  expect_refused(write("vec2.glb", vec.bytes()), "is VEC2 of FLOAT, not VEC3 of FLOAT");
  Glb stride(good);
  stride.accessor("POSITION")["count"] = stride.accessor("POSITION")["count"].get<int>() / 2;
  const std::size_t view = stride.accessor("POSITION")["bufferView"].get<std::size_t>();
  stride.json["bufferViews"][view]["byteStride"] = 24;  // every other vertex, read as all of them
  expect_refused(write("stride.glb", stride.bytes()), "vertices of POSITION");
  Glb offset(good);
  offset.accessor("POSITION")["byteOffset"] = 2;
  expect_refused(write("offset.glb", offset.bytes()), "is not a multiple of its 4-byte component");
}

using hb::test::three_mf;

std::string tetra_3mf(const std::string& vertex1, const std::string& triangle1 = "v1=\"0\" v2=\"1\" v3=\"3\"") {
  return three_mf("<?xml version=\"1.0\"?><model unit=\"millimeter\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">"
                  "<resources><object id=\"1\" type=\"model\"><mesh><vertices><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex " +
                  vertex1 + "/><vertex x=\"0\" y=\"10\" z=\"0\"/><vertex x=\"0\" y=\"0\" z=\"10\"/></vertices><triangles>"
                  "<triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle " + triangle1 + "/><triangle v1=\"1\" v2=\"2\" v3=\"3\"/>"
                  "<triangle v1=\"0\" v2=\"3\" v3=\"2\"/></triangles></mesh></object></resources><build><item objectid=\"1\"/></build></model>");
}

TEST_F(HostileScenesTest, ThreeMfCoordinatesAndCornersAreParsedStrictly) {
  EXPECT_NO_THROW(hb::vtk::load_model(write("good.3mf", tetra_3mf("x=\"1e1\" y=\"0.0\" z=\"-0\""))));
  // "0x10" was read as 16, text and a missing coordinate as 0.
  expect_refused(write("hex.3mf", tetra_3mf("x=\"0x10\" y=\"0\" z=\"0\"")), "3MF object 1 vertex 1: x=\"0x10\" is not a finite decimal number");
  expect_refused(write("text.3mf", tetra_3mf("x=\"ten\" y=\"0\" z=\"0\"")), "vertex 1: x=\"ten\" is not");
  expect_refused(write("missing.3mf", tetra_3mf("x=\"10\" z=\"0\"")), "3MF object 1 vertex 1 has no y attribute");
  expect_refused(write("inf.3mf", tetra_3mf("x=\"1e999\" y=\"0\" z=\"0\"")), "vertex 1: x=\"1e999\" is not");
  expect_refused(write("corner.3mf", tetra_3mf("x=\"10\" y=\"0\" z=\"0\"", "v1=\"0\" v2=\"1\" v3=\"4\"")),
                 "3MF object 1 triangle 1: v3=\"4\" is beyond the 4 vertices of its mesh");
  expect_refused(write("cornerhex.3mf", tetra_3mf("x=\"10\" y=\"0\" z=\"0\"", "v1=\"0\" v2=\"0x1\" v3=\"3\"")),
                 "triangle 1: v2=\"0x1\" is not a whole number");
}

TEST_F(HostileScenesTest, ColladaAccessorWithAChangedStrideOrOffsetIsRefused) {
  hb::vtk::write_scene(hb::make_sphere(10.f, 2), path("s.dae"));
  const std::string good = slurp(path("s.dae"));
  EXPECT_NO_THROW(hb::vtk::load_model(path("s.dae")));
  const std::size_t accessor = good.find("<accessor");
  ASSERT_NE(accessor, std::string::npos);
  const std::size_t stride = good.find("stride=\"3\"", accessor);
  ASSERT_NE(stride, std::string::npos);
  std::string two = good;
  two.replace(stride, 10, "stride=\"2\"");
  expect_refused(write("stride.dae", two), "names 3 params but has a stride of 2");
  // A count one short: the last vertex's values left unread.
  const std::size_t count = good.find("count=\"", accessor) + 7;
  const std::size_t count_end = good.find('"', count);
  std::string fewer = good;
  fewer.replace(count, count_end - count, std::to_string(std::stoul(good.substr(count, count_end - count)) - 1));
  expect_refused(write("count.dae", fewer), "leaving values unread");
  std::string shifted = good;
  shifted.insert(accessor + 9, " offset=\"3\"");
  expect_refused(write("offset.dae", shifted), "from offset 3 of an array");
  // The POSITION input of <vertices> deleted: Assimp said only "vector::_M_fill_insert".
  const std::size_t input = good.find("<input semantic=\"POSITION\"", good.find("<vertices"));
  ASSERT_NE(input, std::string::npos);
  std::string unplaced = good;
  unplaced.erase(input, good.find('>', input) + 1 - input);
  expect_refused(write("noposition.dae", unplaced), "> has no POSITION input");
}

TEST_F(HostileScenesTest, ColladaNodeInstancingItselfOrNestedTooDeepIsRefusedBeforeAssimp) {
  hb::vtk::write_scene(hb::make_sphere(10.f, 2), path("s.dae"));
  const std::string good = slurp(path("s.dae"));
  const std::size_t node = good.find("<node ");
  ASSERT_NE(node, std::string::npos);
  const std::size_t id = good.find("id=\"", node);
  const std::string name = good.substr(id + 4, good.find('"', id + 4) - id - 4);
  std::string self = good;
  self.insert(good.find('>', node) + 1, "<instance_node url=\"#" + name + "\"/>");
  expect_refused(write("self.dae", self), "Collada node " + name + " contains itself");
  std::string deep;
  for (int i = 0; i < 300; ++i) deep += "<node id=\"d" + std::to_string(i) + "\">";
  for (int i = 0; i < 300; ++i) deep += "</node>";
  std::string nested = good;
  nested.insert(good.find('>', node) + 1, deep);
  expect_refused(write("deep.dae", nested), "Collada nodes are nested more than 256 deep");
}

TEST_F(HostileScenesTest, BinaryFbxWithAnUnknownTypeCodeIsNamedInPrintableText) {
  // One node record whose property has type code 0x0B: Assimp's message ended with that byte.
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string name = "Objects";
  const std::string property = std::string(1, '\x0B') + u32(7);
  const std::string head = std::string("Kaydara FBX Binary  \0\x1A\0", 23) + u32(7400);
  const std::uint32_t end = std::uint32_t(head.size() + 13 + name.size() + property.size());
  const std::string node = u32(end) + u32(1) + u32(std::uint32_t(property.size())) + char(name.size()) + name + property;
  const std::string file = write("code.fbx", head + node + std::string(13, '\0') + std::string(160, '\0'));
  try {
    hb::vtk::load_model(file);
    ADD_FAILURE() << "loaded";
  } catch (const hb::Error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(file + ": ", 0), 0u) << m;
    for (char c : m) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7F)) << "raw byte " << int((unsigned char)c) << " in: " << m;
    EXPECT_GT(m.size(), file.size() + 20) << m;
  }
}
#endif

TEST_F(HostileScenesTest, VtpPieceIdOfTypeBitIsRefused) {
  const hb::TriangleMesh sphere = hb::make_sphere(20.f, 2);
  std::vector<std::uint32_t> ids(sphere.triangle_count());
  for (std::size_t t = 0; t < ids.size(); ++t) ids[t] = std::uint32_t(t % 6);
  hb::vtk::write_polydata_xml(hb::vtk::piece_polydata(sphere, ids), path("pieces.vtp"));
  const std::string bit = write("bit.vtp", replaced(slurp(path("pieces.vtp")), "type=\"Int32\" Name=\"PieceId\"", "type=\"Bit\" Name=\"PieceId\""));
  try {
    hb::vtk::read_piece_vtp(bit, ids.size());
    ADD_FAILURE() << "read as pieces";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(bit + ": the cell array PieceId is declared type=\"Bit\""), std::string::npos) << e.what();
  }
}

// A tetrahedron's pieces as a text .vtp, one array a line.
std::string text_vtp(const std::string& connectivity, const std::string& offsets, const std::string& points = "0 0 0 10 0 0 0 10 0 0 0 10") {
  return "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
         "<PolyData>\n<Piece NumberOfPoints=\"4\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"4\">\n"
         "<Points>\n<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">" + points + "</DataArray>\n</Points>\n"
         "<CellData>\n<DataArray type=\"Int32\" Name=\"PieceId\" format=\"ascii\">0 0 1 1</DataArray>\n</CellData>\n"
         "<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">" + connectivity + "</DataArray>\n"
         "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">" + offsets + "</DataArray>\n</Polys>\n"
         "</Piece>\n</PolyData>\n</VTKFile>\n";
}

TEST_F(HostileScenesTest, TextVtpWhoseCellsOrCountsDisagreeIsRefusedBeforeVtk) {
  const std::string good = write("text.vtp", text_vtp("0 2 1 0 1 3 1 2 3 0 3 2", "3 6 9 12"));
  EXPECT_EQ(hb::vtk::read_piece_vtp(good, 4), (std::vector<std::uint32_t>{0, 0, 1, 1}));
  auto refused = [&](const std::string& name, const std::string& bytes, const std::string& cause) {
    const std::string file = write(name, bytes);
    try {
      hb::vtk::read_piece_vtp(file, 4);
      ADD_FAILURE() << name << ": read";
    } catch (const hb::InvalidInput& e) {
      EXPECT_EQ(std::string(e.what()).rfind(file + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(cause), std::string::npos) << e.what();
    }
  };
  refused("point.vtp", text_vtp("0 2 1 0 1 9 1 2 3 0 3 2", "3 6 9 12"), "the Polys connectivity names point 9 (value 5) of the piece's 4");
  refused("fewer.vtp", text_vtp("0 2 1 0 1 3 1 2 3 0 3 2", "3 6 9"), "the Polys offsets hold 3 values for the piece's 4 cells");
  refused("down.vtp", text_vtp("0 2 1 0 1 3 1 2 3 0 3 2", "3 9 6 12"), "the Polys offsets decrease at cell 2");
  refused("end.vtp", text_vtp("0 2 1 0 1 3 1 2 3 0 3 2", "3 6 9 14"), "offsets end at 14 but the connectivity holds 12 values");
  refused("nan.vtp", text_vtp("0 2 1 0 1 3 1 2 3 0 3 2", "3 6 9 12", "0 0 0 10 0 0 0 1x 0 0 0 10"), "holds '1x', not a number");
  refused("short.vtp", text_vtp("0 2 1 0 1 3 1 2 3 0 3 2", "3 6 9 12", "0 0 0 10 0 0 0 10 0 0 0"), "the counts disagree with the arrays");
}

} // namespace
