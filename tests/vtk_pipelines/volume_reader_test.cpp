// Volumes to surfaces: the CT phantom written in every format comes back within half a voxel
// of its analytic surfaces, oriented and in millimetres; the real MRI (nibabel) and CT series
// (pydicom) open; bad input names the file and the cause.
#include "volume_preview.h"
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include "errors.h"
#include "model_loader.h"
#include "volume_phantom.h"
#include "volume_reader.h"
#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace {

namespace fs = std::filesystem;

// The real volumes: fetched into datasets/data/volumes by datasets/fetch.sh, else straight
// from the Debian packages scripts/install_deps.sh installs.
std::string real_file(const std::string& fetched, const std::string& debian) {
  const fs::path a = fs::path(HB_DATASETS_DIR) / "volumes" / fetched;
  return fs::exists(a) ? a.string() : debian;
}
const std::string kNibabel = "/usr/lib/python3/dist-packages/nibabel/tests/data/";
const std::string kPydicom = "/usr/lib/python3/dist-packages/pydicom/data/test_files/";

class VolumeReaderTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_volume_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const hb::vtk::CtPhantom phantom;
    const auto image = hb::vtk::make_ct_phantom(phantom);
    for (const char* name : {"phantom.nii.gz", "phantom.mha", "phantom.nrrd"})
      hb::vtk::write_volume(image, phantom.index_to_mm(), (dir_ / name).string());
    hb::vtk::write_volume(hb::vtk::make_phantom_labels(phantom), phantom.index_to_mm(), (dir_ / "labels.nii").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string write(const std::string& name, const std::string& text) {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }
  static fs::path dir_;
};
fs::path VolumeReaderTest::dir_;

double min_spacing(const hb::vtk::CtPhantom& p) {
  return std::min({p.spacing_mm[0], p.spacing_mm[1], p.spacing_mm[2]});
}

TEST_F(VolumeReaderTest, PhantomIsosurfaceIsWithinHalfAVoxelOfTheAnalyticSurfaceInEveryFormat) {
  const hb::vtk::CtPhantom phantom;
  for (const char* name : {"phantom.nii.gz", "phantom.mha", "phantom.nrrd"}) {
    SCOPED_TRACE(name);
    const hb::vtk::Volume volume = hb::vtk::read_volume(path(name));
    // Spacing and orientation kept: the file's matrix is the phantom's.
    EXPECT_LT((volume.index_to_mm - phantom.index_to_mm()).cwiseAbs().maxCoeff(), 1e-4);
    for (const bool bone : {false, true}) {
      hb::vtk::VolumeSurfaceOptions options;
      options.iso = bone ? phantom.bone_iso() : phantom.body_iso();
      const hb::TriangleMesh mesh = hb::vtk::volume_surface(volume, options, path(name));
      ASSERT_GT(mesh.triangle_count(), 1000u);
      double worst = 0.0, outward = 0.0;
      for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        const Eigen::Vector3d p = mesh.positions[v].cast<double>();
        const double d = bone ? phantom.bone_distance(p) : phantom.body_distance(p);
        worst = std::max(worst, std::abs(d));
        // The analytic outward normal, by finite differences of the distance.
        Eigen::Vector3d g;
        for (int a = 0; a < 3; ++a) {
          Eigen::Vector3d e = Eigen::Vector3d::Zero();
          e[a] = 1e-3;
          g[a] = bone ? phantom.bone_distance(p + e) - phantom.bone_distance(p - e)
                      : phantom.body_distance(p + e) - phantom.body_distance(p - e);
        }
        outward += g.normalized().dot(mesh.normals[v].cast<double>());
      }
      RecordProperty(std::string(name) + (bone ? "_bone" : "_body") + "_max_error_mm", std::to_string(worst));
      EXPECT_LT(worst, 0.5 * min_spacing(phantom)) << (bone ? "bone" : "body") << " surface, worst " << worst << " mm";
      EXPECT_GT(outward / double(mesh.vertex_count()), 0.95) << "normals point out of the bright region";
    }
  }
}

TEST_F(VolumeReaderTest, LabelSurfaceBoundsTheLabelledVoxels) {
  const hb::vtk::CtPhantom phantom;
  hb::vtk::ModelOptions options;
  options.volume.label = 2;
  const hb::vtk::LoadedModel model = hb::vtk::load_model(path("labels.nii"), options);
  EXPECT_EQ(model.kind, hb::vtk::ModelKind::Volume);
  ASSERT_TRUE(model.facts.contains("labels"));
  EXPECT_TRUE(model.facts["labels"].contains("2"));
  const double max_spacing = std::max({phantom.spacing_mm[0], phantom.spacing_mm[1], phantom.spacing_mm[2]});
  for (const hb::Vec3& p : model.mesh.positions)
    ASSERT_LT(std::abs(phantom.bone_distance(p.cast<double>())), max_spacing) << "a voxel face lies off the torus";
}

