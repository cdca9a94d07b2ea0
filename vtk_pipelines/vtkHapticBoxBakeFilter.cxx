// 1. convert the surface, read the piece ids if any (hb::bake numbers them compactly);
// 2. hb::bake with the recipe and a progress callback that also honours AbortExecute;
// 3. outputs: the scene, the PBB outlines and the position points for display.
#include "vtkHapticBoxBakeFilter.h"
#include "errors.h"
#include <algorithm>
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDemandDrivenPipeline.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

vtkStandardNewMacro(vtkHapticBoxBakeFilter);

vtkHapticBoxBakeFilter::vtkHapticBoxBakeFilter() {
  this->SetNumberOfOutputPorts(3);
  this->SetPieceArrayName("PieceId");
}

vtkHapticBoxBakeFilter::~vtkHapticBoxBakeFilter() { this->SetPieceArrayName(nullptr); }

void vtkHapticBoxBakeFilter::SetRecipe(const hb::BakeRecipe& recipe) {
  this->Recipe = recipe;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetM(int m) {
  m = std::clamp(m, 2, 1024);
  if (m == this->Recipe.options.params.m) return;
  this->Recipe.options.params.m = m;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetN(int n) {
  n = std::clamp(n, 2, 256);
  if (n == this->Recipe.options.params.n) return;
  this->Recipe.options.params.n = n;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetPadding(double padding) {
  const float p = float(std::clamp(padding, 0.0, 1.0));
  if (p == this->Recipe.options.obb.padding) return;
  this->Recipe.options.obb.padding = p;
  this->Modified();
}

void vtkHapticBoxBakeFilter::SetRefine(bool refine) {
  if (refine == this->Recipe.options.refine) return;
  this->Recipe.options.refine = refine;
  this->Modified();
}

vtkHapticBoxSet* vtkHapticBoxBakeFilter::GetBoxSet() {
  return vtkHapticBoxSet::SafeDownCast(this->GetOutputDataObject(0));
}

int vtkHapticBoxBakeFilter::FillOutputPortInformation(int port, vtkInformation* info) {
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkHapticBoxSet" : "vtkPolyData");
  return 1;
}

vtkTypeBool vtkHapticBoxBakeFilter::ProcessRequest(vtkInformation* request, vtkInformationVector** inputVector,
                                                   vtkInformationVector* outputVector) {
  // vtkDataObjectTypes cannot make a vtkHapticBoxSet: create the outputs here.
  if (request->Has(vtkDemandDrivenPipeline::REQUEST_DATA_OBJECT())) {
    for (int port = 0; port < this->GetNumberOfOutputPorts(); ++port) {
      vtkInformation* info = outputVector->GetInformationObject(port);
      vtkDataObject* current = info->Get(vtkDataObject::DATA_OBJECT());
      if (port == 0 && !vtkHapticBoxSet::SafeDownCast(current)) {
        vtkNew<vtkHapticBoxSet> set;
        info->Set(vtkDataObject::DATA_OBJECT(), set);
      } else if (port > 0 && !vtkPolyData::SafeDownCast(current)) {
        vtkNew<vtkPolyData> pd;
        info->Set(vtkDataObject::DATA_OBJECT(), pd);
      }
    }
    return 1;
  }
  return this->Superclass::ProcessRequest(request, inputVector, outputVector);
}

int vtkHapticBoxBakeFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                        vtkInformationVector* outputVector) {
  try {
    vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
    vtkHapticBoxSet* boxes = vtkHapticBoxSet::GetData(outputVector, 0);
    vtkPolyData* outlines = vtkPolyData::GetData(outputVector, 1);
    vtkPolyData* positions = vtkPolyData::GetData(outputVector, 2);
    this->UpdateProgress(0.0);
    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(input);

    hb::BakeRecipe recipe = this->Recipe;
    // Piece ids: only meaningful when no triangle was dropped or split by the conversion.
    vtkDataArray* ids = (this->PieceArrayName && input->GetCellData())
        ? input->GetCellData()->GetArray(this->PieceArrayName) : nullptr;
    if (ids) {
      if (ids->GetNumberOfTuples() != vtkIdType(mesh.triangle_count()) || input->GetNumberOfStrips() > 0 ||
          input->GetNumberOfPolys() != vtkIdType(mesh.triangle_count()))
        throw hb::InvalidInput(std::string("the cell array ") + this->PieceArrayName +
                               " needs a surface of triangles only (one id per triangle)");
      recipe.pieces.kind = hb::PiecesRecipe::Kind::given;
      recipe.pieces.given.resize(mesh.triangle_count());
      for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c) {
        const double v = ids->GetComponent(c, 0);
        if (!(v >= 0.0 && v < 4294967296.0))
          throw hb::InvalidInput(std::string("the cell array ") + this->PieceArrayName + " holds " +
                                 std::to_string(v) + " (piece ids are integers >= 0)");
        recipe.pieces.given[std::size_t(c)] = std::uint32_t(v);
      }
    }
    const bool decompose = recipe.pieces.kind == hb::PiecesRecipe::Kind::automatic;
    if (decompose) recipe.pieces.automatic.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, 0.02, 0.3);
    recipe.options.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, decompose ? 0.3 : 0.02, 0.98);
    hb::SourceInfo source;
    source.triangles = mesh.triangle_count();
    source.diagonal = mesh.bounds().diagonal();
    hb::BakeResult baked = hb::bake(mesh, recipe, source);
    const hb::BakeStats stats = baked.stats;
    auto scene = std::make_shared<const hb::BoxScene>(std::move(baked.scene));
    this->BakeSeconds = stats.seconds;
    boxes->SetScene(scene);

    outlines->ShallowCopy(vtkHapticBoxUtilities::BoxOutlines(*scene));
    // Position points with their box and face.
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> verts;
    vtkNew<vtkIntArray> ptBox, ptFace;
    ptBox->SetName("BoxId");
    ptFace->SetName("Face");
    for (std::size_t b = 0; b < scene->boxes().size(); ++b) {
      const hb::HapticBox& box = scene->boxes()[b];
      const int m = box.params().m;
      for (int face = 0; face < 6; ++face)
        for (int i = 0; i < m; ++i)
          for (int j = 0; j < m; ++j) {
            const hb::Vec3 p = box.layout().position_point(face, i, j);
            const vtkIdType id = pts->InsertNextPoint(p.x(), p.y(), p.z());
            verts->InsertNextCell(1, &id);
            ptBox->InsertNextValue(int(b));
            ptFace->InsertNextValue(face);
          }
    }
    vtkNew<vtkDoubleArray> seconds, bytes;
    seconds->SetName("BakeSeconds");
    seconds->InsertNextValue(stats.seconds);
    bytes->SetName("TableBytes");
    bytes->InsertNextValue(double(scene->table_bytes()));
    outlines->GetFieldData()->AddArray(seconds);
    outlines->GetFieldData()->AddArray(bytes);
    positions->SetPoints(pts);
    positions->SetVerts(verts);
    positions->GetPointData()->AddArray(ptBox);
    positions->GetPointData()->AddArray(ptFace);
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
}

void vtkHapticBoxBakeFilter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "M: " << this->GetM() << "\n"
     << indent << "N: " << this->GetN() << "\n"
     << indent << "Padding: " << this->GetPadding() << "\n"
     << indent << "Refine: " << this->GetRefine() << "\n"
     << indent << "Pieces: " << hb::pieces_spec(this->Recipe.pieces) << "\n"
     << indent << "PieceArrayName: " << (this->PieceArrayName ? this->PieceArrayName : "(none)") << "\n";
}
