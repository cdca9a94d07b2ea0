// Hostile input to the readers of volumes, CAD solids, scenes and piece files, end
// to end through `hapticbox`: each damaged file is a valid one written here (the CT phantom,
// a sphere exported through Assimp, the real pydicom CT) with one fault of a class the fuzzing
// found; the command must exit non-zero (never by a signal), name the file and give the cause.
#include "run_cli.h"
#include "volume_phantom.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkImageData.h>
#include <zlib.h>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#ifdef HB_HAVE_ASSIMP
#include "../vtk_pipelines/stored_zip.h"
#include "scene_reader.h"
#endif
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif

namespace {

namespace fs = std::filesystem;
using Result = hb::test::CommandResult;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string real_dicom(const std::string& fetched, const std::string& debian) {
  const fs::path a = fs::path(HB_DATASETS_DIR) / "volumes" / "dicom" / fetched;
  return fs::exists(a) ? a.string() : "/usr/lib/python3/dist-packages/pydicom/data/test_files/" + debian;
}

class HostileModelsTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_cli_hostile_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const hb::vtk::CtPhantom phantom;
    hb::vtk::write_volume(hb::vtk::make_ct_phantom(phantom), phantom.index_to_mm(), path("phantom.mha"));
    hb::vtk::write_volume(hb::vtk::make_ct_phantom(phantom), phantom.index_to_mm(), path("phantom.nrrd"));
    hb::vtk::write_volume(hb::vtk::make_ct_phantom(phantom), phantom.index_to_mm(), path("phantom.nii"));
    const std::string mha = slurp(path("phantom.mha"));
    const std::size_t cut = mha.find("ElementDataFile = LOCAL\n") + std::strlen("ElementDataFile = LOCAL\n");
    mha_header_ = mha.substr(0, cut);
    mha_data_ = mha.substr(cut);
    const std::string nrrd = slurp(path("phantom.nrrd"));
    const std::size_t end = nrrd.find("\n\n") + 2;
    nrrd_header_ = nrrd.substr(0, end);
    nrrd_data_ = nrrd.substr(end);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static Result run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string write(const std::string& name, const std::string& bytes) {
    fs::create_directories(fs::path(path(name)).parent_path());
    std::ofstream(path(name), std::ios::binary) << bytes;
    return path(name);
  }
  static std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
  }
  // `info FILE` must fail with exit code 1 (no signal, no hang), naming the file, the cause
  // containing `cause`.
  static void expect_refused(const std::string& file, const std::string& cause, const std::string& extra = "") {
    const Result r = run("info " + file + extra);
    EXPECT_EQ(r.code, 1) << file << "\n" << r.err;
    EXPECT_NE(r.err.find("hapticbox: error: " + file + ": "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(cause), std::string::npos) << "expected '" << cause << "' in: " << r.err;
    const std::size_t colon = r.err.find(file + ": ");
    if (colon != std::string::npos) EXPECT_GT(r.err.size(), colon + file.size() + 4) << "empty cause: " << r.err;
  }
  static fs::path dir_;
  static std::string mha_header_, mha_data_, nrrd_header_, nrrd_data_;
};
fs::path HostileModelsTest::dir_;
std::string HostileModelsTest::mha_header_, HostileModelsTest::mha_data_, HostileModelsTest::nrrd_header_,
    HostileModelsTest::nrrd_data_;

TEST_F(HostileModelsTest, TheUndamagedFilesLoad) {
  for (const char* f : {"phantom.mha", "phantom.nrrd", "phantom.nii"}) {
    const Result r = run("info " + path(f));
    EXPECT_EQ(r.code, 0) << f << ": " << r.err;
  }
}

