#include "recipe/box_cache.h"
#include "store/box_file.h"
#include "test_meshes.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxDecompositionFilter.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <iterator>
#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>

TEST(BakeFilterTest, OneBoxWithOutlinesAndPositionPoints) {
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(hb::test::SpherePolyData(2));
  bake->SetM(4);
  bake->SetN(3);
  bake->Update();
  vtkHapticBoxSet* set = bake->GetBoxSet();
  ASSERT_NE(set, nullptr);
  ASSERT_EQ(set->GetNumberOfBoxes(), 1);
  EXPECT_EQ(set->GetScene()->parts().boxes[0].params().m, 4);
  EXPECT_EQ(set->GetScene()->bytes().tables, std::size_t(6 * 16 * 12 * 9 * 8));
  vtkPolyData* outlines = vtkPolyData::SafeDownCast(bake->GetOutputDataObject(1));
  vtkPolyData* positions = vtkPolyData::SafeDownCast(bake->GetOutputDataObject(2));
  EXPECT_EQ(outlines->GetNumberOfLines(), 12);
  EXPECT_EQ(outlines->GetNumberOfPoints(), 8);
  EXPECT_NE(outlines->GetCellData()->GetArray("BoxId"), nullptr);
  EXPECT_NE(outlines->GetFieldData()->GetArray("BakeSeconds"), nullptr);
  EXPECT_EQ(positions->GetNumberOfPoints(), 6 * 4 * 4);
  EXPECT_NE(positions->GetPointData()->GetArray("Face"), nullptr);
  // The position points lie on the box: the sphere of radius 1 is inside them.
  double b[6];
  positions->GetBounds(b);
  EXPECT_LE(b[0], -1.0);
  EXPECT_GE(b[1], 1.0);
}

TEST(BakeFilterTest, RefineOnGivesBoxesThatRefineExactly) {
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(hb::test::SpherePolyData(2));
  bake->SetM(4);
  bake->SetN(3);
  bake->RefineOn();
  bake->Update();
  const std::shared_ptr<const hb::BoxScene> scene = bake->GetBoxSet()->GetScene();
  ASSERT_NE(scene, nullptr);
  ASSERT_TRUE(scene->parts().boxes[0].refines());
  // A probe straight down onto the sphere's pole answers with the mesh's own surface.
  const hb::Contact c = scene->query({hb::Vec3(0.f, 0.f, 2.f), hb::Vec3(0.f, 0.f, 0.9f)}, hb::ForceLaw{});
  ASSERT_TRUE(c.contact);
  EXPECT_GT(c.depth, 0.f);
  EXPECT_GT(c.normal.z(), 0.9f);
}

TEST(BakeFilterTest, PieceIdArrayGivesOneBoxPerPiece) {
  vtkSmartPointer<vtkPolyData> sphere = hb::test::SpherePolyData(2);
  vtkNew<vtkIntArray> piece;
  piece->SetName("PieceId");
  for (vtkIdType c = 0; c < sphere->GetNumberOfCells(); ++c) {
    double centre[3] = {0, 0, 0}, p[3];
    for (int k = 0; k < 3; ++k) {
      sphere->GetPoint(sphere->GetCell(c)->GetPointId(k), p);
      centre[0] += p[0];
    }
    piece->InsertNextValue(centre[0] > 0 ? 7 : 3);  // arbitrary ids, renumbered 0..1
  }
  sphere->GetCellData()->AddArray(piece);
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(sphere);
  bake->SetM(3);
  bake->SetN(2);
  bake->Update();
  EXPECT_EQ(bake->GetBoxSet()->GetNumberOfBoxes(), 2);
  EXPECT_EQ(vtkPolyData::SafeDownCast(bake->GetOutputDataObject(1))->GetNumberOfLines(), 24);
}

