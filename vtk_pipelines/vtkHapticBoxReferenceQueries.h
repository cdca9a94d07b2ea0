/**
 * @class   vtkHapticBoxReferenceQueries
 * @brief   The reference methods a sweep or report measures next to the haptic box: exact
 *          Embree (hb::ExactQuery, the ground truth, first) and VTK's vtkStaticCellLocator
 *          (vtkHapticBoxCellLocatorQuery), built once over one mesh with their build times.
 *
 * Shared by the hapticbox command and the desktop window so both measure the same things.
 * The mesh must outlive this object.
 */
#ifndef vtkHapticBoxReferenceQueries_h
#define vtkHapticBoxReferenceQueries_h

#include "recipe/sweep.h"
#include "exact/exact_query.h"
#include "vtkHapticBoxCellLocatorQuery.h"
#include <memory>
#include <vector>

class vtkHapticBoxReferenceQueries {
public:
  explicit vtkHapticBoxReferenceQueries(const hb::TriangleMesh& mesh);

  const hb::ExactQuery& Exact() const { return *this->ExactQuery; }
  const vtkHapticBoxCellLocatorQuery& Locator() const { return *this->LocatorQuery; }
  /// "exact_embree" first (the ground truth), then "vtk_static_cell_locator".
  std::vector<hb::SweepReference> References() const;

private:
  std::unique_ptr<hb::ExactQuery> ExactQuery;
  std::unique_ptr<vtkHapticBoxCellLocatorQuery> LocatorQuery;
  double ExactSeconds = 0.0;
  std::size_t MeshBytes = 0;
};

#endif
