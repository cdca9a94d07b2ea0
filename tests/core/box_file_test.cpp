// .hbox round trip and every way a box file can be bad.
#include "errors.h"
#include "scene/bake.h"
#include "store/box_file.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <xxhash.h>
#include <cmath>
#include <cstring>
#include <limits>
#include <filesystem>
#include <fstream>
#include <random>

namespace hb {
namespace {

namespace fs = std::filesystem;

class BoxFileTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hb_box_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    mesh_ = make_sphere(1.f, 3);
    BakeOptions options;
    options.params = {6, 4};
    scene_ = bake_scene(mesh_, {}, options, {"sphere.off", 1234u, mesh_.triangle_count(), 2.f});
    path_ = (dir_ / "sphere.hbox").string();
    save_box_file(scene_, path_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<char> bytes() const {
    std::ifstream in(path_, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  std::string write(const std::string& name, const std::vector<char>& data) const {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary).write(data.data(), std::streamsize(data.size()));
    return p;
  }
  void expect_invalid(const std::string& path, const std::string& cause, bool verify = true) const {
    try {
      load_box_file(path, LoadOptions{verify});
      FAIL() << "no error for " << path;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(cause), std::string::npos) << e.what();
    }
  }

  // Layout of this one-box version-7 file (box_file_format.h): the prefix, the box's entry, the
  // surface, piece-id, scene-grid, budget-report and normal-map sections.
  static constexpr std::size_t kPrefix = 8 + 4 + 4 + 8 + 8 + 4 + 4 + 10;  // path "sphere.off"
  static constexpr std::size_t kCenter = kPrefix + 12, kAxes = kCenter + 12, kHalf = kAxes + 36;
  static constexpr std::size_t kHeaderEnd = kPrefix + 72 + 24 + 28 + 28 + 24 + 24 + 24 + 24 + 28;
  static void put_float(std::vector<char>& data, std::size_t at, float v) { std::memcpy(&data[at], &v, 4); }
  // Re-signs the header, as a file corrupted before it was written would be signed.
  static void resign(std::vector<char>& data) {
    const std::uint64_t h = XXH3_64bits(data.data(), kHeaderEnd);
    std::memcpy(&data[kHeaderEnd], &h, 8);
  }
  // The saved file with one OBB float replaced, re-signed.
  std::string with_float(const std::string& name, std::size_t at, float v) const {
    auto data = bytes();
    put_float(data, at, v);
    resign(data);
    return write(name, data);
  }

  fs::path dir_;
  TriangleMesh mesh_;
  BoxScene scene_;
  std::string path_;
};

TEST_F(BoxFileTest, RoundTripGivesIdenticalAnswers) {
  const BoxScene loaded = load_box_file(path_);
  ASSERT_EQ(loaded.parts().boxes.size(), 1u);
  EXPECT_EQ(loaded.parts().source.mesh_hash, 1234u);
  EXPECT_EQ(loaded.parts().source.mesh_path, "sphere.off");
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-2.f, 2.f);
  for (int i = 0; i < 200; ++i) {
    const Segment s{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)) * 0.3f};
    const Contact a = scene_.query(s, {}), b = loaded.query(s, {});
    ASSERT_EQ(a.contact, b.contact);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.force, b.force);
  }
}

TEST_F(BoxFileTest, HugePageCopyGivesIdenticalAnswers) {
  LoadOptions options;
  options.huge_pages = true;
  const BoxScene mapped = load_box_file(path_);
  BoxScene copied = load_box_file(path_, options);
  ASSERT_EQ(copied.parts().boxes.size(), 1u);
  EXPECT_NE(copied.parts().boxes[0].table(), mapped.parts().boxes[0].table());
  const BoxScene kept = copied;  // the copy stays alive with any scene sharing it
  copied = BoxScene();
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2.f, 2.f);
  for (int i = 0; i < 200; ++i) {
    const Segment s{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)) * 0.3f};
    const Contact a = mapped.query(s, {}), b = kept.query(s, {});
    ASSERT_EQ(a.contact, b.contact);
    EXPECT_EQ(a.depth, b.depth);
    EXPECT_EQ(a.force, b.force);
  }
}

