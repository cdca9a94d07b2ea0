// 1. convert the surface; 2. hb::decompose_auto with progress/abort; 3. piece ids as cell data.
#include "vtkHapticBoxDecompositionFilter.h"
#include "decomposition/auto_decomposition.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

vtkStandardNewMacro(vtkHapticBoxDecompositionFilter);

vtkHapticBoxDecompositionFilter::vtkHapticBoxDecompositionFilter() = default;
vtkHapticBoxDecompositionFilter::~vtkHapticBoxDecompositionFilter() = default;

int vtkHapticBoxDecompositionFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                                 vtkInformationVector* outputVector) {
  try {
    vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
    vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
    this->UpdateProgress(0.0);
    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(input);
    hb::AutoDecompositionOptions options;
    options.threshold = this->Threshold;
    options.min_area_fraction = this->MinAreaFraction;
    options.max_pieces = this->MaxPieces;
    options.leaves = this->Leaves;
    options.lines = this->Lines;
    options.seed = this->Seed;
    options.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, 0.02, 0.98);
    const hb::Decomposition d = hb::decompose_auto(mesh, options);

    output->ShallowCopy(vtkHapticBoxUtilities::ToPolyData(mesh));
    vtkNew<vtkIntArray> piece;
    piece->SetName("PieceId");
    piece->SetNumberOfTuples(vtkIdType(mesh.triangle_count()));
    vtkNew<vtkDoubleArray> probability;
    probability->SetName("PocketProbability");
    probability->SetNumberOfTuples(vtkIdType(mesh.triangle_count()));
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
      const std::uint32_t p = d.piece_of_triangle[t];
      piece->SetValue(vtkIdType(t), int(p));
      probability->SetValue(vtkIdType(t), p < d.estimated_probability.size() ? d.estimated_probability[p] : 0.0);
    }
    output->GetCellData()->AddArray(piece);
    output->GetCellData()->AddArray(probability);
    output->GetCellData()->SetActiveScalars("PieceId");
    vtkNew<vtkIntArray> count;
    count->SetName("PieceCount");
    count->InsertNextValue(int(d.piece_count));
    output->GetFieldData()->AddArray(count);
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
}

void vtkHapticBoxDecompositionFilter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Threshold: " << this->Threshold << "\n"
     << indent << "MinAreaFraction: " << this->MinAreaFraction << "\n"
     << indent << "MaxPieces: " << this->MaxPieces << "\n"
     << indent << "Leaves: " << this->Leaves << "\n"
     << indent << "Lines: " << this->Lines << "\n"
     << indent << "Seed: " << this->Seed << "\n";
}