TEST_F(HostileModelsTest, NrrdHeaderFaultsAreNamedBeforeTheReaderRuns) {
  // No sizes line: VTK's reader crashed.
  expect_refused(write("nosizes.nrrd", replaced(nrrd_header_, "sizes: 96 96 60\n", "") + nrrd_data_), "no 'sizes:' field");
  expect_refused(write("negative.nrrd", replaced(nrrd_header_, "sizes: 96 96 60", "sizes: -1 96 60") + nrrd_data_),
                 "each size must be a whole number");
  // A data-file pattern of step 0 looped forever.
  expect_refused(write("step0.nhdr", replaced(nrrd_header_, "encoding: raw\n", "encoding: raw\ndata file: slice%03d.raw 1 60 0\n")),
                 "step 0");
  // Garbage bytes in the header looped.
  expect_refused(write("garbage.nrrd", replaced(nrrd_header_, "kinds:", std::string("ki\x01\x02nds:", 9)) + nrrd_data_),
                 "is not text");
  // A data file LIST in a file that holds its voxels: the voxels were read as file names, and
  // 64 KB of them printed as one; now the first line of bytes is named, cut and escaped.
  const std::string header = replaced(nrrd_header_, "encoding: raw\n", "encoding: raw\ndata file: LIST\n");
  const std::string list = write("list.nrrd", header.substr(0, header.size() - 1) + nrrd_data_);
  expect_refused(list, "after \"data file: LIST\", is not a file name");
  const Result r = run("info " + list);
  EXPECT_LT(r.err.size(), 2000u) << r.err.size();
  for (char c : r.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7F)) << "raw byte " << int((unsigned char)c);
}

TEST_F(HostileModelsTest, ShortOrMisencodedVolumeDataIsAnErrorNeverZeros) {
  expect_refused(write("short.nrrd", nrrd_header_ + nrrd_data_.substr(0, nrrd_data_.size() / 2)), "the volume is truncated");
  expect_refused(write("text.nrrd", replaced(nrrd_header_, "encoding: raw", "encoding: text") + nrrd_data_), "not a number");
  expect_refused(write("short.mha", mha_header_ + mha_data_.substr(0, mha_data_.size() - 1000)), "the volume is truncated");
  // Data shifted by an inserted chunk: as long as the header's sizes plus a few bytes.
  expect_refused(write("long.nrrd", nrrd_header_ + nrrd_data_.substr(0, 5000) + "xyzw" + nrrd_data_.substr(5000)),
                 "the data holds more: the header's sizes or type are wrong, or the data was altered");
  // A corrupt zlib stream: header says compressed, data is raw.
  expect_refused(write("zlib.mha", replaced(mha_header_, "CompressedData = False", "CompressedData = True") + mha_data_), "damaged");
  // A truncated NIfTI.
  const std::string nii = slurp(path("phantom.nii"));
  expect_refused(write("short.nii", nii.substr(0, nii.size() - 5000)), "the volume is truncated");
}

TEST_F(HostileModelsTest, MetaImageHeaderFaultsAreNamed) {
  expect_refused(write("ndims.mha", replaced(mha_header_, "NDims = 3", "NDims = 2147483648") + mha_data_), "NDims");
  expect_refused(write("pattern0.mhd", replaced(mha_header_, "ElementDataFile = LOCAL", "ElementDataFile = s%03d.raw 1 60 0")),
                 "step 0");
  expect_refused(write("pattern-1.mhd", replaced(mha_header_, "ElementDataFile = LOCAL", "ElementDataFile = s%03d.raw 1 60 -1")),
                 "never reaches");
  expect_refused(write("type.mha", replaced(mha_header_, "MET_SHORT", "MET_SHORT_ARRAY") + mha_data_), "not a scalar type");
}