TEST_F(BoxFileTest, MissingFileIsAnIoError) { EXPECT_THROW(load_box_file((dir_ / "nope.hbox").string()), IoError); }

TEST_F(BoxFileTest, ForeignFileIsRejected) {
  expect_invalid(write("foreign.hbox", std::vector<char>(4096, 'x')), "not a HapticBox box file");
}

TEST_F(BoxFileTest, TruncatedFileIsRejected) {
  auto data = bytes();
  data.resize(data.size() / 2);
  expect_invalid(write("truncated.hbox", data), "truncated");
  data.resize(40);
  expect_invalid(write("truncated2.hbox", data), "truncated");
}

TEST_F(BoxFileTest, CorruptTableIsRejected) {
  auto data = bytes();
  data[data.size() - 100] ^= 0x5a;
  expect_invalid(write("corrupt.hbox", data), "checksum");
}

TEST_F(BoxFileTest, CorruptHeaderIsRejected) {
  auto data = bytes();
  data[30] ^= 0x01;  // inside the mesh hash
  expect_invalid(write("corrupt_header.hbox", data), "checksum");
}

TEST_F(BoxFileTest, WrongVersionIsRejected) {
  auto data = bytes();
  data[8] = 99;
  expect_invalid(write("version.hbox", data), "version 99");
}

TEST_F(BoxFileTest, ResignedUnchangedFileLoads) {
  auto data = bytes();
  resign(data);  // the layout constants above are right
  EXPECT_NO_THROW(load_box_file(write("resigned.hbox", data), LoadOptions{true}));
}

// Found by fuzzing: a box whose OBB holds NaN, Inf or 3.4e38 loaded and crashed the query.
TEST_F(BoxFileTest, NonFiniteOrHugeObbAxisIsRejectedAtLoad) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  int k = 0;
  for (float v : {nan, inf, -inf, 3.4e38f}) {
    SCOPED_TRACE(v);
    expect_invalid(with_float("axis" + std::to_string(k++) + ".hbox", kAxes + 4, v), "box 0", false);
  }
}

TEST_F(BoxFileTest, NonOrthonormalObbAxesAreRejectedAtLoad) {
  expect_invalid(with_float("skew.hbox", kAxes, 1.5f), "not orthonormal", false);
  auto data = bytes();
  for (int r = 0; r < 3; ++r) {  // the first axis reversed: orthonormal but left-handed
    float v;
    std::memcpy(&v, &data[kAxes + 4 * r], 4);
    put_float(data, kAxes + 4 * r, -v);
  }
  resign(data);
  expect_invalid(write("left.hbox", data), "right-handed", false);
}

TEST_F(BoxFileTest, NanNegativeOrZeroHalfExtentIsRejectedAtLoad) {
  int k = 0;
  for (float v : {std::numeric_limits<float>::quiet_NaN(), -0.5f, 0.f, std::numeric_limits<float>::infinity()}) {
    SCOPED_TRACE(v);
    expect_invalid(with_float("half" + std::to_string(k++) + ".hbox", kHalf + 4, v), "half extent", false);
  }
}

TEST_F(BoxFileTest, NonFiniteObbCentreIsRejectedAtLoad) {
  expect_invalid(with_float("centre.hbox", kCenter + 8, std::numeric_limits<float>::quiet_NaN()), "centre", false);
  expect_invalid(with_float("far.hbox", kCenter, 1e30f), "centre", false);
}

TEST_F(BoxFileTest, BytesAfterTheLastSectionAreRejectedByVerify) {
  auto data = bytes();
  data.insert(data.end(), 100, '\0');
  const std::string p = write("appended.hbox", data);
  expect_invalid(p, "100 bytes after the last section", true);
  EXPECT_NO_THROW(load_box_file(p, LoadOptions{false}));  // lazy opening reads no table end
}

TEST(HapticBoxGeometryTest, ConstructorRefusesAnObbTheQueryCannotUse) {
  Obb bad;
  bad.half = Vec3(1.f, std::numeric_limits<float>::quiet_NaN(), 1.f);
  EXPECT_THROW(HapticBox(bad, BoxParams{2, 2}, std::vector<Sample>(BoxParams{2, 2}.sample_count())), InvalidInput);
  EXPECT_EQ(obb_problem(Obb{}), "");
}

} // namespace
} // namespace hb
