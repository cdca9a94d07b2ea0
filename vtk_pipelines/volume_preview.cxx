#include "volume_preview.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkImageData.h>
#include <vtkImageShrink3D.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <chrono>
#include <cmath>

namespace hb::vtk {

VolumePreview volume_preview_surface(const Volume& volume, VolumeSurfaceOptions options, const std::string& path,
                                     std::size_t max_voxels) {
  const auto t0 = std::chrono::steady_clock::now();
  VolumePreview out;
  int dims[3];
  volume.image->GetDimensions(dims);
  const double voxels = double(dims[0]) * double(dims[1]) * double(dims[2]);
  out.shrink = std::max(1, int(std::ceil(std::cbrt(voxels / double(std::max<std::size_t>(1, max_voxels))) - 1e-9)));
  Volume coarse = volume;  // the same calibration and index-to-millimetre map
  coarse.image = vtkSmartPointer<vtkImageData>::New();
  if (out.shrink > 1) {
    // Never connect the shared image to a pipeline: a shallow copy is this call's own.
    auto input = vtkSmartPointer<vtkImageData>::New();
    input->ShallowCopy(volume.image);
    vtkNew<vtkImageShrink3D> shrink;
    shrink->SetInputData(input);
    shrink->SetShrinkFactors(out.shrink, out.shrink, out.shrink);
    const bool average = !options.label;  // labels keep their exact values
    shrink->SetAveraging(average);
    shrink->Update();
    coarse.image->ShallowCopy(shrink->GetOutput());
    // Output voxel i is the block f i .. f i + f - 1 (averaged) or voxel f i (sampled): its
    // position in the full volume's index space, which index_to_mm maps to millimetres.
    const double centre = average ? 0.5 * (out.shrink - 1) : 0.0;
    coarse.image->SetOrigin(centre, centre, centre);
  } else {
    coarse.image->ShallowCopy(volume.image);
  }
  options.target_triangles = 0;
  const TriangleMesh mesh = volume_surface(coarse, options, path);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(vtkHapticBoxUtilities::ToPolyData(mesh));
  normals->SplittingOff();
  normals->ConsistencyOff();
  normals->Update();
  out.surface = normals->GetOutput();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

} // namespace hb::vtk