TEST_F(HostileModelsTest, NiftiHeaderFieldsAreChecked) {
  const std::string nii = slurp(path("phantom.nii"));
  auto with_short = [&](std::size_t at, std::int16_t v) {
    std::string b = nii;
    std::memcpy(b.data() + at, &v, 2);
    return b;
  };
  auto with_float = [&](std::size_t at, float v) {
    std::string b = nii;
    std::memcpy(b.data() + at, &v, 4);
    return b;
  };
  expect_refused(write("complex.nii", with_short(72, 128)), "bitpix");  // bitpix no longer matches
  std::string complex = with_short(70, 1792);  // datatype complex128: VTK crashed
  expect_refused(write("c128.nii", complex), "complex128");
  expect_refused(write("offset0.nii", with_float(108, 0.f)), "vox_offset");
  expect_refused(write("pixdim.nii", with_float(80, std::numeric_limits<float>::quiet_NaN())), "pixdim[1]");
  expect_refused(write("dims.nii", with_short(42, -5)), "dim[1]");
  // An infinite value scaling made every voxel one value: any label gave the same surface.
  expect_refused(write("slope.nii", with_float(112, std::numeric_limits<float>::infinity())), "NIfTI scl_slope (the value scaling) is inf");
  std::string inter = with_float(112, 2.f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(inter.data() + 116, &nan, 4);
  expect_refused(write("inter.nii", inter), "NIfTI scl_inter (the value offset) is nan");
}

TEST_F(HostileModelsTest, DicomSizesAndEmptyTagsAreCheckedBeforeTheParser) {
  const std::string ct = slurp(real_dicom("CT_small.dcm", "CT_small.dcm"));
  ASSERT_GT(ct.size(), 1000u);
  // Rows (0028,0010) US: 65535 rows with the pixel data of 128.
  const std::string rows_tag("\x28\x00\x10\x00US\x02\x00", 8);
  std::string big = ct;
  const std::size_t at = big.find(rows_tag);
  ASSERT_NE(at, std::string::npos);
  big[at + 8] = '\xff';
  big[at + 9] = '\xff';
  expect_refused(write("rows/a.dcm", big), "65535 rows");
  // RescaleSlope present but blank (spaces): VTK's DICOM parser crashed on an empty value.
  const std::string slope_tag("\x28\x00\x53\x10" "DS", 6);
  std::string blank = ct;
  const std::size_t s = blank.find(slope_tag);
  ASSERT_NE(s, std::string::npos);
  const std::size_t len = std::size_t((unsigned char)blank[s + 6]) | std::size_t((unsigned char)blank[s + 7]) << 8;
  for (std::size_t i = 0; i < len; ++i) blank[s + 8 + i] = ' ';
  expect_refused(write("slope/a.dcm", blank), "RescaleSlope (0028,1053) is empty");
}

TEST_F(HostileModelsTest, ADicomFileReadsItsOwnSeriesAndExtensionlessFilesAreDicom) {
  // CT_small.dcm beside MR_small.dcm: its own series has one slice (it read the MR file and
  // failed as a mixed series).
  fs::create_directories(path("pair"));
  fs::copy_file(real_dicom("CT_small.dcm", "CT_small.dcm"), path("pair/CT_small.dcm"));
  fs::copy_file(real_dicom("MR_small.dcm", "MR_small.dcm"), path("pair/MR_small.dcm"));
  expect_refused(path("pair/CT_small.dcm"), "a single DICOM slice is not a volume (a series needs at least 2 slices of its SeriesInstanceUID");
  // A series of files without extensions, opened through one of them.
  const std::string series = real_dicom("CT5N", "dicomdirtests/98892001/CT5N");
  fs::create_directories(path("ct5n"));
  for (const auto& e : fs::directory_iterator(series)) fs::copy_file(e.path(), path("ct5n") + "/" + e.path().filename().string());
  const std::string one = fs::directory_iterator(path("ct5n"))->path().string();
  ASSERT_TRUE(fs::path(one).extension().empty()) << one;
  const Result r = run("info --json " + one + " --volume iso=-500");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["format"], "DICOM series");
}

TEST_F(HostileModelsTest, JsonOnStdoutIsOnlyJson) {
  const Result r = run("info --json " + path("phantom.mha") + " --volume smooth=1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NO_THROW(nlohmann::json::parse(r.out)) << r.out;
}

TEST_F(HostileModelsTest, ReaderLimitsStopAReaderAndSaySo) {
  const Result r = hb::test::run_cli("info " + path("phantom.mha") + " --volume smooth=1000", dir_.string(), "HB_READER_TIMEOUT_S=0.1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find(path("phantom.mha") + ": the MetaImage reader failed on this file (it was still running after 0.1 s"),
            std::string::npos) << r.err;
}

TEST_F(HostileModelsTest, PieceFileFaultsNameTheFile) {
  hb::write_mesh(hb::make_sphere(1.f, 1), path("sphere.off"));
  // `element vertex x` was read as 0 vertices.
  const std::string bad_count = write("x.ply", "ply\nformat ascii 1.0\nelement vertex x\nproperty float x\nelement face 1\n"
                                               "property list uchar int vertex_indices\nproperty int piece\nend_header\n3 0 1 2 0\n");
  Result r = run("bake " + path("sphere.off") + " --pieces " + bad_count + " -o " + path("s.hbox") + " -m 4 -n 4 --cache none");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find(bad_count + ": bad element line 'element vertex x'"), std::string::npos) << r.err;
  // A face count far beyond the file: refused before any allocation, naming the file.
  const std::string huge = write("huge.ply", "ply\nformat binary_little_endian 1.0\nelement face 4000000000000\n"
                                             "property int piece\nend_header\n0000");
  r = run("bake " + path("sphere.off") + " --pieces " + huge + " -o " + path("s.hbox") + " -m 4 -n 4 --cache none");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find(huge + ": the face element claims 4000000000000 faces"), std::string::npos) << r.err;
  // A .vtp of another mesh's pieces: the mismatch names the piece file.
  hb::write_mesh(hb::make_sphere(1.f, 2), path("finer.off"));
  r = run("decompose " + path("finer.off") + " --max-pieces 2 --lines 1000 --leaves 4 -o " + path("finer.vtp"));
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("bake " + path("sphere.off") + " --pieces " + path("finer.vtp") + " -o " + path("s.hbox") + " -m 4 -n 4 --cache none");
  EXPECT_NE(r.code, 0) << r.err;
  EXPECT_NE(r.err.find(path("finer.vtp") + ": "), std::string::npos) << r.err;
}

