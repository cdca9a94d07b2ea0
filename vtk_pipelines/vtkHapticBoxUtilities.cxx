#include "vtkHapticBoxUtilities.h"
#include "errors.h"
#include "scene/box_scene.h"
#include <vtkCellData.h>
#include <vtkIntArray.h>
#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <thread>

hb::TriangleMesh vtkHapticBoxUtilities::ToTriangleMesh(vtkPolyData* polyData) {
  if (!polyData) throw hb::InvalidInput("vtkHapticBoxUtilities: no input polydata");
  hb::TriangleMesh mesh;
  const vtkIdType np = polyData->GetNumberOfPoints();
  mesh.positions.resize(std::size_t(np));
  for (vtkIdType i = 0; i < np; ++i) {
    double p[3];
    polyData->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw hb::InvalidInput("vtkHapticBoxUtilities: point " + std::to_string(i) + " has a NaN or infinite coordinate");
    mesh.positions[std::size_t(i)] = hb::Vec3(float(p[0]), float(p[1]), float(p[2]));
  }
  auto add = [&mesh](vtkIdType a, vtkIdType b, vtkIdType c) {
    if (a == b || b == c || a == c) return;
    mesh.triangles.push_back({std::uint32_t(a), std::uint32_t(b), std::uint32_t(c)});
  };
  vtkNew<vtkIdList> ids;
  if (vtkCellArray* polys = polyData->GetPolys()) {
    for (polys->InitTraversal(); polys->GetNextCell(ids);)
      for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k) add(ids->GetId(0), ids->GetId(k), ids->GetId(k + 1));
  }
  if (vtkCellArray* strips = polyData->GetStrips()) {
    for (strips->InitTraversal(); strips->GetNextCell(ids);)
      for (vtkIdType k = 0; k + 2 < ids->GetNumberOfIds(); ++k) {
        if (k % 2 == 0) add(ids->GetId(k), ids->GetId(k + 1), ids->GetId(k + 2));
        else add(ids->GetId(k + 1), ids->GetId(k), ids->GetId(k + 2));
      }
  }
  if (mesh.triangles.empty()) throw hb::InvalidInput("vtkHapticBoxUtilities: the polydata has no triangles");
  vtkDataArray* normals = polyData->GetPointData() ? polyData->GetPointData()->GetNormals() : nullptr;
  if (normals && normals->GetNumberOfComponents() == 3 && normals->GetNumberOfTuples() == np) {
    mesh.normals.resize(std::size_t(np));
    for (vtkIdType i = 0; i < np; ++i) {
      double n[3];
      normals->GetTuple(i, n);
      const hb::Vec3 v{float(n[0]), float(n[1]), float(n[2])};
      const float len = v.norm();
      // A normal already of unit length (the core's, through ToPolyData) is kept bit for bit:
      // dividing by a length that rounds to 1 +- 1 ulp would change its last bits, and with
      // them the bake (the window's box would not be the command line's).
      if (std::abs(len - 1.f) <= 4e-6f) mesh.normals[std::size_t(i)] = v;
      else mesh.normals[std::size_t(i)] = (len > 0.f && std::isfinite(len)) ? hb::Vec3(v / len) : hb::Vec3::UnitZ();
    }
  } else {
    mesh.compute_vertex_normals();
  }
  return mesh;
}

vtkSmartPointer<vtkPolyData> vtkHapticBoxUtilities::BoxOutlines(const hb::BoxScene& scene) {
  auto corners = vtkSmartPointer<vtkPoints>::New();
  auto lines = vtkSmartPointer<vtkCellArray>::New();
  auto lineBox = vtkSmartPointer<vtkIntArray>::New();
  lineBox->SetName("BoxId");
  static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                   {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (std::size_t b = 0; b < scene.parts().boxes.size(); ++b) {
    const hb::Obb& o = scene.parts().boxes[b].obb();
    const vtkIdType base = corners->GetNumberOfPoints();
    for (int k = 0; k < 8; ++k) {
      const hb::Vec3 w = o.to_world(hb::Vec3((k & 1) ? o.half.x() : -o.half.x(), (k & 2) ? o.half.y() : -o.half.y(),
                                             (k & 4) ? o.half.z() : -o.half.z()));
      corners->InsertNextPoint(w.x(), w.y(), w.z());
    }
    for (const auto& e : edges) {
      const vtkIdType line[2] = {base + e[0], base + e[1]};
      lines->InsertNextCell(2, line);
      lineBox->InsertNextValue(int(b));
    }
  }
  auto outlines = vtkSmartPointer<vtkPolyData>::New();
  outlines->SetPoints(corners);
  outlines->SetLines(lines);
  outlines->GetCellData()->AddArray(lineBox);
  return outlines;
}

vtkSmartPointer<vtkPolyData> vtkHapticBoxUtilities::ToPolyData(const hb::TriangleMesh& mesh) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(vtkIdType(mesh.vertex_count()));
  for (std::size_t i = 0; i < mesh.vertex_count(); ++i)
    points->SetPoint(vtkIdType(i), mesh.positions[i].x(), mesh.positions[i].y(), mesh.positions[i].z());
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(vtkIdType(mesh.triangle_count()), vtkIdType(3 * mesh.triangle_count()));
  for (const hb::Triangle& t : mesh.triangles) {
    const vtkIdType ids[3] = {vtkIdType(t[0]), vtkIdType(t[1]), vtkIdType(t[2])};
    polys->InsertNextCell(3, ids);
  }
  auto out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  out->SetPolys(polys);
  if (mesh.normals.size() == mesh.vertex_count()) out->GetPointData()->SetNormals(ToVectorArray("Normals", mesh.normals));
  return out;
}

vtkSmartPointer<vtkFloatArray> vtkHapticBoxUtilities::ToVectorArray(const char* name, const std::vector<hb::Vec3>& values) {
  auto a = vtkSmartPointer<vtkFloatArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(3);
  a->SetNumberOfTuples(vtkIdType(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i)
    a->SetTypedTuple(vtkIdType(i), values[i].data());
  return a;
}

vtkSmartPointer<vtkFloatArray> vtkHapticBoxUtilities::ToScalarArray(const char* name, const std::vector<float>& values) {
  auto a = vtkSmartPointer<vtkFloatArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(1);
  a->SetNumberOfTuples(vtkIdType(values.size()));
  std::copy(values.begin(), values.end(), a->GetPointer(0));
  return a;
}

hb::ProgressCallback vtkHapticBoxUtilities::MakeProgressCallback(vtkAlgorithm* algorithm, double begin, double end) {
  const std::thread::id owner = std::this_thread::get_id();
  return [algorithm, owner, begin, end](double fraction) {
    if (std::this_thread::get_id() == owner) algorithm->UpdateProgress(begin + (end - begin) * fraction);
    return algorithm->GetAbortExecute() == 0;
  };
}

std::string vtkHapticBoxUtilities::Extension(const std::string& path) {
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

std::string vtkHapticBoxUtilities::DecompositionSignature(const hb::AutoDecompositionOptions& o) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "auto %a %a %d %d %d %llu", o.threshold, o.min_area_fraction, o.max_pieces, o.leaves,
                o.lines, static_cast<unsigned long long>(o.seed));
  return buf;
}
