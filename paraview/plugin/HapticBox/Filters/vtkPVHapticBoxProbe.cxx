#include "vtkPVHapticBoxProbe.h"
#include "perception/perceptible.h"
#include "exact/exact_query.h"
#include "pv_scene_source.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <exception>

vtkStandardNewMacro(vtkPVHapticBoxProbe);

vtkPVHapticBoxProbe::vtkPVHapticBoxProbe() { this->SetPerceptual("nominal"); }

vtkPVHapticBoxProbe::~vtkPVHapticBoxProbe() {
  this->SetBoxFile(nullptr);
  this->SetWorkspace(nullptr);
  this->SetPerceptual(nullptr);
}

int vtkPVHapticBoxProbe::RequestData(vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  try {
    const vtkSmartPointer<vtkPolyData> surface = hb::paraview::input_surface(inputVector);
    const hb::TriangleMesh mesh = vtkHapticBoxUtilities::ToTriangleMesh(surface);
    const std::string workspace = this->Workspace ? this->Workspace : "";
    const hb::ForceLaw law = hb::paraview::workspace_for(mesh.bounds().diagonal(), workspace).law();
    const hb::PerceptualJudge judge = hb::paraview::judge_for(workspace, this->Perceptual ? this->Perceptual : "");
    const hb::Segment segment{hb::Vec3(float(this->Point1[0]), float(this->Point1[1]), float(this->Point1[2])),
                              hb::Vec3(float(this->Point2[0]), float(this->Point2[1]), float(this->Point2[2]))};
    const auto scene = hb::paraview::scene_for(this->BoxFile ? this->BoxFile : "", surface);
    const hb::ExactQuery exact(mesh);
    const hb::Contact answers[2] = {exact.query(segment, law), scene->query(segment, law)};
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> lines, verts;
    vtkNew<vtkFloatArray> force, depth;
    vtkNew<vtkIntArray> method;
    force->SetName("Force");
    force->SetNumberOfComponents(3);
    depth->SetName("Depth");
    method->SetName("Method");
    const auto add = [&](const hb::Vec3& p, const hb::Vec3& f, float d, int m) {
      const vtkIdType id = points->InsertNextPoint(p.x(), p.y(), p.z());
      force->InsertNextTuple3(f.x(), f.y(), f.z());
      depth->InsertNextValue(d);
      method->InsertNextValue(m);
      return id;
    };
    const vtkIdType line[2] = {add(segment.start, hb::Vec3::Zero(), 0.f, -1), add(segment.end, hb::Vec3::Zero(), 0.f, -1)};
    lines->InsertNextCell(2, line);
    for (int m = 0; m < 2; ++m)
      if (answers[m].contact) {
        const vtkIdType id = add(answers[m].point, answers[m].force, answers[m].depth, m);
        verts->InsertNextCell(1, &id);
      }
    output->SetPoints(points);
    output->SetLines(lines);
    output->SetVerts(verts);
    output->GetPointData()->AddArray(force);
    output->GetPointData()->AddArray(depth);
    output->GetPointData()->AddArray(method);
    output->GetPointData()->SetActiveVectors("Force");
    vtkNew<vtkStringArray> verdict;
    verdict->SetName("Perceptible");
    verdict->InsertNextValue(hb::perceived_by_name(hb::perceive(answers[0], answers[1], judge.thresholds, judge.max_force_n).by));
    output->GetFieldData()->AddArray(verdict);
    for (int m = 0; m < 2; ++m) {
      vtkNew<vtkDoubleArray> magnitude;
      magnitude->SetName(m == 0 ? "ExactForceN" : "BoxForceN");
      magnitude->InsertNextValue(answers[m].force.norm());
      output->GetFieldData()->AddArray(magnitude);
    }
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}
