// 1. convert the surface to the core mesh; the exact reference is the one given (checked to
//    be over the same mesh) or built on it;
// 2. choose the points (vertices or an even sampling) and call hb::compute_error_field;
// 3. convert the per-point statistics to point arrays.
#include "vtkHapticBoxErrorFieldFilter.h"
#include "errors.h"
#include <algorithm>
#include "polydata_files.h"
#include "codec/codec.h"
#include "evaluation/error_field.h"
#include "exact/exact_query.h"
#include "scene/density_range.h"
#include "vtkHapticBoxSet.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkStringArray.h>
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

void vtkHapticBoxErrorFieldFilter::SetExactQuery(std::shared_ptr<const hb::ExactQuery> exact) {
  if (exact == this->Exact) return;
  this->Exact = std::move(exact);
  this->Modified();
}

void vtkHapticBoxErrorFieldFilter::SetWorkspace(const hb::Workspace& workspace) {
  this->SetStiffness(workspace.stiffness_n_per_m);
  this->SetMetresPerUnit(workspace.metres_per_unit);
  this->SetMaxForce(workspace.max_force_n);
}

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
  this->Field.reset();
  this->LastError.clear();
  try {
    vtkPolyData* input = vtkPolyData::GetData(inputVector[0], 0);
    vtkHapticBoxSet* boxes = vtkHapticBoxSet::GetData(inputVector[1], 0);
    vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
    if (!boxes || !boxes->GetScene() || boxes->GetScene()->parts().boxes.empty())
      throw hb::InvalidInput("no boxes on input port 1");
    this->UpdateProgress(0.0);

    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(input);
    std::unique_ptr<hb::ExactQuery> built;
    if (this->Exact) {
      const hb::TriangleMesh& over = this->Exact->mesh();
      if (over.vertex_count() != mesh.vertex_count() || over.triangle_count() != mesh.triangle_count() ||
          !std::equal(over.triangles.begin(), over.triangles.end(), mesh.triangles.begin()) ||
          !std::equal(over.positions.begin(), over.positions.end(), mesh.positions.begin(),
                      [](const hb::Vec3& a, const hb::Vec3& b) { return a.x() == b.x() && a.y() == b.y() && a.z() == b.z(); }))
        throw hb::InvalidInput("the exact query was built over another mesh (" + std::to_string(over.vertex_count()) +
                               " vertices, " + std::to_string(over.triangle_count()) + " triangles) than the input (" +
                               std::to_string(mesh.vertex_count()) + ", " + std::to_string(mesh.triangle_count()) + ")");
    } else {
      built = std::make_unique<hb::ExactQuery>(mesh);
    }
    this->BuiltExact = built != nullptr;
    const hb::ExactQuery& exact = built ? *built : *this->Exact;
    const float diagonal =
        boxes->GetScene()->parts().source.diagonal > 0.f ? boxes->GetScene()->parts().source.diagonal : mesh.bounds().diagonal();

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
    options.thresholds = this->Thresholds;
    options.max_force_n = this->MaxForce;
    options.progress = vtkHapticBoxUtilities::MakeProgressCallback(this, 0.05, 0.95);
    options.communicator = this->Communicator;
    this->Field = std::make_unique<hb::ErrorField>(
        hb::compute_error_field(*boxes->GetScene(), exact, points, diagonal, options));
    const hb::ErrorField& field = *this->Field;

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
    vtkFieldData* fd = output->GetFieldData();
    auto add = [&](vtkSmartPointer<vtkFloatArray> a, const char* unit) {
      pd->AddArray(a);
      hb::vtk::label_units(fd, a, unit);
    };
    add(vtkHapticBoxUtilities::ToVectorArray("ExactForce", field.exact_force), "N");
    add(vtkHapticBoxUtilities::ToVectorArray("ApproxForce", field.approx_force), "N");
    add(vtkHapticBoxUtilities::ToScalarArray("AbsoluteForceError", field.force_error_newtons), "N");
    add(vtkHapticBoxUtilities::ToScalarArray("RelativeForceError", field.force_error), "fraction of |F exact| (NaN: no data)");
    add(vtkHapticBoxUtilities::ToScalarArray("DirectionError", field.direction_error), "degrees (NaN: no data)");
    add(vtkHapticBoxUtilities::ToScalarArray("ContactDisagreement", field.contact_disagreement), "fraction of probes");
    add(vtkHapticBoxUtilities::ToScalarArray("ExactContactFraction", field.exact_contact_fraction), "fraction of probes");
    add(vtkHapticBoxUtilities::ToScalarArray("PerceptibleRatio", field.perceptible_ratio),
        "difference over its perceptual threshold (> 1: a hand would feel it)");
    add(vtkHapticBoxUtilities::ToScalarArray("PerceptibleFraction", field.perceptible_fraction), "fraction of probes");
    // The first array ParaView colours by: defined everywhere, anchored at what a hand feels.
    pd->SetActiveScalars("PerceptibleRatio");
    // Which box each triangle belongs to, when the scene is cut into pieces.
    const std::vector<std::uint32_t>& pieces = boxes->GetScene()->parts().piece_of_triangle;
    if (this->SampleMode == VERTICES && !pieces.empty() && pieces.size() == mesh.triangle_count()) {
      vtkNew<vtkIntArray> ids;
      ids->SetName("PieceId");
      ids->SetNumberOfValues(vtkIdType(pieces.size()));
      for (std::size_t t = 0; t < pieces.size(); ++t) ids->SetValue(vtkIdType(t), int(pieces[t]));
      output->GetCellData()->AddArray(ids);
    }
    vtkNew<vtkDoubleArray> seconds;
    seconds->SetName("ErrorFieldSeconds");
    seconds->InsertNextValue(field.seconds);
    fd->AddArray(seconds);
    hb::vtk::label_units(fd, seconds, "s");
    // Provenance: what was measured, with what, so the file explains itself.
    const hb::BoxScene& scene = *boxes->GetScene();
    const hb::DensityRange densities = hb::density_range(scene);
    hb::vtk::Provenance p;
    p.strings = {{"Codec", hb::codec_name(scene.parts().boxes.front().codec())},
                 {"Refined", scene.refines() ? "yes" : "no"},
                 {"SourceMesh", scene.parts().source.mesh_path},
                 {"SampleMode", this->SampleMode == EVEN ? "even" : "vertices"},
                 {"NoData", "NaN in RelativeForceError and DirectionError: no probe at the point had a contact in both "
                            "answers (no data, not zero error; see ContactDisagreement and AbsoluteForceError)"}};
    p.numbers = {{"Boxes", double(scene.parts().boxes.size())},
                 {"MMin", double(densities.m_min)},
                 {"MMax", double(densities.m_max)},
                 {"NMin", double(densities.n_min)},
                 {"NMax", double(densities.n_max)},
                 {"ProbesPerPoint", double(this->ProbesPerPoint)},
                 {"Probes", double(field.probes)},
                 {"Seed", double(this->Seed)},
                 {"Stiffness_N_per_m", this->Stiffness},
                 {"MetresPerUnit", this->MetresPerUnit},
                 {"MaxForce_N", this->MaxForce},
                 {"WorkspaceDiagonal_mm", double(diagonal) * this->MetresPerUnit * 1000.0},
                 {"PerceptibleWeber", this->Thresholds.weber},
                 {"PerceptibleFloor_N", this->Thresholds.floor_n},
                 {"PerceptibleAngle_deg", this->Thresholds.angle_deg},
                 {"PerceptibleAngleMinForce_N", this->Thresholds.angle_min_force_n},
                 {"ConeAngle_deg", this->ConeAngle},
                 {"LengthFraction", this->LengthFraction},
                 {"MaxDepthFraction", this->MaxDepthFraction}};
    hb::vtk::add_provenance(fd, p);
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    this->Field.reset();
    this->LastError = e.what();
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
