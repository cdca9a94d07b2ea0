#include "evaluation/error_field.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "test_meshes.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxSet.h"
#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <cmath>
#include <memory>

namespace {

struct Pipeline {
  vtkSmartPointer<vtkPolyData> surface = hb::test::SpherePolyData(3);
  vtkNew<vtkHapticBoxBakeFilter> bake;
  vtkNew<vtkHapticBoxErrorFieldFilter> field;
  Pipeline() {
    bake->SetInputData(surface);
    bake->SetM(8);
    bake->SetN(4);
    field->SetInputData(surface);
    field->SetBoxSetConnection(bake->GetOutputPort(0));
  }
};

} // namespace

TEST(ErrorFieldFilterTest, VertexFieldHasOneValuePerVertexAndNamedArrays) {
  Pipeline p;
  p.field->SetSeed(5);
  p.field->Update();
  vtkPolyData* out = p.field->GetOutput();
  EXPECT_EQ(out->GetNumberOfPoints(), p.surface->GetNumberOfPoints());
  EXPECT_EQ(out->GetNumberOfPolys(), p.surface->GetNumberOfPolys());
  for (const char* name : {"ExactForce", "ApproxForce", "RelativeForceError", "DirectionError",
                           "ContactDisagreement", "ExactContactFraction", "Normals"}) {
    vtkDataArray* a = out->GetPointData()->GetArray(name);
    ASSERT_NE(a, nullptr) << name;
    EXPECT_EQ(a->GetNumberOfTuples(), out->GetNumberOfPoints()) << name;
  }
  EXPECT_EQ(out->GetPointData()->GetArray("ExactForce")->GetNumberOfComponents(), 3);
  EXPECT_NE(out->GetFieldData()->GetArray("ErrorFieldSeconds"), nullptr);
}

TEST(ErrorFieldFilterTest, ValuesMatchTheCore) {
  Pipeline p;
  p.field->SetSeed(9);
  p.field->SetProbesPerPoint(3);
  p.field->Update();
  vtkPolyData* out = p.field->GetOutput();
  // The same computation straight through the core.
  const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(p.surface);
  const hb::ExactQuery exact(mesh);
  hb::ErrorFieldOptions options;
  options.seed = 9;
  options.probes_per_point = 3;
  const hb::ErrorField field = hb::compute_error_field(*p.bake->GetBoxSet()->GetScene(), exact,
                                                       hb::surface_points_at_vertices(mesh),
                                                       mesh.bounds().diagonal(), options);
  ASSERT_EQ(field.size(), std::size_t(out->GetNumberOfPoints()));
  vtkDataArray* err = out->GetPointData()->GetArray("RelativeForceError");
  vtkDataArray* fe = out->GetPointData()->GetArray("ExactForce");
  vtkDataArray* dis = out->GetPointData()->GetArray("ContactDisagreement");
  int compared = 0;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    const float core = field.force_error[std::size_t(i)];
    if (std::isnan(core)) {
      EXPECT_TRUE(std::isnan(err->GetComponent(i, 0)));
    } else {
      EXPECT_FLOAT_EQ(float(err->GetComponent(i, 0)), core);
      ++compared;
    }
    EXPECT_FLOAT_EQ(float(fe->GetComponent(i, 2)), field.exact_force[std::size_t(i)].z());
    EXPECT_FLOAT_EQ(float(dis->GetComponent(i, 0)), field.contact_disagreement[std::size_t(i)]);
  }
  EXPECT_GT(compared, out->GetNumberOfPoints() / 2);
}

TEST(ErrorFieldFilterTest, SphereFieldIsSmallAndMostlyInContact) {
  Pipeline p;
  p.bake->SetM(16);
  p.bake->SetN(8);
  p.field->Update();
  vtkPolyData* out = p.field->GetOutput();
  vtkDataArray* exactIn = out->GetPointData()->GetArray("ExactContactFraction");
  vtkDataArray* err = out->GetPointData()->GetArray("RelativeForceError");
  double sumIn = 0.0;
  std::vector<double> errors;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    sumIn += exactIn->GetComponent(i, 0);
    if (!std::isnan(err->GetComponent(i, 0))) errors.push_back(err->GetComponent(i, 0));
  }
  EXPECT_GT(sumIn / double(out->GetNumberOfPoints()), 0.95);  // every probe reaches the sphere
  ASSERT_FALSE(errors.empty());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.25);
}