TEST_F(VolumeReaderTest, SmoothingAndDecimationReachTheTargetAndStayNearTheSurface) {
  const hb::vtk::CtPhantom phantom;
  hb::vtk::ModelOptions options;
  options.volume.iso = phantom.body_iso();
  options.volume.smooth_iterations = 15;
  options.volume.target_triangles = 5000;
  const hb::vtk::LoadedModel model = hb::vtk::load_model(path("phantom.nrrd"), options);
  EXPECT_LE(model.mesh.triangle_count(), 5500u);
  EXPECT_GE(model.mesh.triangle_count(), 4000u);
  double worst = 0.0;
  for (const hb::Vec3& p : model.mesh.positions) worst = std::max(worst, std::abs(phantom.body_distance(p.cast<double>())));
  EXPECT_LT(worst, min_spacing(phantom));
}

TEST_F(VolumeReaderTest, InfoFactsNameDimensionsSpacingAndRange) {
  const hb::vtk::LoadedModel model = hb::vtk::load_model(path("phantom.mha"));
  const hb::vtk::CtPhantom phantom;
  EXPECT_EQ(model.facts["format"], "MetaImage");
  EXPECT_EQ(model.facts["dimensions"][2], phantom.dims[2]);
  EXPECT_NEAR(model.facts["spacing_mm"][2].get<double>(), 1.4, 1e-6);
  EXPECT_NEAR(model.facts["value_range"][0].get<double>(), -1000.0, 0.5);
  EXPECT_NEAR(model.facts["value_range"][1].get<double>(), 700.0, 0.5);
  // No --iso: Otsu's threshold, said so.
  EXPECT_TRUE(model.facts.contains("iso"));
  EXPECT_NE(model.facts["iso_source"].get<std::string>().find("automatic"), std::string::npos);
  EXPECT_EQ(model.unit, "mm");
}

TEST_F(VolumeReaderTest, IsoValueOutsideTheValuesNamesFileAndRange) {
  hb::vtk::ModelOptions options;
  options.volume.iso = 5000.0;
  try {
    hb::vtk::load_model(path("phantom.nii.gz"), options);
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("phantom.nii.gz"), std::string::npos) << m;
    EXPECT_NE(m.find("no voxel crosses the iso-value 5000"), std::string::npos) << m;
    EXPECT_NE(m.find("-1000"), std::string::npos) << m;
  }
}

TEST_F(VolumeReaderTest, AbsentLabelListsTheLabelsPresent) {
  hb::vtk::ModelOptions options;
  options.volume.label = 7;
  try {
    hb::vtk::load_model(path("labels.nii"), options);
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("no voxel has label 7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"2\""), std::string::npos) << e.what();
  }
}

TEST_F(VolumeReaderTest, AbsurdHeaderSizeIsRefusedBeforeReading) {
  const std::string f = write("huge.mha",
                              "ObjectType = Image\nNDims = 3\nBinaryData = True\nElementSpacing = 1 1 1\n"
                              "DimSize = 100000 100000 100000\nElementType = MET_SHORT\nElementDataFile = LOCAL\nxx");
  try {
    hb::vtk::read_volume(f);
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("huge.mha"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("100000 x 100000 x 100000"), std::string::npos) << e.what();
  }
  // A size beyond a 64-bit integer (found by fuzzing: it escaped as std::out_of_range).
  const std::string wide = write("wide.mha",
                                 "ObjectType = Image\nNDims = 3\nBinaryData = True\nElementSpacing = 1 1 1\n"
                                 "DimSize = 96 9690000000000000002 8\nElementType = MET_SHORT\nElementDataFile = LOCAL\nxx");
  try {
    hb::vtk::read_volume(wide);
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("wide.mha"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("9690000000000000002"), std::string::npos) << e.what();
  }
}

