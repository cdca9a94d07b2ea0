#include "vtkPVHapticBoxBake.h"
#include "errors.h"
#include "pv_scene_source.h"
#include "store/box_file.h"
#include "perception/budget_report.h"
#include "recipe/bake_recipe.h"
#include "vtkHapticBoxBakeFilter.h"
#include "vtkHapticBoxSet.h"
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <exception>

vtkStandardNewMacro(vtkPVHapticBoxBake);

vtkPVHapticBoxBake::vtkPVHapticBoxBake() { this->SetNumberOfOutputPorts(2); }

vtkPVHapticBoxBake::~vtkPVHapticBoxBake() {
  this->SetOutputFile(nullptr);
  this->SetBudget(nullptr);
}

int vtkPVHapticBoxBake::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector) {
  try {
    const vtkSmartPointer<vtkPolyData> surface = hb::paraview::input_surface(inputVector);
    hb::BakeRecipe recipe = hb::default_recipe();
    if (this->Budget && *this->Budget) recipe.budget.budget = hb::parse_budget(this->Budget);
    vtkNew<vtkHapticBoxBakeFilter> bake;
    bake->SetRecipe(recipe);
    bake->SetInputData(surface);
    bake->Update();
    if (!bake->GetLastError().empty()) throw hb::Error(bake->GetLastError());
    if (this->OutputFile && *this->OutputFile) hb::save_box_file(*bake->GetBoxSet()->GetScene(), this->OutputFile);
    vtkPolyData::GetData(outputVector, 0)->ShallowCopy(bake->GetOutput(1));
    vtkPolyData::GetData(outputVector, 1)->ShallowCopy(bake->GetOutput(3));
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}
