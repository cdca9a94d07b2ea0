#include "errors.h"
#include "mesh/mesh_io.h"
#include "test_meshes.h"
#include "vtkHapticBoxMeshReader.h"
#include <cstring>
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <cmath>
#include <unistd.h>

namespace {

// Bit for bit: a filter bakes the very mesh the core read (unit normals are not divided by a
// length that rounds to 1 +- 1 ulp), so its boxes and cache key are the command line's.
void ExpectSameMeshBits(const hb::TriangleMesh& back, const hb::TriangleMesh& mesh) {
  ASSERT_EQ(back.triangles, mesh.triangles);
  ASSERT_EQ(back.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(back.normals.size(), mesh.normals.size());
  EXPECT_EQ(std::memcmp(back.positions.data(), mesh.positions.data(), mesh.vertex_count() * sizeof(hb::Vec3)), 0);
  EXPECT_EQ(std::memcmp(back.normals.data(), mesh.normals.data(), mesh.vertex_count() * sizeof(hb::Vec3)), 0);
}

} // namespace

TEST(ConversionTest, RoundTripKeepsPointsTrianglesAndNormals) {
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 2);
  vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::ToPolyData(mesh);
  EXPECT_EQ(pd->GetNumberOfPoints(), vtkIdType(mesh.vertex_count()));
  EXPECT_EQ(pd->GetNumberOfPolys(), vtkIdType(mesh.triangle_count()));
  ASSERT_NE(pd->GetPointData()->GetNormals(), nullptr);
  ExpectSameMeshBits(vtkHapticBoxUtilities::ToTriangleMesh(pd), mesh);
}

TEST(ConversionTest, ARealModelThroughTheReaderIsTheCoresMeshBitForBit) {
  const std::string path = std::string(HB_DATASETS_DIR) + "/meshes/cactus.off";
  // ./test.sh fetches the datasets first: a missing mesh is a failure, not a skip.
  ASSERT_EQ(::access(path.c_str(), R_OK), 0) << path << " missing: run datasets/fetch.sh";
  const hb::TriangleMesh core = hb::read_mesh(path);
  vtkNew<vtkHapticBoxMeshReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  ExpectSameMeshBits(vtkHapticBoxUtilities::ToTriangleMesh(reader->GetOutput()), core);
}

TEST(ConversionTest, NormalsNotOfUnitLengthAreNormalised) {
  vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::ToPolyData(hb::make_sphere(1.f, 2));
  vtkDataArray* normals = pd->GetPointData()->GetNormals();
  for (vtkIdType i = 0; i < normals->GetNumberOfTuples(); ++i) {
    double n[3];
    normals->GetTuple(i, n);
    normals->SetTuple3(i, 3 * n[0], 3 * n[1], 3 * n[2]);
  }
  const hb::TriangleMesh back = vtkHapticBoxUtilities::ToTriangleMesh(pd);
  for (const hb::Vec3& n : back.normals) EXPECT_NEAR(n.norm(), 1.f, 1e-6f);
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
