// A volume's surface in millimetres (volume_surface, declared in volume_reader.h):
//  1. flying edges at the stored iso-value (the Otsu threshold when none is given), or
//     discrete flying edges at a label, in index space;
//  2. the points mapped to millimetres by index_to_mm, then smoothing (windowed sinc) and
//     decimation (quadric) in millimetres, so anisotropic voxels are smoothed evenly;
//  3. the winding chosen by sampling the volume just off a few thousand triangles along their
//     normals: normals point to where the value is below the iso-value (or another label),
//     i.e. out of the bright region, whatever the handedness of index_to_mm.
#include "volume_reader.h"
#include "errors.h"
#include "volume_histogram.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkDataArray.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkQuadricDecimation.h>
#include <vtkWindowedSincPolyDataFilter.h>
#include <algorithm>
#include <cmath>
#include <sstream>

namespace hb::vtk {

namespace {

// The contour in index space and the stored value it was taken at (the label's, or the
// iso-value's before the rescale).
struct Contour {
  vtkSmartPointer<vtkPolyData> surface;
  double stored_iso = 0;
};

// Discrete flying edges at the label's stored value; refused when no voxel holds it.
Contour label_contour(const Volume& volume, long label, const std::string& path, nlohmann::json* facts) {
  vtkDataArray* scalars = volume.image->GetPointData()->GetScalars();
  const double stored = (double(label) - volume.intercept) / volume.slope;
  bool present = false;
  const vtkIdType n = scalars->GetNumberOfTuples();
  for (vtkIdType i = 0; i < n && !present; ++i) present = scalars->GetComponent(i, 0) == stored;
  if (!present) {
    std::string have = volume.facts.contains("labels") ? " (labels present: " + volume.facts["labels"].dump() + ")" : "";
    throw InvalidInput(path + ": no voxel has label " + std::to_string(label) + have);
  }
  vtkNew<vtkDiscreteFlyingEdges3D> contour;
  contour->SetInputData(volume.image);
  contour->SetValue(0, stored);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  if (facts) (*facts)["label"] = label;
  return {contour->GetOutput(), stored};
}

// Flying edges at the iso-value given, else at the Otsu threshold of the histogram; refused
// when no voxel crosses it.
Contour iso_contour(const Volume& volume, const VolumeSurfaceOptions& options, const std::string& path,
                    nlohmann::json* facts) {
  vtkDataArray* scalars = volume.image->GetPointData()->GetScalars();
  double range[2];
  scalars->GetRange(range, 0);
  const double lo = std::min(range[0] * volume.slope + volume.intercept, range[1] * volume.slope + volume.intercept);
  const double hi = std::max(range[0] * volume.slope + volume.intercept, range[1] * volume.slope + volume.intercept);
  double iso;
  if (options.iso) {
    iso = *options.iso;
    if (!std::isfinite(iso)) throw InvalidInput(path + ": the iso-value is not a finite number");
  } else {
    if (!(hi > lo)) throw InvalidInput(path + ": every voxel holds " + std::to_string(lo) + ": no surface in a constant volume");
    iso = otsu_threshold(volume_histogram(volume));  // the Surface panel's histogram and Otsu value
  }
  if (!(iso > lo && iso < hi)) {
    std::ostringstream msg;
    msg << path << ": no voxel crosses the iso-value " << iso << ": the values range from " << lo << " to " << hi;
    throw InvalidInput(msg.str());
  }
  const double stored_iso = (iso - volume.intercept) / volume.slope;
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(volume.image);
  contour->SetValue(0, stored_iso);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  if (facts) {
    (*facts)["iso"] = iso;
    (*facts)["iso_source"] = options.iso ? "--volume iso" : "automatic (Otsu threshold of the histogram; set --volume iso=V)";
  }
  return {contour->GetOutput(), stored_iso};
}

// Voxel indices to millimetres, then smoothing and decimation as the options ask.
vtkSmartPointer<vtkPolyData> in_millimetres(vtkSmartPointer<vtkPolyData> surface, const Volume& volume,
                                            const VolumeSurfaceOptions& options) {
  vtkPoints* points = surface->GetPoints();
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
    double p[3];
    points->GetPoint(i, p);
    const Eigen::Vector4d q = volume.index_to_mm * Eigen::Vector4d(p[0], p[1], p[2], 1.0);
    points->SetPoint(i, q[0], q[1], q[2]);
  }
  surface->Modified();
  if (options.smooth_iterations > 0) {
    vtkNew<vtkWindowedSincPolyDataFilter> smooth;
    smooth->SetInputData(surface);
    smooth->SetNumberOfIterations(options.smooth_iterations);
    smooth->SetPassBand(0.1);
    smooth->NormalizeCoordinatesOn();
    smooth->BoundarySmoothingOff();
    smooth->FeatureEdgeSmoothingOff();
    smooth->NonManifoldSmoothingOn();
    smooth->Update();
    surface = smooth->GetOutput();
  }
  if (options.target_triangles > 0 && std::size_t(surface->GetNumberOfPolys()) > options.target_triangles) {
    vtkNew<vtkQuadricDecimation> decimate;
    decimate->SetInputData(surface);
    decimate->SetTargetReduction(1.0 - double(options.target_triangles) / double(surface->GetNumberOfPolys()));
    decimate->VolumePreservationOn();
    decimate->Update();
    surface = decimate->GetOutput();
  }
  return surface;
}

// Winding: normals out of the region at or above the iso-value (or inside the label), by a
// vote of triangles sampled just off their centres on both sides.
void orient_outward(TriangleMesh& mesh, const Volume& volume, bool label, double stored_iso) {
  vtkDataArray* scalars = volume.image->GetPointData()->GetScalars();
  const Eigen::Matrix4d mm_to_index = volume.index_to_mm.inverse();
  double min_spacing = 1e30;
  for (int a = 0; a < 3; ++a) min_spacing = std::min(min_spacing, volume.index_to_mm.block<3, 1>(0, a).norm());
  int dims[3];
  volume.image->GetDimensions(dims);
  auto inside = [&](const Eigen::Vector3d& mm, bool& valid) {
    const Eigen::Vector4d q = mm_to_index * Eigen::Vector4d(mm.x(), mm.y(), mm.z(), 1.0);
    int ijk[3];
    for (int a = 0; a < 3; ++a) {
      ijk[a] = int(std::lround(q[a]));
      if (ijk[a] < 0 || ijk[a] >= dims[a]) {
        valid = false;
        return false;
      }
    }
    valid = true;
    const double x = scalars->GetComponent(volume.image->ComputePointId(ijk), 0);
    return label ? x == stored_iso : (volume.slope > 0 ? x >= stored_iso : x <= stored_iso);
  };
  long votes = 0;
  const std::size_t stride = std::max<std::size_t>(1, mesh.triangle_count() / 4000);
  for (std::size_t t = 0; t < mesh.triangle_count(); t += stride) {
    const Triangle& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.positions[tri[0]].cast<double>(), b = mesh.positions[tri[1]].cast<double>(),
                          c = mesh.positions[tri[2]].cast<double>();
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) continue;
    const Eigen::Vector3d centre = (a + b + c) / 3.0, step = n.normalized() * (0.75 * min_spacing);
    bool v1 = false, v2 = false;
    const bool ahead = inside(centre + step, v1), behind = inside(centre - step, v2);
    if (!v1 || !v2 || ahead == behind) continue;
    votes += ahead ? -1 : 1;
  }
  if (votes < 0) {
    for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
  }
}

} // namespace

TriangleMesh volume_surface(const Volume& volume, const VolumeSurfaceOptions& options, const std::string& path,
                            nlohmann::json* facts) {
  if (options.iso && options.label) throw InvalidInput(path + ": give an iso-value or a label, not both");
  const Contour contour =
      options.label ? label_contour(volume, *options.label, path, facts) : iso_contour(volume, options, path, facts);
  if (!contour.surface || contour.surface->GetNumberOfPolys() == 0)
    throw InvalidInput(path + ": the surface at " + (options.label ? "label " + std::to_string(*options.label) : "the iso-value") +
                       " is empty");
  if (facts) (*facts)["surface_triangles"] = contour.surface->GetNumberOfPolys();
  const vtkSmartPointer<vtkPolyData> surface = in_millimetres(contour.surface, volume, options);
  TriangleMesh mesh;
  try {
    mesh = vtkHapticBoxUtilities::ToTriangleMesh(surface);
  } catch (const Error& e) {
    throw InvalidInput(path + ": " + e.what());
  }
  orient_outward(mesh, volume, options.label.has_value(), contour.stored_iso);
  mesh.compute_vertex_normals();
  if (facts) (*facts)["triangles"] = mesh.triangle_count();
  return mesh;
}

} // namespace hb::vtk
