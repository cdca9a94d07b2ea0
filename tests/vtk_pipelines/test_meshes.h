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

/// A scratch path under /tmp unique to this process.
inline std::string ScratchPath(const std::string& name) {
  return "/tmp/vtk_hb_test_" + std::to_string(::getpid()) + "_" + name;
}

} // namespace hb::test