TEST_F(VolumeReaderTest, ZeroSpacingAndGarbageAreClearErrors) {
  std::string data(8 * 8 * 8 * 2, '\0');
  const std::string zero = write("zero.mha",
                                 "ObjectType = Image\nNDims = 3\nBinaryData = True\nElementSpacing = 1 0 1\n"
                                 "DimSize = 8 8 8\nElementType = MET_SHORT\nElementDataFile = LOCAL\n" + data);
  EXPECT_THROW(
      {
        try {
          hb::vtk::read_volume(zero);
        } catch (const hb::InvalidInput& e) {
          EXPECT_NE(std::string(e.what()).find("spacing"), std::string::npos) << e.what();
          throw;
        }
      },
      hb::InvalidInput);
  EXPECT_THROW(hb::vtk::read_volume(write("garbage.nii", std::string(400, 'x'))), hb::InvalidInput);
  EXPECT_THROW(hb::vtk::read_volume(write("garbage.nrrd", "not a nrrd\n")), hb::InvalidInput);
  EXPECT_THROW(hb::vtk::read_volume(path("missing.nii")), hb::IoError);
  const hb::vtk::CtPhantom phantom;
  const auto image = hb::vtk::make_ct_phantom(phantom);
  // A constant volume has no surface.
  hb::vtk::CtPhantom flat;
  flat.dims[0] = flat.dims[1] = flat.dims[2] = 4;
  flat.body_radius_mm = 0.1;
  flat.torus_minor_mm = 0.01;
  hb::vtk::write_volume(hb::vtk::make_ct_phantom(flat), flat.index_to_mm(), path("flat.nrrd"));
  EXPECT_THROW(hb::vtk::load_model(path("flat.nrrd")), hb::InvalidInput);
}

TEST_F(VolumeReaderTest, RealMriOpensInMillimetresWithItsOrientation) {
  const std::string f = real_file("anatomical.nii", kNibabel + "anatomical.nii");
  const hb::vtk::LoadedModel model = hb::vtk::load_model(f);
  EXPECT_EQ(model.format, "NIfTI");
  EXPECT_GT(model.mesh.triangle_count(), 1000u);
  EXPECT_EQ(model.facts["dimensions"].size(), 3u);
  // Every vertex lies inside the volume's box in patient millimetres.
  const hb::vtk::Volume volume = hb::vtk::read_volume(f);
  const Eigen::Matrix4d inv = volume.index_to_mm.inverse();
  int dims[3];
  volume.image->GetDimensions(dims);
  for (std::size_t v = 0; v < model.mesh.vertex_count(); v += 37) {
    const Eigen::Vector3d p = model.mesh.positions[v].cast<double>();
    const Eigen::Vector4d q = inv * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
    for (int a = 0; a < 3; ++a) ASSERT_TRUE(q[a] > -1e-3 && q[a] < dims[a] - 1 + 1e-3) << "vertex " << v << " axis " << a;
  }
}

TEST_F(VolumeReaderTest, RealCtSeriesOpensSortedAlongItsNormal) {
  const std::string dir = real_file("dicom/CT5N", kPydicom + "dicomdirtests/98892001/CT5N");
  const hb::vtk::Volume volume = hb::vtk::read_volume(dir);
  EXPECT_EQ(volume.format, "DICOM series");
  EXPECT_EQ(volume.facts["dimensions"], nlohmann::json({16, 16, 5}));
  EXPECT_NEAR(volume.facts["spacing_mm"][0].get<double>(), 0.488281, 1e-5);
  EXPECT_NEAR(volume.facts["spacing_mm"][2].get<double>(), 2.5, 1e-4);
  // The lowest slice (z = -1.2375 mm) is slice 0.
  EXPECT_NEAR(volume.index_to_mm(2, 3), -1.2375, 1e-3);
  // Pixels where pydicom has them (stored 908, 923, 929; rescale intercept -1024, applied by
  // the reader: HU): DICOM (row r, column c) of that slice is voxel (c, 15 - r, 0), at
  // ImagePositionPatient + c dx X + r dy Y.
  EXPECT_EQ(volume.image->GetScalarComponentAsDouble(7, 12, 0, 0), 908.0 - 1024.0);   // r 3, c 7
  EXPECT_EQ(volume.image->GetScalarComponentAsDouble(15, 15, 0, 0), 923.0 - 1024.0);  // r 0, c 15
  EXPECT_EQ(volume.image->GetScalarComponentAsDouble(0, 0, 0, 0), 929.0 - 1024.0);    // r 15, c 0
  const Eigen::Vector4d r3c7 = volume.index_to_mm * Eigen::Vector4d(7, 12, 0, 1);
  EXPECT_NEAR(r3c7.x(), -72.199997 + 7 * 0.488281, 1e-3);
  EXPECT_NEAR(r3c7.y(), -143.0 + 3 * 0.488281, 1e-3);
  EXPECT_EQ(volume.intercept, 0.0);
  EXPECT_EQ(volume.facts["rescale_applied"]["intercept"], -1024.0);
  const hb::vtk::LoadedModel model = hb::vtk::load_model(dir);
  EXPECT_GT(model.mesh.triangle_count(), 10u);
}