TEST_F(HostileModelsTest, VtpCountsAndBlockHeadersAreHeldToTheFile) {
  // VTK's XML reader crashed when the cell counts disagreed with the arrays, and allocated
  // gigabytes for a damaged compressed-block header.
  hb::write_mesh(hb::make_sphere(1.f, 2), path("v.off"));
  Result r = run("decompose " + path("v.off") + " --max-pieces 2 --lines 1000 --leaves 4 -o " + path("v.vtp"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string vtp = slurp(path("v.vtp"));
  r = run("info " + path("v.vtp"));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::size_t n = vtp.find("NumberOfPoints=\"");
  ASSERT_NE(n, std::string::npos);
  std::string counts = vtp;
  counts.replace(n + 16, 1, "9");  // a different point count, same length
  if (counts == vtp) counts.replace(n + 16, 1, "8");
  expect_refused(write("counts.vtp", counts), "the counts disagree with the arrays");
  std::string blocks = vtp;
  const std::size_t data = blocks.find('_', blocks.find("<AppendedData")) + 1;
  const std::uint32_t many = 0x40000000u;
  std::memcpy(blocks.data() + data, &many, 4);  // the first array's number of blocks
  expect_refused(write("blocks.vtp", blocks), "compressed blocks, more than the file holds");
}

TEST_F(HostileModelsTest, TrajectoryRefusesALogWithNonFiniteOrUnrenderableRecords) {
  const std::string log = path("run.hbslog");
  Result r = run("servo plane --device virtual --seconds 0.05 --record " + log);
  ASSERT_EQ(r.code, 0) << r.err;
  std::string bytes = slurp(log);
  ASSERT_GE(bytes.size(), 128u);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bytes.data() + bytes.size() - 64 + 8, &nan, 4);  // the last record's position x
  write("nan.hbslog", bytes);
  r = run("trajectory " + path("nan.hbslog") + " plane -o " + path("t.vtp"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find(path("nan.hbslog") + ": record "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("non-finite position"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("t.vtp")));
  // A finite force no device renders (1e30 N) was written as ForceMagnitude = inf.
  bytes = slurp(log);
  const float huge = 1e30f;
  std::memcpy(bytes.data() + bytes.size() - 64 + 20, &huge, 4);  // the last record's force x
  write("huge.hbslog", bytes);
  r = run("trajectory " + path("huge.hbslog") + " plane -o " + path("t.vtp"));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find(path("huge.hbslog") + ": record "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("has a force of 1e+30 N, beyond the 8 N its device"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("t.vtp")));
}

#ifdef HB_HAVE_ASSIMP
using hb::test::three_mf;

const char* const kTetra =
    "<mesh><vertices><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"10\" y=\"0\" z=\"0\"/><vertex x=\"0\" y=\"10\" z=\"0\"/>"
    "<vertex x=\"0\" y=\"0\" z=\"10\"/></vertices><triangles><triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle v1=\"0\" v2=\"1\" v3=\"3\"/>"
    "<triangle v1=\"1\" v2=\"2\" v3=\"3\"/><triangle v1=\"0\" v2=\"3\" v3=\"2\"/></triangles></mesh>";

TEST_F(HostileModelsTest, SceneContainersAreCheckedBeforeAssimp) {
  hb::vtk::write_scene(hb::make_sphere(10.f, 2), path("s.glb"));
  std::string glb = slurp(path("s.glb"));
  const std::uint32_t huge = 0xFFFFFFF8u;  // the JSON chunk's length: Assimp allocated 4 GB
  std::memcpy(glb.data() + 12, &huge, 4);
  expect_refused(write("chunk.glb", glb), "GLB chunk 0 claims 4294967288 bytes");
  // 20,000 nested nodes: Assimp's recursion overflowed the stack.
  std::string nodes;
  for (int i = 0; i < 20000; ++i) nodes += std::string(i ? "," : "") + "{\"children\":[" + std::to_string(i + 1) + "]}";
  nodes += ",{}";
  expect_refused(write("deep.gltf", "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[" + nodes + "]}"),
                 "nested 257 deep");
  expect_refused(write("cycle.gltf", "{\"asset\":{\"version\":\"2.0\"},\"nodes\":[{\"children\":[1]},{\"children\":[0]}]}"),
                 "cycle");
  // An accessor past its buffer.
  expect_refused(write("accessor.gltf",
                       "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":12,\"uri\":\"data:application/octet-stream;base64,"
                       "AAAAAAAAAAAAAAAA\"}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":12}],\"accessors\":[{\"bufferView\":0,"
                       "\"componentType\":5126,\"count\":1000,\"type\":\"VEC3\"}]}"),
                 "runs past its end");
  // Collada: a non-number in an index list cost gigabytes; a wrong float_array count crashed.
  hb::vtk::write_scene(hb::make_sphere(10.f, 2), path("s.dae"));
  const std::string dae = slurp(path("s.dae"));
  const std::size_t p = dae.find("<p>");
  ASSERT_NE(p, std::string::npos);
  expect_refused(write("index.dae", dae.substr(0, p + 3) + "1x2 " + dae.substr(p + 3)), "Collada index in <p> is '1x2', not a whole number");
  const std::size_t count = dae.find("count=\"", dae.find("<float_array"));
  ASSERT_NE(count, std::string::npos);
  expect_refused(write("count.dae", dae.substr(0, count + 7) + "9" + dae.substr(count + 7)), "declares");
  const std::string header = "<?xml version=\"1.0\"?><model unit=\"millimeter\" xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\"><resources>";
  const std::string good = header + "<object id=\"1\" type=\"model\">" + kTetra + "</object></resources><build><item objectid=\"1\"/></build></model>";
  const Result ok = run("info " + write("good.3mf", three_mf(good)));
  EXPECT_EQ(ok.code, 0) << ok.err;
  // A transform of 3 numbers was read into an uninitialised matrix.
  expect_refused(write("transform.3mf", three_mf(replaced(good, "<item objectid=\"1\"/>", "<item objectid=\"1\" transform=\"1 0 0\"/>"))),
                 "holds 3 numbers, not 12");
  // A component that contains itself: Assimp recursed without end.
  expect_refused(write("self.3mf", three_mf(header + "<object id=\"1\" type=\"model\">" + kTetra + "</object><object id=\"2\" type=\"model\">"
                                            "<components><component objectid=\"2\"/></components></object></resources><build>"
                                            "<item objectid=\"2\"/></build></model>")),
                 "contains itself");
}
#endif

#ifdef HB_HAVE_OCCT
TEST_F(HostileModelsTest, CadFacesThatFailToTranslateAreCountedAndRefusedUnlessAccepted) {
  hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
  std::string step = slurp(path("solid.step"));
  // Point one ADVANCED_FACE at a surface id that does not exist.
  const std::size_t face = step.find("ADVANCED_FACE");
  ASSERT_NE(face, std::string::npos);
  const std::size_t close = step.find("),#", face);
  ASSERT_NE(close, std::string::npos);
  const std::size_t end = step.find(',', close + 3);
  step.replace(close + 2, end - close - 2, "#999999");
  const std::string bad = write("lost.step", step);
  const Result r = run("info " + bad);
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find(bad + ": "), std::string::npos) << r.err;
  if (r.err.find("faces lost") != std::string::npos) {
    EXPECT_NE(r.err.find("--cad accept-lost-faces"), std::string::npos) << r.err;
    const Result kept = run("info " + bad + " --cad accept-lost-faces");
    EXPECT_EQ(kept.code, 0) << kept.err;
    EXPECT_NE(kept.err.find("faces lost"), std::string::npos) << kept.err;
  }
}
#endif

} // namespace
