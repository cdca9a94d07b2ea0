#pragma once
// A quick look at a volume's surface while its options are being chosen (the window's Surface
// panel previews the iso-value, label and smoothing before the model is re-read and baked):
// the surface volume_surface would give, from the volume reduced to a few million voxels.
#include "volume_reader.h"
#include <vtkSmartPointer.h>
#include <cstddef>

class vtkPolyData;

namespace hb::vtk {

struct VolumePreview {
  vtkSmartPointer<vtkPolyData> surface;  ///< triangles with point normals, millimetres.
  int shrink = 1;                        ///< voxels merged along each axis (1: full resolution).
  double seconds = 0.0;                  ///< wall time of the preview.
};

/// The surface of `volume` per `options` (iso-value or label, smoothing; no decimation: the
/// preview is already coarse), from the volume shrunk by a whole factor per axis until it has at
/// most `max_voxels` (block averages for an iso-value, every f-th voxel for a label, which must
/// keep its values; placed at the blocks' centres, so the preview lies where the full surface
/// does, within the merged voxels). Safe to call on a worker thread while nothing else uses
/// `volume`. Throws what volume_surface throws (hb::InvalidInput naming `path`).
VolumePreview volume_preview_surface(const Volume& volume, VolumeSurfaceOptions options, const std::string& path,
                                     std::size_t max_voxels = 2000000);

} // namespace hb::vtk
