// .hbox round trip and every way a box file can be bad.
#include "errors.h"
#include "haptic_box/bake.h"
#include "haptic_box/box_file.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
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

  fs::path dir_;
  TriangleMesh mesh_;
  BoxScene scene_;
  std::string path_;
};

TEST_F(BoxFileTest, RoundTripGivesIdenticalAnswers) {
  const BoxScene loaded = load_box_file(path_);
  ASSERT_EQ(loaded.boxes().size(), 1u);
  EXPECT_EQ(loaded.source().mesh_hash, 1234u);
  EXPECT_EQ(loaded.source().mesh_path, "sphere.off");
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
  ASSERT_EQ(copied.boxes().size(), 1u);
  EXPECT_NE(copied.boxes()[0].table(), mapped.boxes()[0].table());
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

} // namespace
} // namespace hb
