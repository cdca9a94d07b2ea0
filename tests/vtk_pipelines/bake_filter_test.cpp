#include "test_meshes.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <cstring>
#include <gtest/gtest.h>
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
  EXPECT_EQ(set->GetScene()->boxes()[0].params().m, 4);
  EXPECT_EQ(set->GetScene()->table_bytes(), std::size_t(6 * 16 * 12 * 9 * 8));
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
  ASSERT_TRUE(scene->boxes()[0].refines());
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
  ASSERT_EQ(filtered->boxes().size(), 2u);
  EXPECT_EQ(filtered->piece_of_triangle(), ids);

  hb::BakeRecipe recipe = bake->GetRecipe();
  recipe.pieces.kind = hb::PiecesRecipe::Kind::given;
  recipe.pieces.given = ids;
  const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(sphere);
  const hb::BoxScene direct = hb::bake(mesh, recipe).scene;
  recipe.seams.rings = 0;
  recipe.seams.cells = 0.f;
  const hb::BoxScene no_seams = hb::bake(mesh, recipe).scene;
  for (std::size_t b = 0; b < 2; ++b) {
    const hb::HapticBox& f = filtered->boxes()[b];
    const hb::HapticBox& d = direct.boxes()[b];
    EXPECT_EQ(f.obb().center, d.obb().center);
    EXPECT_EQ(f.obb().half, d.obb().half);
    ASSERT_EQ(f.table_bytes(), d.table_bytes());
    EXPECT_EQ(std::memcmp(f.samples().data(), d.samples().data(), f.table_bytes()), 0);
    // The shared seam triangles make each half's box reach past the equator.
    EXPECT_NE(f.obb().half, no_seams.boxes()[b].obb().half);
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