TEST(BakeFilterTest, PiecesShareTheirSeamsAsEveryFrontEndBakesThem) {
  // The filter bakes through hb::bake: the same boxes as the command line for the same ids.
  vtkSmartPointer<vtkPolyData> sphere = hb::test::SpherePolyData(3);
  vtkNew<vtkIntArray> piece;
  piece->SetName("PieceId");
  std::vector<std::uint32_t> ids;
  for (vtkIdType c = 0; c < sphere->GetNumberOfCells(); ++c) {
    double p[3];
    sphere->GetPoint(sphere->GetCell(c)->GetPointId(0), p);
    ids.push_back(p[2] > 0 ? 1u : 0u);
    piece->InsertNextValue(int(ids.back()));
  }
  sphere->GetCellData()->AddArray(piece);
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(sphere);
  bake->SetM(6);
  bake->SetN(3);
  bake->Update();
  const std::shared_ptr<const hb::BoxScene> filtered = bake->GetBoxSet()->GetScene();
  ASSERT_NE(filtered, nullptr);
  ASSERT_EQ(filtered->parts().boxes.size(), 2u);
  EXPECT_EQ(filtered->parts().piece_of_triangle, ids);

  hb::BakeRecipe recipe = bake->GetRecipe();
  recipe.pieces.kind = hb::PiecesRecipe::Kind::given;
  recipe.pieces.given = ids;
  const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(sphere);
  const hb::BoxScene direct = hb::bake(mesh, recipe).scene;
  recipe.seams.rings = 0;
  recipe.seams.cells = 0.f;
  const hb::BoxScene no_seams = hb::bake(mesh, recipe).scene;
  for (std::size_t b = 0; b < 2; ++b) {
    const hb::HapticBox& f = filtered->parts().boxes[b];
    const hb::HapticBox& d = direct.parts().boxes[b];
    EXPECT_EQ(f.obb().center, d.obb().center);
    EXPECT_EQ(f.obb().half, d.obb().half);
    ASSERT_EQ(f.table_bytes(), d.table_bytes());
    EXPECT_EQ(std::memcmp(f.samples().data(), d.samples().data(), f.table_bytes()), 0);
    // The shared seam triangles make each half's box reach past the equator.
    EXPECT_NE(f.obb().half, no_seams.parts().boxes[b].obb().half);
  }
}

TEST(BakeFilterTest, AbortStopsTheBakeAndReportsProgress) {
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(hb::test::SpherePolyData(3));
  bake->SetM(16);
  bake->SetN(8);
  int events = 0;
  vtkNew<vtkCallbackCommand> onProgress;
  onProgress->SetClientData(&events);
  onProgress->SetCallback([](vtkObject* caller, unsigned long, void* data, void*) {
    ++*static_cast<int*>(data);
    auto* algorithm = static_cast<vtkHapticBoxBakeFilter*>(caller);
    if (algorithm->GetProgress() > 0.1) algorithm->SetAbortExecute(1);
  });
  bake->AddObserver(vtkCommand::ProgressEvent, onProgress);
  vtkObject::GlobalWarningDisplayOff();
  bake->Update();
  vtkObject::GlobalWarningDisplayOn();
  EXPECT_GT(events, 1);
  vtkHapticBoxSet* set = bake->GetBoxSet();
  EXPECT_TRUE(set == nullptr || set->GetNumberOfBoxes() == 0);
}

namespace {

// A box file's bytes.
std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

struct ScratchDir {
  std::string path = hb::test::ScratchPath("cache");
  ~ScratchDir() { std::filesystem::remove_all(path); }
};

}  // namespace

// With a cache directory and a source hash the filter is hb::bake_cached: the entry is the box
// cache's for (hash, recipe), holding hb::bake's scene; a second filter loads it (no bake);
// CacheOnly fails on a miss instead of baking.
TEST(BakeFilterTest, CacheDirectoryMakesItTheCoresCachedBake) {
  ScratchDir dir;
  vtkSmartPointer<vtkPolyData> sphere = hb::test::SpherePolyData(2);
  hb::SourceInfo source;
  source.mesh_path = "sphere.off";
  source.mesh_hash = 0x1234abcdULL;
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(sphere);
  bake->SetM(4);
  bake->SetN(3);
  bake->SetSource(source);
  bake->SetCacheDirectory(dir.path.c_str());
  EXPECT_FALSE(bake->HasCachedScene());
  bake->Update();
  ASSERT_TRUE(bake->GetLastError().empty()) << bake->GetLastError();
  EXPECT_FALSE(bake->GetFromCache());
  const hb::BoxCache cache(dir.path);
  EXPECT_EQ(bake->GetCachePath(), cache.path_for(source.mesh_hash, bake->GetRecipe()));
  EXPECT_TRUE(bake->HasCachedScene());

  // The entry is what hb::bake gives for the same mesh, recipe and source, byte for byte.
  const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(sphere);
  hb::SourceInfo full = source;
  full.triangles = mesh.triangle_count();
  full.diagonal = mesh.bounds().diagonal();
  const std::string direct = dir.path + "/direct.hbox.tmp";
  hb::save_box_file(hb::bake(mesh, bake->GetRecipe(), full).scene, direct);
  EXPECT_EQ(fileBytes(bake->GetCachePath()), fileBytes(direct));

  vtkNew<vtkHapticBoxBakeFilter> again;
  again->SetInputData(sphere);
  again->SetRecipe(bake->GetRecipe());
  again->SetSource(source);
  again->SetCacheDirectory(dir.path.c_str());
  again->CacheOnlyOn();
  again->Update();
  ASSERT_TRUE(again->GetLastError().empty()) << again->GetLastError();
  EXPECT_TRUE(again->GetFromCache());
  EXPECT_EQ(again->GetBakeSeconds(), 0.0);
  EXPECT_EQ(again->GetBoxSet()->GetScene()->bytes().tables, bake->GetBoxSet()->GetScene()->bytes().tables);

  again->SetM(5);  // another recipe: not cached
  vtkObject::GlobalWarningDisplayOff();
  again->Update();
  vtkObject::GlobalWarningDisplayOn();
  EXPECT_NE(again->GetLastError().find("no cached scene"), std::string::npos) << again->GetLastError();
}

