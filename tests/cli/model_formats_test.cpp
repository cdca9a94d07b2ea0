// The hapticbox command on volumes, CAD solids and scenes, end to end: the CT phantom and a STEP
// file written here, the real DICOM series and MRI from Debian's pydicom and nibabel; `info`
// prints what a user needs to choose settings; bad input names the file and the cause.
#include "run_cli.h"
#include "volume_phantom.h"
#include <gtest/gtest.h>
#include <vtkImageData.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#ifdef HB_HAVE_OCCT
#include "cad_reader.h"
#endif

namespace {

namespace fs = std::filesystem;
using Result = hb::test::CommandResult;

std::string real_file(const std::string& fetched, const std::string& debian) {
  const fs::path a = fs::path(HB_DATASETS_DIR) / "volumes" / fetched;
  return fs::exists(a) ? a.string() : debian;
}

class ModelFormatsCliTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_cli_models_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const hb::vtk::CtPhantom phantom;
    hb::vtk::write_volume(hb::vtk::make_ct_phantom(phantom), phantom.index_to_mm(), path("phantom.mha"));
    hb::vtk::write_volume(hb::vtk::make_phantom_labels(phantom), phantom.index_to_mm(), path("labels.nii.gz"));
#ifdef HB_HAVE_OCCT
    hb::vtk::write_reference_solid_step(path("solid.step"), 10.0, 30.0);
#endif
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static Result run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static fs::path dir_;
};
fs::path ModelFormatsCliTest::dir_;

TEST_F(ModelFormatsCliTest, InfoOnAVolumePrintsDimensionsSpacingRangeLabelsAndUnit) {
  const Result r = run("info " + path("labels.nii.gz") + " --volume label=2 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["kind"], "volume");
  EXPECT_EQ(j["format"], "NIfTI");
  EXPECT_EQ(j["dimensions"], nlohmann::json({96, 96, 60}));
  EXPECT_NEAR(j["spacing_mm"][2].get<double>(), 1.4, 1e-5);
  EXPECT_TRUE(j["labels"].contains("1"));
  EXPECT_EQ(j["label"], 2);
  EXPECT_EQ(j["unit"], "mm");
  EXPECT_GT(j["triangles"].get<double>(), 1000.0);
  const Result text = run("info " + path("phantom.mha"));
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("value_range: [-1000, 700]"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("iso_source: automatic"), std::string::npos) << text.out;
}

TEST_F(ModelFormatsCliTest, VolumeBakesAndEvaluatesEndToEnd) {
  const Result bake = run("bake " + path("phantom.mha") + " --volume iso=-480 -o " + path("p.hbox") + " -m 8 -n 6 --json");
  ASSERT_EQ(bake.code, 0) << bake.err;
  EXPECT_NE(bake.err.find("iso -480"), std::string::npos) << bake.err;
  const Result eval = run("eval " + path("p.hbox") + " " + path("phantom.mha") + " --volume iso=-480 --samples 1000 --json");
  ASSERT_EQ(eval.code, 0) << eval.err;
  EXPECT_EQ(eval.err.find("different mesh"), std::string::npos) << eval.err;
  const auto e = nlohmann::json::parse(eval.out);
  EXPECT_GT(e["contact_agreement"].get<double>(), 0.95);
  // Evaluating against another iso-value is noticed.
  const Result other = run("eval " + path("p.hbox") + " " + path("phantom.mha") + " --volume iso=370 --samples 200 --json");
  EXPECT_EQ(other.code, 1);
  EXPECT_NE(other.err.find("different mesh"), std::string::npos) << other.err;
}

TEST_F(ModelFormatsCliTest, BadVolumeInputNamesTheFileAndTheCause) {
  const Result iso = run("bake " + path("phantom.mha") + " --volume iso=9999 -o " + path("x.hbox"));
  EXPECT_EQ(iso.code, 1);
  EXPECT_NE(iso.err.find("phantom.mha: no voxel crosses the iso-value 9999"), std::string::npos) << iso.err;
  const Result both = run("info " + path("phantom.mha") + " --volume iso=1,label=2");
  EXPECT_EQ(both.code, 2) << both.err;
  const std::string gap = real_file("dicom/CT2", "/usr/lib/python3/dist-packages/pydicom/data/test_files/dicomdirtests/77654033/CT2");
  const Result series = run("info " + gap);
  EXPECT_EQ(series.code, 1);
  EXPECT_NE(series.err.find("missing slices"), std::string::npos) << series.err;
}

TEST_F(ModelFormatsCliTest, RealDicomSeriesAndMriOpen) {
  const std::string ct = real_file("dicom/CT5N", "/usr/lib/python3/dist-packages/pydicom/data/test_files/dicomdirtests/98892001/CT5N");
  const Result r = run("info " + ct + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["format"], "DICOM series");
  const std::string mri = real_file("anatomical.nii", "/usr/lib/python3/dist-packages/nibabel/tests/data/anatomical.nii");
  const Result m = run("info " + mri + " --json");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(nlohmann::json::parse(m.out)["format"], "NIfTI");
}

#ifdef HB_HAVE_OCCT
TEST_F(ModelFormatsCliTest, StepInfoAndBakeWithFacesAsPieces) {
  const Result info = run("info " + path("solid.step") + " --json");
  ASSERT_EQ(info.code, 0) << info.err;
  const auto j = nlohmann::json::parse(info.out);
  EXPECT_EQ(j["solids"], 2);
  EXPECT_EQ(j["faces"], 4);
  const auto& box = j["bounding_box_mm"];
  double d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += std::pow(box[1][i].get<double>() - box[0][i].get<double>(), 2);
  const double diagonal = std::sqrt(d2);  // 0.01 N / 1500 N/m at the device, the solid fitted to 80 mm
  EXPECT_NEAR(j["chordal_deviation_mm"].get<double>(), std::clamp(0.01 / 1500.0 * diagonal / 0.08, 1e-4 * diagonal, 1e-2 * diagonal), 1e-9);
  EXPECT_TRUE(j.contains("bounding_box_mm"));
  const Result bake = run("bake " + path("solid.step") + " --pieces faces -o " + path("s.hbox") + " -m 8 -n 6");
  ASSERT_EQ(bake.code, 0) << bake.err;
  const auto boxes = nlohmann::json::parse(run("info " + path("s.hbox") + " --json").out);
  EXPECT_EQ(boxes["boxes"], 4);
  const Result not_cad = run("bake " + path("phantom.mha") + " --pieces faces -o " + path("y.hbox"));
  EXPECT_EQ(not_cad.code, 2) << not_cad.err;
}
#endif

} // namespace
