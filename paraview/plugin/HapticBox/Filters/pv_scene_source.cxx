#include "pv_scene_source.h"
#include "errors.h"
#include "store/box_file.h"
#include "recipe/bake_recipe.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxSet.h"
#include <vtkInformationVector.h>
#include <vtkPolyData.h>
#include <filesystem>
#include <map>
#include <mutex>

namespace hb::paraview {

vtkSmartPointer<vtkPolyData> input_surface(vtkInformationVector** inputVector) {
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->ShallowCopy(vtkPolyData::GetData(inputVector[0]));
  return surface;
}

std::shared_ptr<const BoxScene> scene_for(const std::string& box_file, vtkPolyData* surface) {
  if (box_file.empty()) {
    vtkNew<vtkHapticBoxBakeFilter> bake;
    bake->SetRecipe(default_recipe());
    bake->SetInputData(surface);
    bake->Update();
    if (!bake->GetLastError().empty()) throw Error("bake: " + bake->GetLastError());
    return bake->GetBoxSet()->GetScene();
  }
  // One load per file and modification time: a filter re-executing for a property loads nothing.
  static std::mutex mutex;
  static std::map<std::string, std::pair<std::filesystem::file_time_type, std::shared_ptr<const BoxScene>>> loaded;
  std::error_code ec;
  const auto stamp = std::filesystem::last_write_time(box_file, ec);
  std::lock_guard<std::mutex> lock(mutex);
  auto it = loaded.find(box_file);
  if (!ec && it != loaded.end() && it->second.first == stamp) return it->second.second;
  auto scene = std::make_shared<const BoxScene>(load_box_file(box_file));
  loaded[box_file] = {stamp, scene};
  return scene;
}

Workspace workspace_for(double model_diagonal, const std::string& spec) {
  WorkspaceOptions options;
  parse_workspace_spec(spec, options);
  return make_workspace(model_diagonal, options);
}

PerceptualJudge judge_for(const std::string& workspace_spec, const std::string& perceptual) {
  WorkspaceOptions options;
  parse_workspace_spec(workspace_spec, options);
  PerceptualJudge judge;
  judge.thresholds = parse_thresholds(perceptual.empty() ? "nominal" : perceptual);
  judge.max_force_n = options.max_force_n;
  return judge;
}

} // namespace hb::paraview
