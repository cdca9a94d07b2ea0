// 1. IntersectWithLine(S, E) -> parametric t in [0, 1], the cell (= core triangle) and the
//    parametric coordinates of the hit;
// 2. the geometric normal decides front or back side (back: the handle is inside);
// 3. shaded normal from the vertex normals with weights (1 - r - s, r, s), the core's force law.
#include "vtkHapticBoxCellLocatorQuery.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkGenericCell.h>
#include <vtkPolyData.h>
#include <vtkStaticCellLocator.h>
#include <chrono>

vtkHapticBoxCellLocatorQuery::vtkHapticBoxCellLocatorQuery(const hb::TriangleMesh& mesh, int cellsPerBucket)
  : Mesh(mesh) {
  this->PolyData = vtkHapticBoxUtilities::ToPolyData(mesh);
  this->PolyData->BuildCells();
  this->Locator = vtkSmartPointer<vtkStaticCellLocator>::New();
  this->Locator->SetDataSet(this->PolyData);
  this->Locator->SetNumberOfCellsPerNode(cellsPerBucket);
  const auto t0 = std::chrono::steady_clock::now();
  this->Locator->BuildLocator();
  this->BuildSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Buckets: one offset per bucket plus one (cell, bucket) pair per cell-bucket overlap;
  // at least one pair per cell.
  int div[3];
  this->Locator->GetDivisions(div);
  const std::size_t buckets = std::size_t(div[0]) * std::size_t(div[1]) * std::size_t(div[2]);
  this->MemoryBytes = std::size_t(this->PolyData->GetActualMemorySize()) * 1024u + buckets * sizeof(vtkIdType) +
                      mesh.triangle_count() * 2u * sizeof(vtkIdType);
}

vtkHapticBoxCellLocatorQuery::~vtkHapticBoxCellLocatorQuery() = default;

hb::Contact vtkHapticBoxCellLocatorQuery::query(const hb::Segment& segment, const hb::ForceLaw& law) const noexcept {
  hb::Contact c;
  const hb::Vec3 delta = segment.end - segment.start;
  const float length = delta.norm();
  if (!(length > 0.f) || !std::isfinite(length)) return c;
  // vtkGenericCell is not shareable between threads: one per thread.
  thread_local vtkSmartPointer<vtkGenericCell> cell = vtkSmartPointer<vtkGenericCell>::New();
  const double a[3] = {segment.start.x(), segment.start.y(), segment.start.z()};
  const double b[3] = {segment.end.x(), segment.end.y(), segment.end.z()};
  double t = 0.0, x[3], pcoords[3];
  int subId = 0;
  vtkIdType cellId = -1;
  if (!this->Locator->IntersectWithLine(a, b, 0.0, t, x, pcoords, subId, cellId, cell) || cellId < 0 ||
      std::size_t(cellId) >= this->Mesh.triangle_count())
    return c;
  const hb::Triangle& tri = this->Mesh.triangles[std::size_t(cellId)];
  const hb::Vec3& p0 = this->Mesh.positions[tri[0]];
  const hb::Vec3 geometric = (this->Mesh.positions[tri[1]] - p0).cross(this->Mesh.positions[tri[2]] - p0);
  const hb::Vec3 dir = delta / length;
  if (geometric.dot(dir) >= 0.f) return c;  // back side first: the handle is inside
  const float r = float(pcoords[0]), s = float(pcoords[1]);
  hb::Vec3 n = (1.f - r - s) * this->Mesh.normals[tri[0]] + r * this->Mesh.normals[tri[1]] +
               s * this->Mesh.normals[tri[2]];
  if (n.dot(geometric) < 0.f) n = -n;
  const float len = n.norm();
  n = len > 0.f ? hb::Vec3(n / len) : hb::Vec3(geometric.normalized());
  c.contact = true;
  c.depth = length * float(1.0 - t);
  c.point = hb::Vec3(float(x[0]), float(x[1]), float(x[2]));
  c.normal = n;
  hb::apply_force_law(c, law, dir);
  return c;
}
