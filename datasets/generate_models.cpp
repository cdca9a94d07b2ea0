// Writes the generated models of the volume, CAD and scene formats into a folder:
//   ct_phantom.nii.gz / .mha / .nrrd  the CT phantom (hb::vtk::CtPhantom: air, a soft-tissue
//                                     ball, a bone torus; oblique, anisotropic voxels);
//   ct_phantom_labels.nii.gz          its label map (0 air, 1 soft tissue, 2 bone);
//   femur_ct.nii.gz                   a synthesized CT of a thigh made from CGAL's femur.off
//                                     (hb::vtk::make_mesh_ct: the femur scaled to 420 mm,
//                                     voxelised at 1 mm with its partial volume, cortical and
//                                     cancellous bone in muscle and fat in air, blurred, with
//                                     scanner noise); femur_ct_source.off: the femur as placed
//                                     in the CT's millimetres (what the bone iso should find);
//   femur_ct_dicom/                   the same voxels as a DICOM CT series (slice_0000.dcm ...);
//   reference_solid.step              two solids written by OpenCASCADE: a cylinder (r 10 mm,
//                                     h 30 mm) and a sphere (r 10 mm) beside it;
//   elephant.gltf .glb .3mf .dae .fbx CGAL's elephant.off (taken as mm) through Assimp's
//                                     exporters, each in its format's unit.
// Usage: hb_generate_models OUTPUT_DIR [MESHES_DIR]. Exit 2 for usage, 1 for failure.
#include "errors.h"
#include "mesh/mesh_io.h"
#include "dicom_series.h"
#include "mesh_ct.h"
#include "volume_phantom.h"
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif
#ifdef HB_HAVE_ASSIMP
#include "scene_reader.h"
#endif
#include <vtkImageData.h>
#include <filesystem>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::cerr << "usage: " << argv[0] << " OUTPUT_DIR [MESHES_DIR]\n";
    return 2;
  }
  namespace fs = std::filesystem;
  const fs::path dir(argv[1]);
  try {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw hb::IoError(dir.string() + ": cannot create folder (" + ec.message() + ")");
    const hb::vtk::CtPhantom phantom;
    const auto image = hb::vtk::make_ct_phantom(phantom);
    for (const char* name : {"ct_phantom.nii.gz", "ct_phantom.mha", "ct_phantom.nrrd"}) {
      hb::vtk::write_volume(image, phantom.index_to_mm(), (dir / name).string());
      std::cout << "hb_generate_models: " << (dir / name).string() << ": " << phantom.dims[0] << " x " << phantom.dims[1]
                << " x " << phantom.dims[2] << " voxels, body iso " << phantom.body_iso() << " HU, bone iso "
                << phantom.bone_iso() << " HU\n";
    }
    hb::vtk::write_volume(hb::vtk::make_phantom_labels(phantom), phantom.index_to_mm(), (dir / "ct_phantom_labels.nii.gz").string());
    std::cout << "hb_generate_models: " << (dir / "ct_phantom_labels.nii.gz").string() << ": labels 0 1 2\n";
#ifdef HB_HAVE_OCCT
    hb::vtk::write_reference_solid_step((dir / "reference_solid.step").string(), 10.0, 30.0);
    std::cout << "hb_generate_models: " << (dir / "reference_solid.step").string() << ": cylinder r 10 h 30 and sphere r 10 at (30, 0, 15)\n";
#endif
    if (argc == 3 && fs::exists(fs::path(argv[2]) / "femur.off")) {
      const hb::vtk::MeshCtOptions options;
      const hb::vtk::MeshCt ct = hb::vtk::make_mesh_ct(hb::read_mesh((fs::path(argv[2]) / "femur.off").string()), options);
      hb::vtk::write_volume(ct.image, ct.index_to_mm, (dir / "femur_ct.nii.gz").string());
      hb::write_mesh(ct.source_mm, (dir / "femur_ct_source.off").string());
      // The same voxels as a DICOM series (one file a slice), as a scanner would hand it over.
      std::filesystem::remove_all(dir / "femur_ct_dicom");
      hb::datasets::write_dicom_series(ct.image, ct.index_to_mm, (dir / "femur_ct_dicom").string(), "Synthesized^Femur",
                                       "CT of a thigh synthesized from CGAL femur.off");
      const int* d = ct.image->GetDimensions();
      std::cout << "hb_generate_models: " << (dir / "femur_ct.nii.gz").string() << ": synthesized from femur.off, " << d[0]
                << " x " << d[1] << " x " << d[2] << " voxels of " << options.voxel_mm << " mm, bone iso "
                << options.bone_iso_hu << " HU (" << ct.rays_dropped << " open rays); " << (dir / "femur_ct_source.off").string() << ": its source surface\n";
    }
#ifdef HB_HAVE_ASSIMP
    if (argc == 3) {
      const fs::path source = fs::path(argv[2]) / "elephant.off";
      const hb::TriangleMesh mesh = hb::read_mesh(source.string());
      for (const char* name : {"elephant.gltf", "elephant.glb", "elephant.3mf", "elephant.dae", "elephant.fbx"}) {
        hb::vtk::write_scene(mesh, (dir / name).string());
        std::cout << "hb_generate_models: " << (dir / name).string() << ": " << mesh.triangle_count() << " triangles\n";
      }
    }
#endif
  } catch (const std::exception& e) {
    std::cerr << "hb_generate_models: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
