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
#include <vtkStringArray.h>

vtkStandardNewMacro(vtkHapticBoxDecompositionFilter);

vtkHapticBoxDecompositionFilter::vtkHapticBoxDecompositionFilter() = default;
vtkHapticBoxDecompositionFilter::~vtkHapticBoxDecompositionFilter() = default;

void vtkHapticBoxDecompositionFilter::SetOptions(const hb::AutoDecompositionOptions& o) {
  this->SetThreshold(o.threshold);
  this->SetMinAreaFraction(o.min_area_fraction);
  this->SetMaxPieces(o.max_pieces);
  this->SetLeaves(o.leaves);
  this->SetLines(o.lines);
  this->SetSeed(o.seed);
}

hb::AutoDecompositionOptions vtkHapticBoxDecompositionFilter::GetOptions() const {
  hb::AutoDecompositionOptions o;
  o.threshold = this->Threshold;
  o.min_area_fraction = this->MinAreaFraction;
  o.max_pieces = this->MaxPieces;
  o.leaves = this->Leaves;
  o.lines = this->Lines;
  o.seed = this->Seed;
  return o;
}

int vtkHapticBoxDecompositionFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                                 vtkInformationVector* outputVector) {
  this->LastError.clear();
  try {
    vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
    vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
    this->UpdateProgress(0.0);
    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(input);
    hb::AutoDecompositionOptions options = this->GetOptions();
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
    vtkNew<vtkStringArray> signature;
    signature->SetName("DecompositionOptions");
    signature->InsertNextValue(vtkHapticBoxUtilities::DecompositionSignature(options));
    output->GetFieldData()->AddArray(signature);
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    this->LastError = e.what();
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
