#include "vtkHapticBoxReferenceQueries.h"
#include <chrono>

vtkHapticBoxReferenceQueries::vtkHapticBoxReferenceQueries(const hb::TriangleMesh& mesh) {
  const auto t0 = std::chrono::steady_clock::now();
  this->ExactQuery = std::make_unique<hb::ExactQuery>(mesh);
  this->ExactSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  this->LocatorQuery = std::make_unique<vtkHapticBoxCellLocatorQuery>(mesh);
  this->MeshBytes = mesh.positions.size() * sizeof(hb::Vec3) + mesh.normals.size() * sizeof(hb::Vec3) +
                    mesh.triangles.size() * sizeof(hb::Triangle);
}

std::vector<hb::SweepReference> vtkHapticBoxReferenceQueries::References() const {
  return {{"exact_embree", this->ExactQuery.get(), this->MeshBytes, this->ExactSeconds},
          {"vtk_static_cell_locator", this->LocatorQuery.get(), this->LocatorQuery->GetMemoryBytes(),
           this->LocatorQuery->GetBuildSeconds()}};
}
