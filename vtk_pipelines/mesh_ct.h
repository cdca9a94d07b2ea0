#pragma once
// A CT volume synthesized from a closed surface mesh (a bone): the mesh, scaled to a real
// size in millimetres, is voxelised with its partial volume (the fraction of each voxel inside
// it), given the values of cortical and cancellous bone inside a limb of muscle and fat in air,
// blurred by a scanner's point spread and given its noise. Used by datasets/generate_models to
// make femur_ct.nii.gz from CGAL's femur.off: a realistic test volume of a real shape, and one
// whose bone surface is known (the source mesh) so isosurfaces can be checked against it.
#include "mesh/triangle_mesh.h"
#include <Eigen/Core>
#include <vtkSmartPointer.h>
#include <cstdint>

class vtkImageData;

namespace hb::vtk {

struct MeshCtOptions {
  double length_mm = 420.0;  ///< the mesh's longest bounding-box side once scaled (an adult femur).
  double voxel_mm = 1.0;     ///< isotropic voxel size.
  double limb_margin_mm = 28.0;  ///< soft tissue around the bone's bounding box (the limb's half-axes).
  double fat_mm = 7.0;       ///< subcutaneous fat under the skin.
  double air_margin_mm = 10.0;   ///< air between the skin and the volume's faces.
  double cortical_mm = 4.0;  ///< about how deep the dense cortical shell reaches (cancellous inside).
  int subsamples = 4;        ///< partial volume: sub-rays per voxel side (exact along the ray).
  double psf_sigma_mm = 0.45;  ///< the scanner's point spread (Gaussian sigma).
  double noise_hu = 15.0;    ///< scanner noise (Gaussian sigma, HU).
  std::uint32_t seed = 20261206;
  double air_hu = -1000.0, fat_hu = -100.0, muscle_hu = 50.0, cortical_hu = 1200.0, cancellous_hu = 500.0;
  /// The bone's iso-value: between muscle and bone, below cancellous bone, so it gives the
  /// bone's outer surface only.
  double bone_iso_hu = 300.0;
};

struct MeshCt {
  vtkSmartPointer<vtkImageData> image;  ///< signed 16-bit HU in index space (origin 0, spacing 1).
  Eigen::Matrix4d index_to_mm{Eigen::Matrix4d::Identity()};
  TriangleMesh source_mm;  ///< the source mesh as placed in the CT's millimetres.
  int rays_dropped = 0;    ///< sub-rays with an odd number of crossings (an open spot), not counted.
};

/// Makes the CT. Throws hb::InvalidInput when the mesh is empty or so open that most rays
/// through it cross it an odd number of times.
MeshCt make_mesh_ct(const TriangleMesh& mesh, const MeshCtOptions& options = {});

} // namespace hb::vtk
