// Loads the real datasets (datasets/fetch.sh puts CGAL's .off meshes in datasets/data/meshes).
#include "mesh/mesh_io.h"

#include "errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>

namespace hb {
namespace {

namespace fs = std::filesystem;

const fs::path kMeshes = fs::path(HB_DATASETS_DIR) / "meshes";

/// Loads every dataset once for the whole suite.
class DatasetsTest : public ::testing::Test {
protected:
  struct Loaded {
    TriangleMesh mesh;
    MeshReadReport report;
    std::string error;  ///< what() of the hb::Error thrown, if any
  };

  static void SetUpTestSuite() {
    if (!fs::is_directory(kMeshes)) return;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(kMeshes))
      if (entry.path().extension() == ".off") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
      Loaded l;
      try {
        l.mesh = read_mesh(file.string(), &l.report);
      } catch (const Error& e) {  // a bad dataset must throw our error, never crash
        l.error = e.what();
      }
      loaded_->emplace(file.stem().string(), std::move(l));
    }
  }
  static void TearDownTestSuite() { loaded_->clear(); }

  void SetUp() override {
    if (!fs::is_directory(kMeshes))
      GTEST_SKIP() << kMeshes << " is absent: run datasets/fetch.sh to test the real datasets";
  }

  static std::map<std::string, Loaded>* loaded_;
};

std::map<std::string, DatasetsTest::Loaded>* DatasetsTest::loaded_ = new std::map<std::string, Loaded>;

TEST_F(DatasetsTest, ReferenceMeshesLoadAsClosedMeshes) {
  for (const char* name : {"armadillo", "elephant", "fandisk", "femur", "bunny00", "cow", "knot1"}) {
    SCOPED_TRACE(name);
    const auto it = loaded_->find(name);
    ASSERT_NE(it, loaded_->end()) << "missing dataset";
    EXPECT_EQ(it->second.error, "");
    EXPECT_GT(it->second.mesh.triangle_count(), 1000u);
    EXPECT_FALSE(it->second.report.open);
    EXPECT_FALSE(it->second.report.non_manifold);
    EXPECT_EQ(it->second.mesh.normals.size(), it->second.mesh.vertex_count());
  }
}

TEST_F(DatasetsTest, EveryDatasetLoadsOrFailsCleanly) {
  std::size_t ok = 0;
  for (const auto& [name, l] : *loaded_) {
    if (l.error.empty()) {
      ++ok;
      std::cout << "  " << name << ": " << l.mesh.triangle_count() << " triangles, " << l.mesh.vertex_count()
                << " vertices" << (l.report.open ? ", open" : "") << (l.report.non_manifold ? ", non-manifold" : "")
                << (l.report.polygons_triangulated ? ", polygons triangulated" : "")
                << (l.report.degenerate_dropped ? ", " + std::to_string(l.report.degenerate_dropped) + " degenerate dropped" : "")
                << "\n";
    } else {
      std::cout << "  " << name << ": rejected: " << l.error << "\n";
      EXPECT_NE(l.error.find(name), std::string::npos) << l.error;
    }
  }
  EXPECT_GT(ok, loaded_->size() / 2);
}

TEST(GeneratedDatasetsTest, GeneratedObjectsLoadWithStatedCounts) {
  const fs::path dir = fs::path(HB_DATASETS_DIR) / "generated";
  if (!fs::is_directory(dir))
    GTEST_SKIP() << dir << " is absent: run datasets/fetch.sh build/datasets/hb_generate_datasets";
  MeshReadReport report;
  EXPECT_EQ(read_mesh((dir / "bumpy_sphere.off").string(), &report).triangle_count(), 327680u);
  EXPECT_FALSE(report.open);
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_GE(read_mesh((dir / "chess_piece.off").string(), &report).triangle_count(), 100000u);
  EXPECT_FALSE(report.open);
  EXPECT_TRUE(report.warnings.empty());
}

} // namespace
} // namespace hb
