// CAD solids and scene formats: a STEP file written by OpenCASCADE from known solids comes back
// within its chordal deviation (measured against the analytic surfaces), with its faces as
// pieces; the glTF/3MF/Collada/FBX exports of a mesh come back in millimetres; bad input names
// the file and the cause.
#include "errors.h"
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "model_loader.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif
#ifdef HB_HAVE_ASSIMP
#include "scene_reader.h"
#endif

namespace {

namespace fs = std::filesystem;

// The CAD force budget at 0.01 N: over the product's stiffness at the device, the solid's
// bounding-box diagonal fitted to the default workspace (before the clamp to [1e-4, 1e-2] x it).
[[maybe_unused]] double cad_budget_mm(const nlohmann::json& facts) {
  const auto& box = facts["bounding_box_mm"];
  double d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += std::pow(box[1][i].get<double>() - box[0][i].get<double>(), 2);
  const double diagonal = std::sqrt(d2);
  return 0.01 / hb::WorkspaceOptions::kDefaultStiffness * diagonal / hb::WorkspaceOptions::kDefaultDiagonalM;
}

fs::path temp_dir(const char* name) {
  const fs::path d = fs::temp_directory_path() / (std::string(name) + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

#ifdef HB_HAVE_OCCT
constexpr double kRadius = 10.0, kHeight = 30.0;

// Distance from p to the reference solids' analytic surfaces (the closer of the two).
double reference_distance(const Eigen::Vector3d& p) {
  // Capped cylinder: radius kRadius, z in [0, kHeight].
  const double radial = std::hypot(p.x(), p.y()) - kRadius;
  const double axial = std::max(-p.z(), p.z() - kHeight);
  const double cylinder = std::max(radial, axial) <= 0 ? std::max(radial, axial)
                                                        : std::hypot(std::max(radial, 0.0), std::max(axial, 0.0));
  const double sphere = (p - Eigen::Vector3d(3 * kRadius, 0, kHeight / 2)).norm() - kRadius;
  return std::min(std::abs(cylinder), std::abs(sphere));
}

class CadReaderTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = temp_dir("hb_cad_test_");
    hb::vtk::write_reference_solid_step((dir_ / "reference.step").string(), kRadius, kHeight);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static fs::path dir_;
};
fs::path CadReaderTest::dir_;

TEST_F(CadReaderTest, StepTessellationStaysWithinItsChordalDeviation) {
  for (const double deviation : {0.5, 0.05, 0.01}) {
    SCOPED_TRACE(deviation);
    hb::vtk::CadOptions options;
    options.chordal_deviation_mm = deviation;
    const hb::vtk::CadModel cad = hb::vtk::read_cad(path("reference.step"), options);
    EXPECT_EQ(cad.facts["solids"], 2);
    EXPECT_EQ(cad.facts["faces"], 4);
    // The exact surface is met at the vertices; between them (centroids, edge midpoints) the
    // chords fall short of curved faces by at most the deviation.
    double at_vertices = 0.0, between = 0.0;
    for (const hb::Vec3& v : cad.mesh.positions) at_vertices = std::max(at_vertices, reference_distance(v.cast<double>()));
    for (const hb::Triangle& t : cad.mesh.triangles) {
      const Eigen::Vector3d a = cad.mesh.positions[t[0]].cast<double>(), b = cad.mesh.positions[t[1]].cast<double>(),
                            c = cad.mesh.positions[t[2]].cast<double>();
      for (const Eigen::Vector3d& q : {Eigen::Vector3d((a + b + c) / 3), Eigen::Vector3d((a + b) / 2),
                                       Eigen::Vector3d((b + c) / 2), Eigen::Vector3d((a + c) / 2)})
        between = std::max(between, reference_distance(q));
    }
    RecordProperty("deviation_" + std::to_string(deviation) + "_measured_mm", std::to_string(between));
    EXPECT_LT(at_vertices, 1e-4);
    EXPECT_LE(between, deviation * 1.05) << "measured " << between << " mm for a chordal deviation of " << deviation;
  }
}

TEST_F(CadReaderTest, DeviationFollowsTheForceBudgetAndFacesBecomePieces) {
  hb::vtk::ModelOptions options;  // 0.01 N / 1500 N/m at the device, the solid fitted to 80 mm
  const hb::vtk::LoadedModel coarse = hb::vtk::load_model(path("reference.step"), options);
  const double diagonal_mm = cad_budget_mm(coarse.facts) / 0.01 * hb::WorkspaceOptions::kDefaultStiffness *
                             hb::WorkspaceOptions::kDefaultDiagonalM;
  EXPECT_NEAR(coarse.facts["chordal_deviation_mm"].get<double>(), 1e-4 * diagonal_mm, 1e-9);
  EXPECT_EQ(coarse.kind, hb::vtk::ModelKind::Cad);
  EXPECT_EQ(coarse.unit, "mm");
  ASSERT_EQ(coarse.face_ids.size(), coarse.mesh.triangle_count());
  EXPECT_EQ(std::set<std::uint32_t>(coarse.face_ids.begin(), coarse.face_ids.end()).size(), 4u);
  // The default lands on the floor (1e-4 x the diagonal); ten times the tolerance, ten times
  // the deviation (8.3e-4 x the diagonal), far fewer triangles.
  options.cad.force_tolerance_n = 0.1;
  const hb::vtk::LoadedModel coarser = hb::vtk::load_model(path("reference.step"), options);
  EXPECT_NEAR(coarser.facts["chordal_deviation_mm"].get<double>(), 10 * cad_budget_mm(coarse.facts), 1e-9);
  EXPECT_GT(coarse.mesh.triangle_count(), 2 * coarser.mesh.triangle_count());
  // The model's outward normals: the cylinder's lateral triangles face away from its axis.
  double outward = 0.0;
  for (const hb::Triangle& t : coarse.mesh.triangles) {
    const hb::Vec3 a = coarse.mesh.positions[t[0]], b = coarse.mesh.positions[t[1]], c = coarse.mesh.positions[t[2]];
    const hb::Vec3 centre = (a + b + c) / 3.f;
    if (centre.x() > 15.f || centre.z() < 1.f || centre.z() > 29.f) continue;
    outward += (b - a).cross(c - a).normalized().dot(hb::Vec3(centre.x(), centre.y(), 0).normalized());
  }
  EXPECT_GT(outward, 0.0);
}

TEST_F(CadReaderTest, StepWithoutASolidAndGarbageNameTheFile) {
  hb::vtk::write_vertex_only_step(path("vertex.step"));
  try {
    hb::vtk::read_cad(path("vertex.step"), {});
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("vertex.step: no solid"), std::string::npos) << e.what();
  }
  std::ofstream(path("garbage.step")) << "ISO-10303-21;\nthis is not STEP\n";
  try {
    hb::vtk::read_cad(path("garbage.step"), {});
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("garbage.step"), std::string::npos) << e.what();
  }
  std::ofstream(path("garbage.igs")) << "nothing\n";
  EXPECT_THROW(hb::vtk::read_cad(path("garbage.igs"), {}), hb::InvalidInput);
  EXPECT_THROW(hb::vtk::read_cad(path("missing.step"), {}), hb::IoError);
  hb::vtk::CadOptions absurd;
  absurd.chordal_deviation_mm = 1e-9;
  EXPECT_THROW(hb::vtk::read_cad(path("reference.step"), absurd), hb::InvalidInput);
}
#endif

