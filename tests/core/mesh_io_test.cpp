#include "mesh/mesh_io.h"

#include "errors.h"
#include "mesh/generators.h"
#include "mesh_checks.h"

#include "scratch_dir_test.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <random>
#include <string>

namespace hb {
namespace {

namespace fs = std::filesystem;

/// Gives each test its own scratch folder, removed afterwards.
class MeshReadTest : public test::ScratchDirTest {
protected:
  MeshReadTest() : ScratchDirTest("hb_mesh_io_") {}
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
};

/// Reads `path` expecting exception type E whose message names the file.
template <typename E>
void expect_read_error(const std::string& path, const std::string& cause_fragment = {}) {
  try {
    read_mesh(path);
    ADD_FAILURE() << "no exception for " << path;
  } catch (const E& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(fs::path(path).filename().string()), std::string::npos) << what;
    if (!cause_fragment.empty()) {
      EXPECT_NE(what.find(cause_fragment), std::string::npos) << what;
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type for " << path << ": " << e.what();
  }
}

const char* kTetrahedronOff =
    "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

// --- bad input ------------------------------------------------------------------------

TEST_F(MeshReadTest, MissingFileIsIoError) { expect_read_error<IoError>(path("absent.off"), "no such file"); }

TEST_F(MeshReadTest, EmptyFileIsIoError) { expect_read_error<IoError>(write("empty.off", ""), "empty"); }

TEST_F(MeshReadTest, EmptyObjIsIoError) { expect_read_error<IoError>(write("empty.obj", ""), "empty"); }

TEST_F(MeshReadTest, CommentOnlyOffIsIoError) { expect_read_error<IoError>(write("comments.off", "# nothing\n\n")); }

TEST_F(MeshReadTest, DirectoryIsIoError) {
  fs::create_directories(dir_ / "folder.off");
  expect_read_error<IoError>(path("folder.off"), "directory");
}

TEST_F(MeshReadTest, UnknownExtensionIsInvalidInput) {
  expect_read_error<InvalidInput>(write("mesh.xyz", kTetrahedronOff), "extension");
}

TEST_F(MeshReadTest, NoExtensionIsInvalidInput) { expect_read_error<InvalidInput>(write("mesh", kTetrahedronOff)); }

TEST_F(MeshReadTest, GarbageBytesAreRejectedInEveryFormat) {
  std::mt19937 rng(7);
  std::string garbage(4096, '\0');
  for (char& c : garbage) c = char(rng() & 0xff);
  for (const char* ext : {".off", ".obj", ".ply", ".stl", ".om"}) {
    SCOPED_TRACE(ext);
    expect_read_error<Error>(write(std::string("garbage") + ext, garbage));
  }
}

TEST_F(MeshReadTest, GarbageTextIsInvalidInput) {
  expect_read_error<InvalidInput>(write("text.off", "hello world\nthis is not a mesh\n"), "not an OFF file");
  expect_read_error<InvalidInput>(write("text.obj", "hello world\nthis is not a mesh\n"));
  expect_read_error<InvalidInput>(write("text.ply", "hello world\nthis is not a mesh\n"));
}

TEST_F(MeshReadTest, NanCoordinateIsRejected) {
  expect_read_error<InvalidInput>(write("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"), "vertex 1");
}

TEST_F(MeshReadTest, InfCoordinateIsRejected) {
  expect_read_error<InvalidInput>(write("inf.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n"), "non-finite");
  // Finite in double but not in float.
  expect_read_error<InvalidInput>(write("big.off", "OFF\n3 1 0\n0 0 0\n1 1e300 0\n0 1 0\n3 0 1 2\n"), "non-finite");
}

TEST_F(MeshReadTest, NanCoordinateInObjIsRejected) {
  expect_read_error<InvalidInput>(write("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
}

TEST_F(MeshReadTest, OutOfRangeIndexIsRejected) {
  expect_read_error<InvalidInput>(write("index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n"), "out of range");
  expect_read_error<InvalidInput>(write("negative.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n"), "out of range");
}

TEST_F(MeshReadTest, OutOfRangeIndexInObjIsRejected) {
  // OpenMesh's OBJ reader itself drops such a face with a message; either way nothing valid is left.
  expect_read_error<InvalidInput>(write("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
}

TEST_F(MeshReadTest, TruncatedOffIsIoError) {
  expect_read_error<IoError>(write("truncated.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n"), "truncated");
}

TEST_F(MeshReadTest, AbsurdCountsAreRejectedWithoutAllocating) {
  expect_read_error<IoError>(write("absurd.off", "OFF\n4000000000 4000000000 0\n0 0 0\n"), "truncated");
  expect_read_error<InvalidInput>(write("huge.off", "OFF\n99999999999999 1 0\n0 0 0\n"));
  expect_read_error<InvalidInput>(write("overflow.off", "OFF\n999999999999999999999999 1 0\n"), "bad count");
  expect_read_error<InvalidInput>(write("corners.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n"));
}

TEST_F(MeshReadTest, AbsurdCountsInOtherFormatsAreRejected) {
  // Binary STL header claiming 2^32-1 facets with 100 bytes of data.
  std::string stl(80, '\0');
  stl += std::string("\xff\xff\xff\xff", 4) + std::string(100, '\1');
  expect_read_error<InvalidInput>(write("huge.stl", stl));
  const std::string ply_header = "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 1\n"
                                 "property list uchar int vertex_indices\nend_header\n0 0 0\n";
  expect_read_error<InvalidInput>(write("huge.ply", ply_header));
  expect_read_error<InvalidInput>(write("huge_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n"));
  expect_read_error<InvalidInput>(write("negative_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -7\n"));
}

TEST_F(MeshReadTest, TruncatedPlyIsInvalidInput) {
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                          "end_header\n0 0 0\n1 0 0\n";
  expect_read_error<InvalidInput>(write("truncated.ply", ply));
}

TEST_F(MeshReadTest, PlyNameWithANulByteIsRejectedWithAWholeMessage) {
  // Found by fuzz_ply: an element name holding NUL bytes reached a message that quoted it,
  // and the message was cut after the file name.
  const std::string ply = std::string("ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
                                      "property float y\nproperty float z\nelement \0\0x 4\n", 118) +
                          "property list uchar int vertex_indices\nend_header\n";
  expect_read_error<InvalidInput>(write("nul_name.ply", ply), "not printable ASCII");
}

TEST_F(MeshReadTest, NoTrianglesIsInvalidInput) {
  expect_read_error<InvalidInput>(write("points.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), "no (non-degenerate) triangles");
  expect_read_error<InvalidInput>(write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no (non-degenerate) triangles");
  expect_read_error<InvalidInput>(write("flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n"));
}

TEST_F(MeshReadTest, BinaryOffIsInvalidInput) {
  expect_read_error<InvalidInput>(write("binary.off", "OFF BINARY\n"), "binary");
}

// --- accepted input -------------------------------------------------------------------

TEST_F(MeshReadTest, QuadMeshIsTriangulated) {
  const std::string off =
      "OFF\n8 6 12\n"
      "-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  MeshReadReport report;
  const TriangleMesh m = read_mesh(write("quads.off", off), &report);
  EXPECT_EQ(m.triangle_count(), 12u);
  EXPECT_EQ(report.input_faces, 6u);
  EXPECT_EQ(report.polygons_triangulated, 6u);
  EXPECT_FALSE(report.open);
  EXPECT_TRUE(test::is_watertight(m));
  EXPECT_NEAR(test::signed_volume(m), 8.0, 1e-9);
  EXPECT_TRUE(test::normals_are_unit(m));
}

TEST_F(MeshReadTest, DegenerateTrianglesAreDroppedAndCounted) {
  const std::string off = std::string("OFF\n5 6 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2 0 0\n") +
                          "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"
                          "3 0 0 1\n"   // repeated index
                          "3 0 1 4\n";  // collinear: zero area
  MeshReadReport report;
  const TriangleMesh m = read_mesh(write("degenerate.off", off), &report);
  EXPECT_EQ(m.triangle_count(), 4u);
  EXPECT_EQ(report.degenerate_dropped, 2u);
  EXPECT_FALSE(report.warnings.empty());
}

TEST_F(MeshReadTest, OpenMeshLoadsWithWarning) {
  const std::string off = "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  MeshReadReport report;
  const std::string p = write("open.off", off);
  const TriangleMesh m = read_mesh(p, &report);
  EXPECT_EQ(m.triangle_count(), 3u);
  EXPECT_TRUE(report.open);
  ASSERT_FALSE(report.warnings.empty());
  EXPECT_NE(report.warnings.front().find("open.off"), std::string::npos);
}

TEST_F(MeshReadTest, NonManifoldEdgeIsReportedAndKept) {
  // Three triangles on the edge 0-1.
  const std::string off = "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n";
  MeshReadReport report;
  const TriangleMesh m = read_mesh(write("fin.off", off), &report);
  EXPECT_EQ(m.triangle_count(), 3u);
  EXPECT_TRUE(report.non_manifold);
}

TEST_F(MeshReadTest, NonManifoldObjKeepsEveryFace) {
  // OpenMesh's own importer would detach the third face ("complex edge"); ours keeps it.
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
  MeshReadReport report;
  const TriangleMesh m = read_mesh(write("fin.obj", obj), &report);
  EXPECT_EQ(m.triangle_count(), 3u);
  EXPECT_EQ(m.vertex_count(), 5u);
  EXPECT_TRUE(report.non_manifold);
}

TEST_F(MeshReadTest, OffCommentsBlankLinesAndColoursAreAccepted) {
  const std::string off =
      "# CGAL style\n\nOFF\n\n# counts\n4 4 0\n\n0 0 0 # origin\n1 0 0\n0 1 0\n0 0 1\n"
      "3 0 2 1 255 0 0\n3 0 1 3 0.5 0.5 0.5 1\n3 0 3 2\n3 1 2 3\n";
  const TriangleMesh m = read_mesh(write("cgal.off", off));
  EXPECT_EQ(m.triangle_count(), 4u);
  EXPECT_TRUE(test::is_watertight(m));
}

TEST_F(MeshReadTest, OffCountsOnHeaderLineAndCrlfAreAccepted) {
  const std::string off = "OFF 4 4 6\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n0 0 1\r\n3 0 2 1\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3\r\n";
  EXPECT_EQ(read_mesh(write("header.off", off)).triangle_count(), 4u);
  EXPECT_EQ(read_mesh(write("coff.off", std::string("C") + kTetrahedronOff)).triangle_count(), 4u);
}

TEST_F(MeshReadTest, InconsistentOrientationIsReported) {
  // Tetrahedron with one face flipped.
  const std::string off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  MeshReadReport report;
  read_mesh(write("flipped.off", off), &report);
  EXPECT_TRUE(report.inconsistent_orientation);
  EXPECT_FALSE(report.open);
}

TEST_F(MeshReadTest, ExtensionIsCaseInsensitive) {
  EXPECT_EQ(read_mesh(write("upper.OFF", kTetrahedronOff)).triangle_count(), 4u);
}

TEST_F(MeshReadTest, OpenMeshChatterBecomesWarningsNotStderr) {
  ::testing::internal::CaptureStderr();
  EXPECT_THROW(read_mesh(write("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")), InvalidInput);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(err, "");
}

// --- round trips ----------------------------------------------------------------------

class MeshRoundTripTest : public MeshReadTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(MeshRoundTripTest, CubeSurvivesWriteThenRead) {
  const TriangleMesh cube = make_cube(Vec3(1.f, 2.f, 0.5f), 2);
  const std::string p = path(std::string("cube") + GetParam());
  write_mesh(cube, p);
  MeshReadReport report;
  const TriangleMesh back = read_mesh(p, &report);
  EXPECT_EQ(back.triangle_count(), cube.triangle_count());
  EXPECT_EQ(back.vertex_count(), cube.vertex_count());
  EXPECT_TRUE(test::is_watertight(back));
  EXPECT_NEAR(test::signed_volume(back), test::signed_volume(cube), 1e-5);
  EXPECT_FALSE(report.open);
  EXPECT_FALSE(report.non_manifold);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
}

INSTANTIATE_TEST_SUITE_P(AllFormats, MeshRoundTripTest, ::testing::Values(".off", ".obj", ".ply", ".stl", ".om"),
                         [](const auto& info) { return std::string(info.param + 1); });

TEST_F(MeshReadTest, OffRoundTripIsBitExact) {
  const TriangleMesh sphere = make_sphere(0.7f, 2);
  const std::string p = path("sphere.off");
  write_mesh(sphere, p);
  const TriangleMesh back = read_mesh(p);
  ASSERT_EQ(back.vertex_count(), sphere.vertex_count());
  for (std::size_t i = 0; i < back.vertex_count(); ++i) EXPECT_EQ(back.positions[i], sphere.positions[i]);
  EXPECT_EQ(back.triangles, sphere.triangles);
}

TEST_F(MeshReadTest, WriteToMissingFolderIsIoError) {
  EXPECT_THROW(write_mesh(make_cube(Vec3(1, 1, 1)), path("no/such/dir/cube.off")), IoError);
  EXPECT_THROW(write_mesh(make_cube(Vec3(1, 1, 1)), path("no/such/dir/cube.stl")), IoError);
  EXPECT_THROW(write_mesh(make_cube(Vec3(1, 1, 1)), path("cube.xyz")), IoError);
}

// --- hashing --------------------------------------------------------------------------

TEST_F(MeshReadTest, HashFileIsStableAndSeesChanges) {
  const std::string a = write("a.off", kTetrahedronOff);
  const std::string b = write("b.off", kTetrahedronOff);
  const std::string c = write("c.off", std::string(kTetrahedronOff) + "\n");
  EXPECT_EQ(hash_file(a), hash_file(b));
  EXPECT_NE(hash_file(a), hash_file(c));
  EXPECT_EQ(hash_file(write("empty.bin", "")), 0xEF46DB3751D8E999ull);  // XXH64 of nothing, seed 0
}

TEST_F(MeshReadTest, HashMissingFileIsIoError) {
  EXPECT_THROW(hash_file(path("absent.off")), IoError);
  EXPECT_THROW(hash_file(dir_.string()), IoError);
}

// hash_model: what every front end records as a box's source (the window, the CLI, the cache).
TEST_F(MeshReadTest, HashModelOfAFileIsItsHashAndOptionsChangeIt) {
  const std::string a = write("a.off", kTetrahedronOff);
  EXPECT_EQ(hash_model(a), hash_file(a));
  EXPECT_EQ(hash_model(a, ""), hash_file(a));
  EXPECT_NE(hash_model(a, "iso=300"), hash_file(a));
  EXPECT_NE(hash_model(a, "iso=300"), hash_model(a, "iso=301"));
  EXPECT_EQ(hash_model(a, "iso=300"), hash_model(a, "iso=300"));
}

TEST_F(MeshReadTest, HashModelOfAFolderFoldsItsFilesInNameOrder) {
  fs::create_directories(dir_ / "series");
  const std::string one = write("series/IM0001", "slice one");
  const std::string two = write("series/IM0002", "slice two");
  fs::create_directories(dir_ / "series" / "sub");  // sub-folders are not read
  write("series/sub/IGNORED", "not a slice");
  const std::uint64_t expected = (0ull * 1099511628211ull ^ hash_file(one)) * 1099511628211ull ^ hash_file(two);
  const std::string series = path("series");
  EXPECT_EQ(hash_model(series), expected);
  // Another folder with the same files in the same order: the same hash (the path is not hashed).
  fs::create_directories(dir_ / "copy");
  write("copy/IM0001", "slice one");
  write("copy/IM0002", "slice two");
  EXPECT_EQ(hash_model(path("copy")), expected);
  // A changed slice is seen.
  write("copy/IM0002", "slice 2");
  EXPECT_NE(hash_model(path("copy")), expected);
  EXPECT_THROW(hash_model(path("absent")), IoError);
}

// --- hostile input found by fuzzing ---------------------------------------------------------

std::string ply_header(const std::string& format, const std::string& vertex_count, const std::string& face_count,
                       const std::string& list = "uchar int") {
  return "ply\nformat " + format + " 1.0\nelement vertex " + vertex_count +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + face_count +
         "\nproperty list " + list + " vertex_indices\nend_header\n";
}

std::string le_floats(std::initializer_list<float> values) {
  std::string out;
  for (float v : values) out.append(reinterpret_cast<const char*>(&v), 4);
  return out;
}

const char* kTetrahedronStl =
    "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
    "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
    "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";

// Finding 2: Embree aborted the bake on any coordinate of magnitude >= 1e19.
TEST_F(MeshReadTest, CoordinateBeyondTheSupportedRangeIsRejectedInEveryFormat) {
  const std::string far = "1e19";
  expect_read_error<InvalidInput>(write("far.off", "OFF\n3 1 0\n0 0 0\n" + far + " 0 0\n0 1 0\n3 0 1 2\n"),
                                  "beyond the supported range");
  expect_read_error<InvalidInput>(write("far.obj", "v 0 0 0\nv " + far + " 0 0\nv 0 1 0\nf 1 2 3\n"),
                                  "beyond the supported range");
  expect_read_error<InvalidInput>(
      write("far.ply", ply_header("ascii", "3", "1") + "0 0 0\n" + far + " 0 0\n0 1 0\n3 0 1 2\n"),
      "beyond the supported range");
  std::string stl = kTetrahedronStl;
  stl.replace(stl.find("vertex 1 0 0"), 12, "vertex " + far + " 0 0");
  expect_read_error<InvalidInput>(write("far.stl", stl), "beyond the supported range");
  // At the limit it loads.
  EXPECT_NO_THROW(read_mesh(write("edge.off", "OFF\n3 1 0\n0 0 0\n1e15 0 0\n0 1e15 0\n3 0 1 2\n")));
}

// Finding 3: OpenMesh's ASCII STL reader left unparsable coordinates uninitialised.
TEST_F(MeshReadTest, AsciiStlWithABadCoordinateIsRejectedWithItsLine) {
  int k = 0;
  for (const char* bad : {"inf", "nan", "abc", "1e39", "-inf", "0x1p3", "1.0.0"}) {
    SCOPED_TRACE(bad);
    std::string stl = kTetrahedronStl;
    stl.replace(stl.find("vertex 0 1 0"), 12, std::string("vertex 0 ") + bad + " 0");
    expect_read_error<InvalidInput>(write("bad" + std::to_string(k++) + ".stl", stl), ":5: vertex y");
  }
}

TEST_F(MeshReadTest, StlReadsAsciiAndBinaryWithSharedCorners) {
  const TriangleMesh ascii = read_mesh(write("t.stl", kTetrahedronStl));
  EXPECT_EQ(ascii.vertex_count(), 4u);  // equal corners become one vertex
  EXPECT_EQ(ascii.triangle_count(), 4u);
  MeshReadReport report;
  std::string bin(80, ' ');
  bin.replace(0, 5, "solid");  // binary files may begin with "solid" too: the size decides
  const std::uint32_t n = 1;
  bin.append(reinterpret_cast<const char*>(&n), 4);
  bin += le_floats({0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0}) + std::string(2, '\0');
  const TriangleMesh binary = read_mesh(write("b.stl", bin), &report);
  EXPECT_EQ(binary.triangle_count(), 1u);
  EXPECT_TRUE(report.open);
  // A binary file whose size disagrees with its count names both.
  expect_read_error<InvalidInput>(write("short.stl", bin.substr(0, bin.size() - 1)), "declares 1 triangles");
  expect_read_error<InvalidInput>(write("nan.stl", bin.substr(0, 84) + le_floats({0, 0, 1, NAN, 0, 0, 1, 0, 0, 0, 1, 0}) +
                                                        std::string(2, '\0')),
                                  "non-finite");
  expect_read_error<IoError>(write("cut.stl", std::string(kTetrahedronStl).substr(0, 100)), "truncated");
}

// Finding 4: OpenMesh's PLY reader allocated whatever a header declared, spun without an
// end_header, and accepted a face count larger than the faces present.
TEST_F(MeshReadTest, PlyCountsBeyondTheFileAreRejectedBeforeAllocating) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expect_read_error<InvalidInput>(write("u64.ply", ply_header("ascii", "18446744073709551615", "1") + body), "more than");
  expect_read_error<InvalidInput>(write("i64.ply", ply_header("ascii", "9223372036854775807", "1") + body), "more than");
  expect_read_error<InvalidInput>(write("over.ply", ply_header("ascii", "18446744073709551616", "1") + body),
                                  "not an unsigned integer");
  expect_read_error<InvalidInput>(write("neg.ply", ply_header("ascii", "-3", "1") + body), "not an unsigned integer");
  const std::string vertices = le_floats({0, 0, 0, 1, 0, 0, 0, 1, 0});
  const std::string face = std::string("\x03", 1) + std::string("\0\0\0\0\1\0\0\0\2\0\0\0", 12);
  expect_read_error<InvalidInput>(
      write("faces.ply", ply_header("binary_little_endian", "3", "99999999999") + vertices + face), "more than");
  // Lists whose count runs past the file, or is negative.
  const std::string big_list = std::string("\xff\xff\xff\x7f", 4) + std::string(12, '\0');
  expect_read_error<InvalidInput>(
      write("list.ply", ply_header("binary_little_endian", "3", "1", "int int") + vertices + big_list),
      "runs past the end");
  const std::string negative = std::string("\xfb\xff\xff\xff", 4) + std::string(12, '\0');
  expect_read_error<InvalidInput>(
      write("negative_list.ply", ply_header("binary_little_endian", "3", "1", "int int") + vertices + negative),
      "negative");
  expect_read_error<InvalidInput>(write("negative_ascii.ply", ply_header("ascii", "3", "1") + "0 0 0\n1 0 0\n0 1 0\n-5 0 1 2\n"),
                                  "negative");
}

TEST_F(MeshReadTest, PlyWithoutVerticesOrEndHeaderIsRejected) {
  expect_read_error<InvalidInput>(write("none.ply", ply_header("ascii", "0", "1") + "3 0 1 2\n"), "out of range");
  expect_read_error<InvalidInput>(write("noend.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"),
                                  "end_header");
  std::string spin = "ply\nformat ascii 1.0\n";
  for (int i = 0; i < 2000; ++i) spin += "comment no end\n";
  expect_read_error<InvalidInput>(write("spin.ply", spin), "end_header");
}

TEST_F(MeshReadTest, PlyDeclaringMoreFacesThanItHoldsIsRejected) {
  expect_read_error<InvalidInput>(
      write("more.ply", ply_header("ascii", "3", "2") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), "declares 2 entries");
  expect_read_error<InvalidInput>(
      write("short_face.ply", ply_header("ascii", "3", "1") + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"), "expected 3 values");
  expect_read_error<InvalidInput>(
      write("extra.ply", ply_header("ascii", "3", "1") + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n"), "after the last");
  expect_read_error<InvalidInput>(write("nan.ply", ply_header("ascii", "3", "1") + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n"),
                                  "not a finite float");
}

TEST_F(MeshReadTest, PlyVariantsRead) {
  // Big-endian binary, double coordinates, extra properties and elements, vertex_index.
  std::string be = "ply\nformat binary_big_endian 1.0\ncomment x\nelement vertex 3\nproperty double x\n"
                   "property double y\nproperty double z\nproperty uchar red\nelement face 1\n"
                   "property list uchar ushort vertex_index\nelement edge 1\nproperty int a\nend_header\n";
  const auto be64 = [](double v) {
    std::string b(reinterpret_cast<const char*>(&v), 8);
    return std::string(b.rbegin(), b.rend());
  };
  std::string body;
  const double xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}};
  for (const auto& v : xyz) body += be64(v[0]) + be64(v[1]) + be64(v[2]) + std::string(1, '\x7f');
  body += std::string("\x03\x00\x00\x00\x01\x00\x02", 7) + std::string("\0\0\0\x05", 4);
  const TriangleMesh mesh = read_mesh(write("be.ply", be + body));
  ASSERT_EQ(mesh.triangle_count(), 1u);
  EXPECT_EQ(mesh.positions[2], Vec3(0, 2, 0));
}

// OpenMesh's OBJ reader opened whatever a "mtllib" line names (a device file: a read without
// end) and skipped unparsable vertex lines; ours opens nothing else and names the line.
TEST_F(MeshReadTest, ObjNeverOpensTheFilesItNames) {
  const TriangleMesh m = read_mesh(write("mtl.obj", "mtllib /dev/zero\nmtllib ../../../../dev/urandom\nusemtl x\n"
                                                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\ng a\ns 1\n"
                                                    "f 1/1/1 2/1/1 3/1/1\nf -3 -1 -2\n"));
  EXPECT_EQ(m.triangle_count(), 2u);
}

TEST_F(MeshReadTest, ObjBadStatementIsRejectedWithItsLine) {
  expect_read_error<InvalidInput>(write("v.obj", "v 0 0 0\nv 1 abc 0\nv 0 1 0\nf 1 2 3\n"), ":2: vertex 1");
  expect_read_error<InvalidInput>(write("f.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"), ":4: face 0");
  expect_read_error<InvalidInput>(write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), ":4: face 0");
  expect_read_error<InvalidInput>(write("big.obj", "v 0 0 0\nv 1 1e39 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
}

} // namespace
} // namespace hb
