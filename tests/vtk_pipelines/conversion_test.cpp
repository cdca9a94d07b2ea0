#include "errors.h"
#include "test_meshes.h"
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <cmath>

TEST(ConversionTest, RoundTripKeepsPointsTrianglesAndNormals) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 2);
  vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::ToPolyData(mesh);
  EXPECT_EQ(pd->GetNumberOfPoints(), vtkIdType(mesh.vertex_count()));
  EXPECT_EQ(pd->GetNumberOfPolys(), vtkIdType(mesh.triangle_count()));
  ASSERT_NE(pd->GetPointData()->GetNormals(), nullptr);
  const hb::TriangleMesh back = vtkHapticBoxUtilities::ToTriangleMesh(pd);
  ASSERT_EQ(back.triangles, mesh.triangles);
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
    EXPECT_FLOAT_EQ(back.positions[i].x(), mesh.positions[i].x());
    EXPECT_NEAR((back.normals[i] - mesh.normals[i]).norm(), 0.f, 1e-6f);
  }
}

TEST(ConversionTest, QuadsAreFanTriangulatedAndNormalsComputed) {
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pts->InsertNextPoint(1, 0, 0);
  pts->InsertNextPoint(1, 1, 0);
  pts->InsertNextPoint(0, 1, 0);
  vtkNew<vtkCellArray> polys;
  const vtkIdType quad[4] = {0, 1, 2, 3};
  polys->InsertNextCell(4, quad);
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(pts);
  pd->SetPolys(polys);
  const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(pd);
  EXPECT_EQ(mesh.triangle_count(), 2u);
  ASSERT_EQ(mesh.normals.size(), 4u);
  EXPECT_NEAR(mesh.normals[0].z(), 1.f, 1e-6f);
}

TEST(ConversionTest, NanCoordinateIsRejected) {
  vtkSmartPointer<vtkPolyData> pd = hb::test::SpherePolyData(1);
  pd->GetPoints()->SetPoint(3, std::nan(""), 0, 0);
  EXPECT_THROW(vtkHapticBoxUtilities::ToTriangleMesh(pd), hb::InvalidInput);
}

TEST(ConversionTest, PolyDataWithoutTrianglesIsRejected) {
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  pts->InsertNextPoint(0, 0, 0);
  pd->SetPoints(pts);
  EXPECT_THROW(vtkHapticBoxUtilities::ToTriangleMesh(pd), hb::InvalidInput);
  EXPECT_THROW(vtkHapticBoxUtilities::ToTriangleMesh(nullptr), hb::InvalidInput);
}

TEST(ConversionTest, ExtensionIsLowerCase) {
  EXPECT_EQ(vtkHapticBoxUtilities::Extension("/a.b/c.OFF"), ".off");
  EXPECT_EQ(vtkHapticBoxUtilities::Extension("/a.b/c"), "");
}
