// 1. convert the surface, read the piece ids (numbered compactly) if any;
// 2. hb::bake_scene with a progress callback that also honours AbortExecute;
// 3. outputs: the scene, the PBB outlines and the position points for display.
#include "vtkHapticBoxBakeFilter.h"
#include "errors.h"
#include "haptic_box/bake.h"
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
#include <map>

vtkStandardNewMacro(vtkHapticBoxBakeFilter);

vtkHapticBoxBakeFilter::vtkHapticBoxBakeFilter() {
  this->SetNumberOfOutputPorts(3);
  this->SetPieceArrayName("PieceId");
}

vtkHapticBoxBakeFilter::~vtkHapticBoxBakeFilter() { this->SetPieceArrayName(nullptr); }

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

    // Piece ids: only meaningful when no triangle was dropped or split by the conversion.
    std::vector<std::uint32_t> pieces;
    vtkDataArray* ids = (this->PieceArrayName && input->GetCellData())
        ? input->GetCellData()->GetArray(this->PieceArrayName) : nullptr;
    if (ids) {
      if (ids->GetNumberOfTuples() != vtkIdType(mesh.triangle_count()) || input->GetNumberOfStrips() > 0 ||
          input->GetNumberOfPolys() != vtkIdType(mesh.triangle_count()))
        throw hb::InvalidInput(std::string("the cell array ") + this->PieceArrayName +
                               " needs a surface of triangles only (one id per triangle)");
      std::map<long long, std::uint32_t> number;
      for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c) number.emplace((long long)ids->GetComponent(c, 0), 0u);
      std::uint32_t next = 0;
      for (auto& kv : number) kv.second = next++;
      pieces.resize(mesh.triangle_count());
      for (vtkIdType c = 0; c < ids->GetNumberOfTuples(); ++c)
        pieces[std::size_t(c)] = number[(long long)ids->GetComponent(c, 0)];
    }

    hb::BakeOptions options;
    options.params.m = this->M;
    options.params.n = this->N;
    options.obb.padding = float(this->Padding);
    options.refine = this->Refine;
    options.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, 0.02, 0.98);
    hb::SourceInfo source;
    source.triangles = mesh.triangle_count();
    source.diagonal = mesh.bounds().diagonal();
    hb::BakeStats stats;
    auto scene = std::make_shared<const hb::BoxScene>(hb::bake_scene(mesh, pieces, options, source, &stats));
    this->BakeSeconds = stats.seconds;
    boxes->SetScene(scene);

    // PBB outlines: 8 corners, 12 edges per box.
    vtkNew<vtkPoints> corners;
    vtkNew<vtkCellArray> lines;
    vtkNew<vtkIntArray> lineBox;
    lineBox->SetName("BoxId");
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    // Position points with their box and face.
    vtkNew<vtkPoints> pts;
    vtkNew<vtkCellArray> verts;
    vtkNew<vtkIntArray> ptBox, ptFace;
    ptBox->SetName("BoxId");
    ptFace->SetName("Face");
    for (std::size_t b = 0; b < scene->boxes().size(); ++b) {
      const hb::HapticBox& box = scene->boxes()[b];
      const vtkIdType base = corners->GetNumberOfPoints();
      for (int k = 0; k < 8; ++k) {
        const hb::Vec3 q((k & 1) ? box.obb().half.x() : -box.obb().half.x(),
                         (k & 2) ? box.obb().half.y() : -box.obb().half.y(),
                         (k & 4) ? box.obb().half.z() : -box.obb().half.z());
        const hb::Vec3 w = box.obb().to_world(q);
        corners->InsertNextPoint(w.x(), w.y(), w.z());
      }
      for (const auto& e : edges) {
        const vtkIdType line[2] = {base + e[0], base + e[1]};
        lines->InsertNextCell(2, line);
        lineBox->InsertNextValue(int(b));
      }
      const int m = box.params().m;
      for (int face = 0; face < 6; ++face)
        for (int i = 0; i < m; ++i)
          for (int j = 0; j < m; ++j) {
            const hb::Vec3 p = box.position_point(face, i, j);
            const vtkIdType id = pts->InsertNextPoint(p.x(), p.y(), p.z());
            verts->InsertNextCell(1, &id);
            ptBox->InsertNextValue(int(b));
            ptFace->InsertNextValue(face);
          }
    }
    outlines->SetPoints(corners);
    outlines->SetLines(lines);
    outlines->GetCellData()->AddArray(lineBox);
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
  os << indent << "M: " << this->M << "\n"
     << indent << "N: " << this->N << "\n"
     << indent << "Padding: " << this->Padding << "\n"
     << indent << "PieceArrayName: " << (this->PieceArrayName ? this->PieceArrayName : "(none)") << "\n";
}
