#include "vtkPVHapticBoxDecomposition.h"
#include "errors.h"
#include "pv_scene_source.h"
#include "recipe/bake_recipe.h"
#include "vtkHapticBoxDecompositionFilter.h"
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <exception>

vtkStandardNewMacro(vtkPVHapticBoxDecomposition);

vtkPVHapticBoxDecomposition::vtkPVHapticBoxDecomposition() {
  // The default bake's automatic pieces (hb::default_recipe), so that its bake takes them as its own.
  const hb::AutoDecompositionOptions d = hb::default_recipe().pieces.automatic;
  this->Threshold = d.threshold;
  this->MaxPieces = d.max_pieces;
  this->Seed = int(d.seed);
}

int vtkPVHapticBoxDecomposition::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                             vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  try {
    const vtkSmartPointer<vtkPolyData> surface = hb::paraview::input_surface(inputVector);
    vtkNew<vtkHapticBoxDecompositionFilter> pieces;
    hb::AutoDecompositionOptions options = hb::default_recipe().pieces.automatic;
    options.threshold = this->Threshold;
    options.max_pieces = this->MaxPieces;
    options.seed = std::uint64_t(this->Seed);
    pieces->SetOptions(options);
    pieces->SetInputData(surface);
    pieces->Update();
    if (!pieces->GetLastError().empty()) throw hb::Error(pieces->GetLastError());
    output->ShallowCopy(pieces->GetOutput());
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}