// reader -> decomposition filter -> bake filter with an automatic recipe: the filter's pieces
// stand for the recipe's (no second decomposition), so the scene, and the cache key, are those
// of hb::bake with the automatic recipe, as `hapticbox bake --pieces auto` bakes; output 3
// carries the scene's piece of each triangle.
TEST(BakeFilterTest, DecompositionFilterPiecesAreTheAutomaticRecipes) {
  ScratchDir dir;
  vtkSmartPointer<vtkPolyData> sphere = vtkHapticBoxUtilities::ToPolyData(hb::test::TwoSpheres());
  hb::BakeRecipe recipe;
  recipe.options.params.m = 4;
  recipe.options.params.n = 3;
  recipe.pieces.kind = hb::PiecesRecipe::Kind::automatic;
  recipe.pieces.automatic.lines = 20000;
  vtkNew<vtkHapticBoxDecompositionFilter> decomposition;
  decomposition->SetInputData(sphere);
  decomposition->SetOptions(recipe.pieces.automatic);
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputConnection(decomposition->GetOutputPort());
  bake->SetRecipe(recipe);
  hb::SourceInfo source;
  source.mesh_hash = 0x42ULL;
  bake->SetSource(source);
  bake->SetCacheDirectory(dir.path.c_str());
  bake->Update();
  ASSERT_TRUE(bake->GetLastError().empty()) << bake->GetLastError();
  const std::shared_ptr<const hb::BoxScene> scene = bake->GetBoxSet()->GetScene();
  ASSERT_GT(scene->parts().boxes.size(), 1u);
  EXPECT_EQ(bake->GetCachePath(), hb::BoxCache(dir.path).path_for(source.mesh_hash, recipe));

  const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(sphere);
  hb::SourceInfo full = source;
  full.triangles = mesh.triangle_count();
  full.diagonal = mesh.bounds().diagonal();
  const hb::BoxScene direct = hb::bake(mesh, recipe, full).scene;
  EXPECT_EQ(scene->parts().piece_of_triangle, direct.parts().piece_of_triangle);
  const std::string path = dir.path + "/direct.hbox.tmp";
  hb::save_box_file(direct, path);
  EXPECT_EQ(fileBytes(bake->GetCachePath()), fileBytes(path));

  vtkPolyData* pieces = vtkPolyData::SafeDownCast(bake->GetOutputDataObject(3));
  vtkDataArray* ids = pieces->GetCellData()->GetArray("PieceId");
  ASSERT_NE(ids, nullptr);
  ASSERT_EQ(std::size_t(ids->GetNumberOfTuples()), mesh.triangle_count());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
    ASSERT_EQ(std::uint32_t(ids->GetTuple1(vtkIdType(t))), scene->parts().piece_of_triangle[t]) << t;

  // Other decomposition options: the ids are given ones (another key), not the recipe's.
  decomposition->SetMaxPieces(1);
  bake->Update();
  EXPECT_NE(bake->GetCachePath(), hb::BoxCache(dir.path).path_for(source.mesh_hash, recipe));
}
