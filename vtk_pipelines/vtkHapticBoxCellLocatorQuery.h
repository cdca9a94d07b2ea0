/**
 * @class   vtkHapticBoxCellLocatorQuery
 * @brief   The exact contact answered with VTK's vtkStaticCellLocator: what a VTK user would
 *          reach for, measured next to Embree and the haptic box in sweeps and reports.
 *
 * An hb::ContactQuery: IntersectWithLine on the probe segment S->E gives the first hit; the
 * contact rule is the core's (hb::Contact): a first hit on a triangle's back side means the
 * handle is inside (no contact); the normal is the shaded one (vertex normals interpolated
 * at the hit, oriented like the geometric normal); the same force law. So on the same
 * segments it should agree with hb::ExactQuery up to floating-point ties at edges.
 *
 * Thread-safe (one vtkGenericCell per thread), but unlike the core's queries it allocates:
 * VTK 9.1's locator allocates a visited-cell table per line query. That cost is part of
 * what is being measured.
 */
#ifndef vtkHapticBoxCellLocatorQuery_h
#define vtkHapticBoxCellLocatorQuery_h

#include "contact/contact.h"
#include "mesh/triangle_mesh.h"
#include <vtkSmartPointer.h>

class vtkPolyData;
class vtkStaticCellLocator;

class vtkHapticBoxCellLocatorQuery final : public hb::ContactQuery {
public:
  /// Builds the locator over `mesh` (copied into a polydata; the mesh needs vertex normals).
  /// `cellsPerBucket`: vtkStaticCellLocator's NumberOfCellsPerNode (VTK's default: 10).
  explicit vtkHapticBoxCellLocatorQuery(const hb::TriangleMesh& mesh, int cellsPerBucket = 10);
  ~vtkHapticBoxCellLocatorQuery() override;

  hb::Contact query(const hb::Segment& segment, const hb::ForceLaw& law) const noexcept override;

  /// Seconds BuildLocator took.
  double GetBuildSeconds() const { return this->BuildSeconds; }
  /// Memory of the polydata and locator as VTK reports it, bytes (an estimate: the locator's
  /// bucket arrays are counted from its parameters).
  std::size_t GetMemoryBytes() const { return this->MemoryBytes; }

private:
  const hb::TriangleMesh& Mesh;
  vtkSmartPointer<vtkPolyData> PolyData;
  vtkSmartPointer<vtkStaticCellLocator> Locator;
  double BuildSeconds = 0.0;
  std::size_t MemoryBytes = 0;
};

#endif
