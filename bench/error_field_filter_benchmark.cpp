// vtkHapticBoxErrorFieldFilter with its own Embree scene (what `hapticbox field` runs) against
// the same filter given a shared exact reference (what the window runs: the session's
// vtkHapticBoxReferenceQueries, built once per model). One probe per vertex of the armadillo
// (52K triangles), a m=16 n=8 box baked once. Ratios within one run are what count.
#include "exact/exact_query.h"
#include "recipe/bake_recipe.h"
#include "mesh/mesh_io.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <benchmark/benchmark.h>
#include <vtkPolyData.h>
#include <memory>
#include <string>

namespace {

struct Model {
  hb::TriangleMesh mesh;
  vtkSmartPointer<vtkPolyData> surface;
  vtkSmartPointer<vtkHapticBoxSet> boxes;
  std::shared_ptr<const hb::ExactQuery> exact;
  Model() {
    mesh = hb::read_mesh(std::string(HB_DATASETS_DIR) + "/meshes/armadillo.off");
    surface = vtkHapticBoxUtilities::ToPolyData(mesh);
    hb::BakeRecipe recipe;
    recipe.options.params = {16, 8};
    boxes = vtkSmartPointer<vtkHapticBoxSet>::New();
    boxes->SetScene(std::make_shared<const hb::BoxScene>(hb::bake(mesh, recipe).scene));
    exact = std::make_shared<const hb::ExactQuery>(mesh);
  }
};

const Model& model() {
  static const Model m;
  return m;
}

void run(benchmark::State& state, bool shared) {
  const Model& m = model();
  for (auto _ : state) {
    vtkNew<vtkHapticBoxErrorFieldFilter> field;
    field->SetInputData(0, m.surface);
    field->SetBoxSetData(m.boxes);
    if (shared) field->SetExactQuery(m.exact);
    field->Update();
    if (!field->GetErrorField()) state.SkipWithError(field->GetLastError().c_str());
    benchmark::DoNotOptimize(field->GetOutput());
  }
}

void BM_ErrorFieldFilterBuildsItsExact(benchmark::State& state) { run(state, false); }
void BM_ErrorFieldFilterSharedExact(benchmark::State& state) { run(state, true); }

}  // namespace

BENCHMARK(BM_ErrorFieldFilterBuildsItsExact)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_ErrorFieldFilterSharedExact)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK_MAIN();