#ifdef HB_HAVE_ASSIMP
TEST(SceneReaderTest, EveryFormatComesBackInMillimetres) {
  const fs::path dir = temp_dir("hb_scene_test_");
  const hb::TriangleMesh sphere = hb::make_sphere(25.f, 3);  // mm
  for (const char* name : {"s.gltf", "s.glb", "s.3mf", "s.dae", "s.fbx"}) {
    SCOPED_TRACE(name);
    const std::string file = (dir / name).string();
    hb::vtk::write_scene(sphere, file);
    const hb::vtk::LoadedModel model = hb::vtk::load_model(file);
    EXPECT_EQ(model.kind, hb::vtk::ModelKind::Scene);
    EXPECT_EQ(model.unit_source, "file");
    EXPECT_EQ(model.mesh.triangle_count(), sphere.triangle_count());
    EXPECT_NEAR(model.mesh.bounds().diagonal(), sphere.bounds().diagonal(), 1e-3 * sphere.bounds().diagonal())
        << "unit " << model.unit << " read from " << model.facts["file_unit_read_from"];
  }
  // --unit overrides the file's unit.
  hb::vtk::ModelOptions inch;
  inch.unit = "in";
  const hb::vtk::LoadedModel model = hb::vtk::load_model((dir / "s.3mf").string(), inch);
  EXPECT_NEAR(model.mesh.bounds().diagonal(), 25.4f * sphere.bounds().diagonal(), 1e-2 * sphere.bounds().diagonal());
  EXPECT_EQ(model.unit_source, "--unit");
  std::ofstream((dir / "bad.gltf").string()) << "{ not json";
  try {
    hb::vtk::load_model((dir / "bad.gltf").string());
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    // Refused by the glTF check before Assimp sees it, naming the file and the cause.
    EXPECT_NE(std::string(e.what()).find("bad.gltf: the glTF JSON does not parse"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}
#endif

TEST(ModelLoaderTest, UnitsAreNamedAndAbsurdSizesRefused) {
  EXPECT_DOUBLE_EQ(hb::vtk::mm_per_unit("inch"), 25.4);
  EXPECT_DOUBLE_EQ(hb::vtk::mm_per_unit("m"), 1000.0);
  EXPECT_THROW(hb::vtk::mm_per_unit("furlong"), hb::InvalidInput);
  const fs::path dir = temp_dir("hb_units_test_");
  const std::string off = (dir / "s.off").string();
  hb::write_mesh(hb::make_sphere(10.f, 2), off);
  const hb::vtk::LoadedModel mm = hb::vtk::load_model(off);
  EXPECT_EQ(mm.unit, "mm");
  EXPECT_EQ(mm.unit_source, "default (the format has no unit)");
  hb::vtk::ModelOptions km;
  km.unit = "m";
  const hb::vtk::LoadedModel metres = hb::vtk::load_model(off, km);
  EXPECT_NEAR(metres.mesh.bounds().diagonal(), 1000.f * mm.mesh.bounds().diagonal(), 1.f);
  hb::write_mesh(hb::make_sphere(2e4f, 2), off);  // 20 km in metres: absurd
  try {
    hb::vtk::load_model(off, km);
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("wrong unit"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

} // namespace