TEST(ErrorFieldFilterTest, EvenSamplingGivesTheRequestedPoints) {
  Pipeline p;
  p.field->SetSampleModeToEven();
  p.field->SetNumberOfSamples(500);
  p.field->Update();
  vtkPolyData* out = p.field->GetOutput();
  EXPECT_EQ(out->GetNumberOfPoints(), 500);
  EXPECT_EQ(out->GetNumberOfVerts(), 500);
  EXPECT_EQ(out->GetPointData()->GetArray("ApproxForce")->GetNumberOfTuples(), 500);
}

TEST(ErrorFieldFilterTest, MissingBoxesFail) {
  vtkNew<vtkHapticBoxErrorFieldFilter> field;
  field->SetInputData(hb::test::SpherePolyData(1));
  vtkNew<vtkHapticBoxSet> empty;
  field->SetBoxSetData(empty);
  vtkObject::GlobalWarningDisplayOff();
  field->Update();
  vtkObject::GlobalWarningDisplayOn();
  EXPECT_EQ(field->GetOutput()->GetNumberOfPoints(), 0);
}

#include <vtkCallbackCommand.h>

TEST(ErrorFieldFilterTest, AbortFromAProgressObserverStopsTheField) {
  vtkSmartPointer<vtkPolyData> surface = hb::test::SpherePolyData(6);  // 40,962 vertices: several blocks
  vtkNew<vtkHapticBoxBakeFilter> bake;
  bake->SetInputData(surface);
  bake->SetM(4);
  bake->SetN(3);
  vtkNew<vtkHapticBoxErrorFieldFilter> field;
  field->SetInputData(surface);
  field->SetBoxSetConnection(bake->GetOutputPort(0));
  bake->Update();
  vtkNew<vtkCallbackCommand> onProgress;
  onProgress->SetCallback([](vtkObject* caller, unsigned long, void*, void*) {
    auto* algorithm = static_cast<vtkHapticBoxErrorFieldFilter*>(caller);
    if (algorithm->GetProgress() > 0.06) algorithm->SetAbortExecute(1);
  });
  field->AddObserver(vtkCommand::ProgressEvent, onProgress);
  vtkObject::GlobalWarningDisplayOff();
  field->Update();
  vtkObject::GlobalWarningDisplayOn();
  EXPECT_EQ(field->GetOutput()->GetPointData()->GetArray("RelativeForceError"), nullptr);
}

// An exact query given to the filter (a session's or report's references, built once) is the
// one compared with: no Embree scene of its own, the same values as when it builds one; an
// exact query over another mesh is refused, naming both.
TEST(ErrorFieldFilterTest, SharedExactQueryIsUsedNotBuiltAgain) {
  Pipeline p;
  p.field->SetSeed(4);
  p.field->Update();
  ASSERT_TRUE(p.field->GetBuiltExact());
  vtkSmartPointer<vtkFloatArray> built = vtkFloatArray::SafeDownCast(p.field->GetOutput()->GetPointData()->GetArray("RelativeForceError"));
  ASSERT_NE(built, nullptr);
  vtkNew<vtkFloatArray> before;
  before->DeepCopy(built);

  auto mesh = std::make_shared<const hb::TriangleMesh>(vtkHapticBoxUtilities::ToTriangleMesh(p.surface));
  auto exact = std::make_shared<const hb::ExactQuery>(*mesh);
  p.field->SetExactQuery(std::shared_ptr<const hb::ExactQuery>(exact, exact.get()));
  p.field->Update();
  ASSERT_TRUE(p.field->GetLastError().empty()) << p.field->GetLastError();
  EXPECT_FALSE(p.field->GetBuiltExact());
  vtkDataArray* shared = p.field->GetOutput()->GetPointData()->GetArray("RelativeForceError");
  ASSERT_EQ(shared->GetNumberOfTuples(), before->GetNumberOfTuples());
  for (vtkIdType i = 0; i < shared->GetNumberOfTuples(); ++i) {
    const double a = shared->GetTuple1(i), b = before->GetTuple1(i);
    EXPECT_TRUE((std::isnan(a) && std::isnan(b)) || a == b) << i;
  }

  const hb::TriangleMesh other = hb::make_sphere(1.f, 2);
  auto wrong = std::make_shared<const hb::ExactQuery>(other);
  p.field->SetExactQuery(wrong);
  vtkObject::GlobalWarningDisplayOff();
  p.field->Update();
  vtkObject::GlobalWarningDisplayOn();
  EXPECT_NE(p.field->GetLastError().find("another mesh"), std::string::npos) << p.field->GetLastError();
}
