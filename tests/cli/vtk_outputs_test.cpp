// The files ParaView and MeshLab users open, read back the way ParaView reads them: VTK's XML
// PolyData reader (arrays, field data, NaN) and VTK's delimited-text reader for samples.csv
// (ParaView's CSV reader), from the real binary on real files.
#include "mesh/generators.h"
#include "mesh/mesh_io.h"
#include "run_cli.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDelimitedTextReader.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkXMLPolyDataReader.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using hb::test::CommandResult;

class VtkOutputsTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("hb_vtk_outputs_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    hb::write_mesh(hb::make_torus(10.f, 3.f, 48, 16), (dir_ / "torus.off").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static CommandResult run(const std::string& args) { return hb::test::run_cli(args, dir_.string()); }
  static std::string read(const std::string& name) {
    std::ifstream in(path(name));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }
  static fs::path dir_;
};
fs::path VtkOutputsTest::dir_;

vtkSmartPointer<vtkPolyData> read_vtp(const std::string& file) {
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

double field_number(vtkPolyData* pd, const char* name) {
  vtkDataArray* a = pd->GetFieldData()->GetArray(name);
  return a ? a->GetComponent(0, 0) : std::nan("");
}

std::string field_string(vtkPolyData* pd, const char* name) {
  auto* a = vtkStringArray::SafeDownCast(pd->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfValues() > 0 ? a->GetValue(0) : std::string();
}

std::string units_of(vtkDataArray* a) {
  return a && a->GetInformation()->Has(vtkDataArray::UNITS_LABEL()) ? a->GetInformation()->Get(vtkDataArray::UNITS_LABEL())
                                                                    : std::string();
}

} // namespace

TEST_F(VtkOutputsTest, DecomposeWritesARealVtpWithAPieceIdCellArray) {
  const CommandResult r = run("decompose " + path("torus.off") + " -o " + path("pieces.vtp") + " --plane 0,0,0,1,0,0");
  ASSERT_EQ(r.code, 0) << r.err;
  vtkSmartPointer<vtkPolyData> pd = read_vtp(path("pieces.vtp"));
  ASSERT_EQ(pd->GetNumberOfPolys(), 48 * 16 * 2);
  vtkDataArray* ids = pd->GetCellData()->GetArray("PieceId");
  ASSERT_NE(ids, nullptr);
  std::set<int> seen;
  for (vtkIdType i = 0; i < ids->GetNumberOfTuples(); ++i) seen.insert(int(ids->GetComponent(i, 0)));
  EXPECT_EQ(seen, (std::set<int>{0, 1}));
  EXPECT_EQ(field_number(pd, "Pieces"), 2.0);
  EXPECT_FALSE(field_string(pd, "HapticBoxVersion").empty());
  // The pieces file bakes as the text form does.
  const CommandResult bake = run("bake " + path("torus.off") + " -o " + path("two.hbox") + " -m 4 -n 3 --pieces " +
                                 path("pieces.vtp") + " --json");
  ASSERT_EQ(bake.code, 0) << bake.err;
  EXPECT_EQ(nlohmann::json::parse(bake.out)["boxes"].get<int>(), 2);
}

TEST_F(VtkOutputsTest, DecomposeRefusesAnUnknownExtension) {
  const CommandResult r = run("decompose " + path("torus.off") + " -o " + path("pieces.vtk") + " --plane 0,0,0,1,0,0");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("pieces.vtk"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(".vtp"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(path("pieces.vtk")));
}

TEST_F(VtkOutputsTest, FieldCarriesUnitsProvenanceNanPiecesAndBoxOutlines) {
  ASSERT_EQ(run("decompose " + path("torus.off") + " -o " + path("p2.txt") + " --plane 0,0,0,0,1,0").code, 0);
  ASSERT_EQ(run("bake " + path("torus.off") + " -o " + path("p2.hbox") + " -m 4 -n 3 --pieces " + path("p2.txt")).code, 0);
  const CommandResult r = run("field " + path("p2.hbox") + " " + path("torus.off") + " -o " + path("f.vtp") +
                              " --seed 5 --workspace stiffness=300,real-size");
  ASSERT_EQ(r.code, 0) << r.err;
  vtkSmartPointer<vtkPolyData> pd = read_vtp(path("f.vtp"));
  ASSERT_GT(pd->GetNumberOfPoints(), 0);
  // Provenance.
  EXPECT_EQ(field_number(pd, "Boxes"), 2.0);
  EXPECT_EQ(field_number(pd, "MMin"), 4.0);
  EXPECT_EQ(field_number(pd, "NMax"), 3.0);
  EXPECT_EQ(field_number(pd, "Seed"), 5.0);
  EXPECT_EQ(field_number(pd, "Stiffness_N_per_m"), 300.0);
  EXPECT_NEAR(field_number(pd, "MetresPerUnit"), 0.001, 1e-9);
  EXPECT_EQ(field_number(pd, "ProbesPerPoint"), 1.0);
  EXPECT_EQ(field_string(pd, "BoxFile"), path("p2.hbox"));
  EXPECT_FALSE(field_string(pd, "HapticBoxVersion").empty());
  EXPECT_NE(field_string(pd, "NoData").find("NaN"), std::string::npos);
  // Units, on the arrays and in the field data.
  vtkDataArray* abs_err = pd->GetPointData()->GetArray("AbsoluteForceError");
  ASSERT_NE(abs_err, nullptr);
  EXPECT_EQ(units_of(abs_err), "N");
  EXPECT_EQ(units_of(pd->GetPointData()->GetArray("ExactForce")), "N");
  EXPECT_EQ(std::string(pd->GetPointData()->GetScalars()->GetName()), "PerceptibleRatio");
  auto* units = vtkStringArray::SafeDownCast(pd->GetFieldData()->GetAbstractArray("Units"));
  ASSERT_NE(units, nullptr);
  bool listed = false;
  for (vtkIdType i = 0; i < units->GetNumberOfValues(); ++i) listed |= units->GetValue(i) == "AbsoluteForceError: N";
  EXPECT_TRUE(listed);
  // NaN is no data: a point none of whose probes touched the exact surface has no relative
  // error, while its absolute error is a number.
  vtkDataArray* rel = pd->GetPointData()->GetArray("RelativeForceError");
  vtkDataArray* exact_in = pd->GetPointData()->GetArray("ExactContactFraction");
  ASSERT_NE(rel, nullptr);
  ASSERT_NE(exact_in, nullptr);
  std::size_t nan_points = 0;
  for (vtkIdType i = 0; i < rel->GetNumberOfTuples(); ++i) {
    if (exact_in->GetComponent(i, 0) == 0.0) EXPECT_TRUE(std::isnan(rel->GetComponent(i, 0))) << i;
    nan_points += std::isnan(rel->GetComponent(i, 0));
    EXPECT_FALSE(std::isnan(abs_err->GetComponent(i, 0))) << i;
  }
  EXPECT_NE(r.out.find(std::to_string(nan_points) + " points with no data"), std::string::npos) << r.out;
  // Pieces of the scene, per triangle.
  vtkDataArray* piece = pd->GetCellData()->GetArray("PieceId");
  ASSERT_NE(piece, nullptr);
  EXPECT_EQ(piece->GetRange()[0], 0.0);
  EXPECT_EQ(piece->GetRange()[1], 1.0);
  // Box outlines beside the field.
  vtkSmartPointer<vtkPolyData> boxes = read_vtp(path("f_boxes.vtp"));
  EXPECT_EQ(boxes->GetNumberOfLines(), 24);
  ASSERT_NE(boxes->GetCellData()->GetArray("PieceId"), nullptr);
  EXPECT_EQ(boxes->GetCellData()->GetArray("M")->GetRange()[1], 4.0);
}

TEST_F(VtkOutputsTest, SamplesCsvReadsNoDataAsNanInParaViewsCsvReader) {
  const CommandResult r = run("report " + path("torus.off") + " -o " + path("rep") +
                              " -m 3 -n 2 --samples 2000 --rounds 1 --sweep none --cache none --field probes=0");
  ASSERT_EQ(r.code, 0) << r.err;
  vtkNew<vtkDelimitedTextReader> reader;  // what ParaView's CSV reader runs
  reader->SetFileName(path("rep/samples.csv").c_str());
  reader->SetHaveHeaders(true);
  reader->SetDetectNumericColumns(true);
  reader->Update();
  vtkTable* t = reader->GetOutput();
  ASSERT_EQ(t->GetNumberOfRows(), 2000);
  auto* err = vtkDataArray::SafeDownCast(t->GetColumnByName("relative_force_error"));
  auto* exact = vtkDataArray::SafeDownCast(t->GetColumnByName("exact_contact"));
  auto* approx = vtkDataArray::SafeDownCast(t->GetColumnByName("approx_contact"));
  ASSERT_NE(err, nullptr);
  ASSERT_NE(exact, nullptr);
  ASSERT_NE(approx, nullptr);
  std::size_t no_data = 0;
  for (vtkIdType i = 0; i < t->GetNumberOfRows(); ++i) {
    const bool both = exact->GetComponent(i, 0) == 1.0 && approx->GetComponent(i, 0) == 1.0;
    EXPECT_EQ(std::isnan(err->GetComponent(i, 0)), !both) << "row " << i;
    no_data += !both;
  }
  EXPECT_GT(no_data, 0u);  // missed, false or no contacts exist at m=3 and must not read as 0
  // summary.json: a baked box has its bake time and its refine flag in its own row.
  const auto s = nlohmann::json::parse(read("rep/summary.json"));
  EXPECT_TRUE(s["box"]["bake_seconds"].is_number());
  EXPECT_EQ(s["box"]["refine"], false);
}

TEST_F(VtkOutputsTest, SummaryOfALoadedRefinedBoxSaysNullBakeTimeAndRefine) {
  ASSERT_EQ(run("bake " + path("torus.off") + " -o " + path("ref.hbox") + " -m 4 -n 3 --refine").code, 0);
  const CommandResult r = run("report " + path("ref.hbox") + " " + path("torus.off") + " -o " + path("rep_ref") +
                              " --samples 300 --rounds 1 --sweep none --cache none --field probes=0");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto s = nlohmann::json::parse(read("rep_ref/summary.json"));
  EXPECT_TRUE(s["box"]["bake_seconds"].is_null());
  EXPECT_EQ(s["box"]["refine"], true);
  bool own = false;
  for (const auto& row : s["sweep"])
    if (row["method"] == "haptic_box") {
      own = true;
      EXPECT_EQ(row["refine"], true);
      EXPECT_TRUE(row["bake_seconds"].is_null());
    }
  EXPECT_TRUE(own);
}

TEST_F(VtkOutputsTest, ServoTrajectoryIsAPolylineVtpInTheModelFrame) {
  const CommandResult r = run("servo plane --device virtual --seconds 0.3 --no-realtime --trajectory " + path("t.vtp") +
                              " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  vtkSmartPointer<vtkPolyData> pd = read_vtp(path("t.vtp"));
  ASSERT_EQ(pd->GetNumberOfLines(), 1);
  EXPECT_EQ(pd->GetNumberOfPoints(), j["trajectory_points"].get<vtkIdType>());
  EXPECT_GT(pd->GetNumberOfPoints(), 100);
  for (const char* name : {"Time", "Force", "ForceMagnitude", "Depth", "Contact", "QueryTime", "SafetyFlags"})
    EXPECT_NE(pd->GetPointData()->GetArray(name), nullptr) << name;
  EXPECT_EQ(units_of(pd->GetPointData()->GetArray("Force")), "N");
  EXPECT_EQ(units_of(pd->GetPointData()->GetArray("Time")), "s");
  EXPECT_EQ(field_number(pd, "Rate_Hz"), 1000.0);
  // The plane scene spans 80 mm around z = 0: the tips stay near it.
  double b[6];
  pd->GetBounds(b);
  EXPECT_LT(std::fabs(b[4]), 60.0);
  EXPECT_FALSE(fs::exists(path("t.vtp.hbslog.tmp")));  // the temporary log is gone
  // A recorded log exports the same way afterwards.
  ASSERT_EQ(run("servo plane --device virtual --seconds 0.2 --no-realtime --record " + path("run.hbslog")).code, 0);
  const CommandResult t = run("trajectory " + path("run.hbslog") + " plane -o " + path("t2.vtp"));
  ASSERT_EQ(t.code, 0) << t.err;
  EXPECT_GT(read_vtp(path("t2.vtp"))->GetNumberOfPoints(), 50);
  EXPECT_EQ(run("trajectory " + path("run.hbslog") + " plane -o " + path("t2.csv")).code, 2);
}
