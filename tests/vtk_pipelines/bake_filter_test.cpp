#include "test_meshes.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxSet.h"
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
