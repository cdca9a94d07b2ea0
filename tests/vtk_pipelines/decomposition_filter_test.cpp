#include "test_meshes.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxDecompositionFilter.h"
#include "vtkHapticBoxSet.h"
#include <gtest/gtest.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <set>

TEST(DecompositionFilterTest, PieceIdsPerCellFeedTheBakeFilter) {
  // Two spheres side by side: at least two pieces.
  hb::TriangleMesh a = hb::make_sphere(1.f, 2), b = hb::make_sphere(1.f, 2);
  const std::uint32_t offset = std::uint32_t(a.vertex_count());
  for (hb::Vec3& p : b.positions) p.x() += 3.f;
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (hb::Triangle t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  a.compute_vertex_normals();
  vtkNew<vtkHapticBoxDecompositionFilter> decompose;
  decompose->SetInputData(vtkHapticBoxUtilities::ToPolyData(a));
  decompose->SetLines(20000);
  decompose->Update();
  vtkPolyData* out = decompose->GetOutput();
  vtkDataArray* ids = out->GetCellData()->GetArray("PieceId");
  ASSERT_NE(ids, nullptr);
  ASSERT_EQ(ids->GetNumberOfTuples(), vtkIdType(a.triangle_count()));
  std::set<int> distinct;
  for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c) distinct.insert(int(ids->GetComponent(c, 0)));
  EXPECT_GE(distinct.size(), 2u);
  EXPECT_EQ(int(out->GetFieldData()->GetArray("PieceCount")->GetComponent(0, 0)), int(distinct.size()));
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputConnection(decompose->GetOutputPort());
  bake->SetM(3);
  bake->SetN(2);
  bake->Update();
  EXPECT_EQ(bake->GetBoxSet()->GetNumberOfBoxes(), vtkIdType(distinct.size()));
}
