#pragma once
// Small polydata built in code for the VTK pipeline tests.
#include "mesh/generators.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <string>
#include <unistd.h>

namespace hb::test {

/// An icosphere of radius 1 (80 * 4^(s-2) triangles) as polydata.
inline vtkSmartPointer<vtkPolyData> SpherePolyData(int subdivisions = 3) {
  return vtkHapticBoxUtilities::ToPolyData(hb::make_sphere(1.f, subdivisions));
}

/// Two unit icospheres side by side (centres 3 apart): automatic decomposition gives >= 2 pieces.
inline hb::TriangleMesh TwoSpheres(int subdivisions = 2) {
  hb::TriangleMesh a = hb::make_sphere(1.f, subdivisions), b = hb::make_sphere(1.f, subdivisions);
  const std::uint32_t offset = std::uint32_t(a.vertex_count());
  for (hb::Vec3& p : b.positions) p.x() += 3.f;
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (hb::Triangle t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  a.compute_vertex_normals();
  return a;
}

/// A scratch path under /tmp unique to this process.
inline std::string ScratchPath(const std::string& name) {
  return "/tmp/vtk_hb_test_" + std::to_string(::getpid()) + "_" + name;
}

} // namespace hb::test
