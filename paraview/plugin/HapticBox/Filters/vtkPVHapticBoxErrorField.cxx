#include "vtkPVHapticBoxErrorField.h"
#include "error_colour_map.h"
#include "errors.h"
#include "polydata_files.h"
#include "pv_scene_source.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkDataArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkLookupTable.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnsignedCharArray.h>
#include <exception>

vtkStandardNewMacro(vtkPVHapticBoxErrorField);

vtkPVHapticBoxErrorField::vtkPVHapticBoxErrorField() { this->SetPerceptual("nominal"); }

vtkPVHapticBoxErrorField::~vtkPVHapticBoxErrorField() {
  this->SetBoxFile(nullptr);
  this->SetWorkspace(nullptr);
  this->SetPerceptual(nullptr);
}

void vtkPVHapticBoxErrorField::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "BoxFile: " << (this->BoxFile ? this->BoxFile : "(default bake)") << "\n";
}

int vtkPVHapticBoxErrorField::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                          vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  try {
    const vtkSmartPointer<vtkPolyData> surface = hb::paraview::input_surface(inputVector);
    const double diagonal = vtkHapticBoxUtilities::ToTriangleMesh(surface).bounds().diagonal();  // as `field`
    const std::string workspace = this->Workspace ? this->Workspace : "";
    vtkNew<vtkHapticBoxSet> boxes;
    boxes->SetScene(hb::paraview::scene_for(this->BoxFile ? this->BoxFile : "", surface));
    vtkNew<vtkHapticBoxErrorFieldFilter> field;
    field->SetInputData(surface);
    field->SetBoxSetData(boxes);
    field->SetProbesPerPoint(this->ProbesPerPoint);
    field->SetSeed(vtkTypeUInt64(this->Seed));
    field->SetWorkspace(hb::paraview::workspace_for(diagonal, workspace),
                        hb::paraview::judge_for(workspace, this->Perceptual ? this->Perceptual : ""));
    if (this->SampleMode == 1) {
      field->SetSampleModeToEven();
      field->SetNumberOfSamples(this->NumberOfSamples);
    }
    field->Update();
    if (!field->GetLastError().empty()) throw hb::Error(field->GetLastError());
    output->ShallowCopy(field->GetOutput());
    // The product's perceptible colour scale, as RGBA (colour by it with Map Scalars off).
    double plain[3];
    hb::vtk::plain_surface_colour(plain);
    vtkSmartPointer<vtkLookupTable> table = hb::vtk::perceptible_table(plain);
    if (vtkDataArray* ratio = output->GetPointData()->GetArray("PerceptibleRatio")) {
      vtkSmartPointer<vtkUnsignedCharArray> colours;
      colours.TakeReference(table->MapScalars(ratio, VTK_COLOR_MODE_MAP_SCALARS, 0));
      colours->SetName("PerceptibleColour");
      output->GetPointData()->AddArray(colours);
      output->GetPointData()->SetActiveScalars("PerceptibleRatio");
    }
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}