TEST_F(VolumeReaderTest, DicomSeriesWithMissingSlicesNamesTheGap) {
  const std::string dir = real_file("dicom/CT2", kPydicom + "dicomdirtests/77654033/CT2");
  try {
    hb::vtk::read_volume(dir);
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("missing slices or mixed spacing"), std::string::npos) << m;
    EXPECT_NE(m.find("202.5"), std::string::npos) << m;
  }
}

TEST_F(VolumeReaderTest, DicomSeriesOfMixedOrientationAndSingleSlicesAreRefused) {
  EXPECT_THROW(hb::vtk::read_volume(real_file("dicom/MR2", kPydicom + "dicomdirtests/98892003/MR2")), hb::InvalidInput);
  fs::create_directories(dir_ / "single");
  fs::copy_file(real_file("dicom/CT_small.dcm", kPydicom + "CT_small.dcm"), dir_ / "single" / "CT_small.dcm",
                fs::copy_options::overwrite_existing);
  try {
    hb::vtk::read_volume(path("single"));
    FAIL() << "no error";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("single DICOM slice"), std::string::npos) << e.what();
  }
}

} // namespace

TEST_F(VolumeReaderTest, APreviewOfAReducedVolumeLiesWhereTheSurfaceIs) {
  // The window's live preview (volume_preview.h): the phantom (553 K voxels) reduced to at most
  // 40 K, i.e. blocks of 3 x 3 x 3 voxels, averaged and placed at the blocks' centres.
  const hb::vtk::CtPhantom phantom;
  const hb::vtk::Volume volume = hb::vtk::read_volume(path("phantom.nii.gz"));
  hb::vtk::VolumeSurfaceOptions options;
  options.iso = phantom.bone_iso();
  options.target_triangles = 500;  // ignored: a preview is not decimated
  const hb::vtk::VolumePreview preview = hb::vtk::volume_preview_surface(volume, options, path("phantom.nii.gz"), 40000);
  EXPECT_EQ(preview.shrink, 3);
  ASSERT_TRUE(preview.surface);
  const vtkIdType triangles = preview.surface->GetNumberOfPolys();
  hb::vtk::VolumeSurfaceOptions every = options;
  every.target_triangles = 0;
  const std::size_t full = hb::vtk::volume_surface(volume, every, path("phantom.nii.gz")).triangle_count();
  EXPECT_GT(triangles, 500);                    // not decimated to the target
  EXPECT_LT(std::size_t(triangles), full / 4);  // coarser than the full surface
  double worst = 0.0, mean = 0.0;
  for (vtkIdType i = 0; i < preview.surface->GetNumberOfPoints(); ++i) {
    double p[3];
    preview.surface->GetPoint(i, p);
    const double d = std::abs(phantom.bone_distance(Eigen::Vector3d(p[0], p[1], p[2])));
    worst = std::max(worst, d);
    mean += d;
  }
  mean /= double(preview.surface->GetNumberOfPoints());
  const double voxel = std::max({phantom.spacing_mm[0], phantom.spacing_mm[1], phantom.spacing_mm[2]});
  std::printf("preview at 1/%d: %lld triangles (full %zu), distance to the torus mean %.3f mm, max %.3f mm, %.3f s\n",
              preview.shrink, static_cast<long long>(triangles), full, mean, worst, preview.seconds);
  EXPECT_LT(mean, 0.35 * voxel);          // centred: no shift of a voxel along the grid
  EXPECT_LT(worst, preview.shrink * voxel);
  ASSERT_NE(preview.surface->GetPointData()->GetNormals(), nullptr);  // shaded in the view
  // A label map keeps its labels (subsampled, not averaged into a value no voxel holds).
  hb::vtk::VolumeSurfaceOptions label;
  label.label = 2;
  const hb::vtk::Volume labels = hb::vtk::read_volume(path("labels.nii"));
  const hb::vtk::VolumePreview bone = hb::vtk::volume_preview_surface(labels, label, path("labels.nii"), 40000);
  EXPECT_GT(bone.surface->GetNumberOfPolys(), 100);
  // An iso-value no voxel reaches names the file, as the full extraction does.
  hb::vtk::VolumeSurfaceOptions none;
  none.iso = 5000.0;
  try {
    hb::vtk::volume_preview_surface(volume, none, path("phantom.nii.gz"), 40000);
    ADD_FAILURE() << "an iso-value above every voxel gave a preview";
  } catch (const hb::InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("phantom.nii.gz"), std::string::npos) << e.what();
  }
}
