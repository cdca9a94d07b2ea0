// 1. convert the surface to the core mesh and build the exact reference on it;
// 2. choose the points (vertices or an even sampling) and call hb::compute_error_field;
// 3. convert the per-point statistics to point arrays.
#include "vtkHapticBoxErrorFieldFilter.h"
#include "errors.h"
#include "evaluation/error_field.h"
#include "exact/exact_query.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

vtkStandardNewMacro(vtkHapticBoxErrorFieldFilter);

vtkHapticBoxErrorFieldFilter::vtkHapticBoxErrorFieldFilter() { this->SetNumberOfInputPorts(2); }
vtkHapticBoxErrorFieldFilter::~vtkHapticBoxErrorFieldFilter() = default;

void vtkHapticBoxErrorFieldFilter::SetBoxSetData(vtkHapticBoxSet* boxes) { this->SetInputData(1, boxes); }

int vtkHapticBoxErrorFieldFilter::FillInputPortInformation(int port, vtkInformation* info) {
  if (port == 0) {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
    return 1;
  }
  if (port == 1) {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkHapticBoxSet");
    return 1;
  }
  return 0;
}

int vtkHapticBoxErrorFieldFilter::RequestData(vtkInformation*, vtkInformationVector** inputVector,
                                              vtkInformationVector* outputVector) {
  try {
    vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
    vtkHapticBoxSet* boxes = vtkHapticBoxSet::GetData(inputVector[1], 0);
    vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
    if (!boxes || !boxes->GetScene() || boxes->GetScene()->boxes().empty())
      throw hb::InvalidInput("no boxes on input port 1");
    this->UpdateProgress(0.0);

    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(input);
    const hb::ExactQuery exact(mesh);
    const float diagonal =
        boxes->GetScene()->source().diagonal > 0.f ? boxes->GetScene()->source().diagonal : mesh.bounds().diagonal();

    std::vector<hb::SurfacePoint> points = this->SampleMode == EVEN
        ? hb::sample_surface_evenly(mesh, std::size_t(this->NumberOfSamples), this->Seed)
        : hb::surface_points_at_vertices(mesh);

    hb::ErrorFieldOptions options;
    options.probes_per_point = this->ProbesPerPoint;
    options.cone_degrees = float(this->ConeAngle);
    options.length_fraction = float(this->LengthFraction);
    options.max_depth_fraction = float(this->MaxDepthFraction);
    options.seed = this->Seed;
    options.law.stiffness_n_per_m = float(this->Stiffness);
    options.law.metres_per_unit = float(this->MetresPerUnit);
    options.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, 0.05, 0.95);
    options.communicator = this->Communicator;
    const hb::ErrorField field = hb::compute_error_field(*boxes->GetScene(), exact, points, diagonal, options);

    if (this->SampleMode == EVEN) {
      vtkNew<vtkPoints> pts;
      pts->SetDataTypeToFloat();
      pts->SetNumberOfPoints(vtkIdType(points.size()));
      std::vector<hb::Vec3> normals(points.size());
      vtkNew<vtkCellArray> verts;
      verts->AllocateExact(vtkIdType(points.size()), vtkIdType(points.size()));
      for (std::size_t i = 0; i < points.size(); ++i) {
        pts->SetPoint(vtkIdType(i), points[i].position.x(), points[i].position.y(), points[i].position.z());
        normals[i] = points[i].normal;
        const vtkIdType id = vtkIdType(i);
        verts->InsertNextCell(1, &id);
      }
      output->SetPoints(pts);
      output->SetVerts(verts);
      output->GetPointData()->SetNormals(vtkHapticBoxUtilities::ToVectorArray("Normals", normals));
    } else {
      output->ShallowCopy(vtkHapticBoxUtilities::ToPolyData(mesh));
    }
    vtkPointData* pd = output->GetPointData();
    if (field.size() != points.size()) {  // a rank other than 0 of a shared field
      this->UpdateProgress(1.0);
      return 1;
    }
    pd->AddArray(vtkHapticBoxUtilities::ToVectorArray("ExactForce", field.exact_force));
    pd->AddArray(vtkHapticBoxUtilities::ToVectorArray("ApproxForce", field.approx_force));
    pd->AddArray(vtkHapticBoxUtilities::ToScalarArray("RelativeForceError", field.force_error));
    pd->AddArray(vtkHapticBoxUtilities::ToScalarArray("DirectionError", field.direction_error));
    pd->AddArray(vtkHapticBoxUtilities::ToScalarArray("ContactDisagreement", field.contact_disagreement));
    pd->AddArray(vtkHapticBoxUtilities::ToScalarArray("ExactContactFraction", field.exact_contact_fraction));
    pd->SetActiveScalars("RelativeForceError");
    vtkNew<vtkDoubleArray> seconds;
    seconds->SetName("ErrorFieldSeconds");
    seconds->InsertNextValue(field.seconds);
    output->GetFieldData()->AddArray(seconds);
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
}

void vtkHapticBoxErrorFieldFilter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SampleMode: " << (this->SampleMode == EVEN ? "Even" : "Vertices") << "\n"
     << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n"
     << indent << "ProbesPerPoint: " << this->ProbesPerPoint << "\n"
     << indent << "ConeAngle: " << this->ConeAngle << "\n"
     << indent << "LengthFraction: " << this->LengthFraction << "\n"
     << indent << "MaxDepthFraction: " << this->MaxDepthFraction << "\n"
     << indent << "Seed: " << this->Seed << "\n"
     << indent << "Stiffness: " << this->Stiffness << "\n"
     << indent << "MetresPerUnit: " << this->MetresPerUnit << "\n";
}
