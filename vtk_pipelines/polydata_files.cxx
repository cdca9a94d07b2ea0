// VTK XML PolyData outputs: pieces, box outlines, trajectories, provenance. Each builder makes
// a polydata from core values only; write_polydata_xml writes it atomically.
#include "polydata_files.h"
#include "errors.h"
#include "scene/box_scene.h"
#include "vtkHapticBoxUtilities.h"
#include "isolated_reader.h"
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkType.h>
#include <vtkUnsignedIntArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>
#include <zlib.h>
#include <map>
#include <set>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <filesystem>

namespace hb::vtk {

void write_polydata_xml(vtkPolyData* data, const std::string& path) {
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(data);
  const std::string tmp = path + ".tmp";
  writer->SetFileName(tmp.c_str());
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();
  if (writer->Write() != 1) {
    std::remove(tmp.c_str());
    throw IoError(path + ": cannot write");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw IoError(path + ": cannot rename the written file into place");
  }
}

vtkSmartPointer<vtkPolyData> piece_polydata(const TriangleMesh& mesh, const std::vector<std::uint32_t>& piece_of_triangle) {
  if (piece_of_triangle.size() != mesh.triangle_count())
    throw InvalidInput("piece ids: " + std::to_string(piece_of_triangle.size()) + " ids for " +
                       std::to_string(mesh.triangle_count()) + " triangles");
  vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::ToPolyData(mesh);
  vtkNew<vtkIntArray> ids;
  ids->SetName("PieceId");
  ids->SetNumberOfValues(vtkIdType(piece_of_triangle.size()));
  for (std::size_t t = 0; t < piece_of_triangle.size(); ++t) ids->SetValue(vtkIdType(t), int(piece_of_triangle[t]));
  pd->GetCellData()->AddArray(ids);
  pd->GetCellData()->SetActiveScalars("PieceId");
  return pd;
}


namespace {

std::string xml_attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return {};
  const std::size_t end = tag.find('"', at + key.size());
  return end == std::string::npos ? std::string() : tag.substr(at + key.size(), end - at - key.size());
}

// The PieceId array's declared type, before VTK reads it: a Bit array holds 0 and 1 only, so
// the ids would read back as two pieces whatever was written.
void check_piece_id_type(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(1 << 20, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  head = head.substr(0, head.find("<AppendedData"));
  for (std::size_t at = head.find("<DataArray"); at != std::string::npos; at = head.find("<DataArray", at + 1)) {
    const std::string tag = head.substr(at, head.find('>', at) - at);
    if (xml_attribute(tag, "Name") == "PieceId" && xml_attribute(tag, "type") == "Bit")
      throw InvalidInput(path + ": the cell array PieceId is declared type=\"Bit\" (values 0 and 1 only), not a whole-number type");
  }
}

} // namespace

std::vector<std::uint32_t> read_piece_vtp(const std::string& path, std::size_t triangle_count) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw IoError(path + ": cannot open the piece file");
  // VTK's XML reader crashes on cell counts that disagree with the arrays: it runs in a child
  // process (isolated_reader.h).
  const std::string bytes = run_isolated(path, "VTK XML polydata", ReaderLimits::from_environment(), [&] {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(path.c_str());
    if (!reader->CanReadFile(path.c_str())) throw InvalidInput(path + ": not a VTK XML PolyData file");
    check_vtp_appended_data(path);
    check_piece_id_type(path);
    reader->Update();
    if (reader->GetErrorCode() != 0)
      throw InvalidInput(path + ": the VTK XML reader failed (" + std::string(vtkErrorCode::GetStringFromErrorCode(reader->GetErrorCode())) + ")");
    vtkPolyData* pd = reader->GetOutput();
    vtkDataArray* ids = pd ? pd->GetCellData()->GetArray("PieceId") : nullptr;
    if (!ids || ids->GetNumberOfComponents() != 1) throw InvalidInput(path + ": no cell array PieceId");
    // A Bit array holds 0 and 1 only: the ids read back as two pieces, whatever was written.
    if (ids->GetDataType() == VTK_BIT)
      throw InvalidInput(path + ": the cell array PieceId is declared type=\"Bit\" (values 0 and 1 only), not a whole-number type");
    // Cells are verts, lines, polys, strips in that order; the triangles are the polygons.
    const vtkIdType first = pd->GetNumberOfVerts() + pd->GetNumberOfLines();
    const vtkIdType polys = pd->GetNumberOfPolys();
    if (ids->GetNumberOfTuples() != pd->GetNumberOfCells())
      throw InvalidInput(path + ": the PieceId array has " + std::to_string(ids->GetNumberOfTuples()) + " values for " +
                         std::to_string(pd->GetNumberOfCells()) + " cells");
    std::vector<std::uint32_t> out(static_cast<std::size_t>(polys));
    for (vtkIdType i = 0; i < polys; ++i) {
      const double v = ids->GetComponent(first + i, 0);
      if (!(v >= 0.0) || v > 4294967295.0 || v != double(std::uint64_t(v)))
        throw InvalidInput(path + ": PieceId of polygon " + std::to_string(i) + " is not a non-negative integer");
      out[std::size_t(i)] = std::uint32_t(v);
    }
    ByteWriter w;
    w.put_vector(out);
    return w.take();
  });
  std::vector<std::uint32_t> out;
  ByteReader(bytes).get_vector(out);
  if (triangle_count != 0 && out.size() != triangle_count)
    throw InvalidInput(path + ": " + std::to_string(out.size()) + " polygons with a PieceId, the mesh has " +
                       std::to_string(triangle_count) + " triangles");
  return out;
}

vtkSmartPointer<vtkPolyData> box_outline_polydata(const BoxScene& scene) {
  vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::BoxOutlines(scene);
  vtkNew<vtkIntArray> piece, m, n;
  piece->SetName("PieceId");
  m->SetName("M");
  n->SetName("N");
  for (std::size_t b = 0; b < scene.parts().boxes.size(); ++b)
    for (int e = 0; e < 12; ++e) {
      piece->InsertNextValue(int(b));
      m->InsertNextValue(scene.parts().boxes[b].params().m);
      n->InsertNextValue(scene.parts().boxes[b].params().n);
    }
  pd->GetCellData()->AddArray(piece);
  pd->GetCellData()->AddArray(m);
  pd->GetCellData()->AddArray(n);
  pd->GetCellData()->SetActiveScalars("PieceId");
  return pd;
}

void add_provenance(vtkFieldData* fd, const Provenance& p) {
  for (const auto& [name, value] : p.strings) {
    fd->RemoveArray(name.c_str());
    vtkNew<vtkStringArray> a;
    a->SetName(name.c_str());
    a->InsertNextValue(value);
    fd->AddArray(a);
  }
  for (const auto& [name, value] : p.numbers) {
    fd->RemoveArray(name.c_str());
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->InsertNextValue(value);
    fd->AddArray(a);
  }
}

void label_units(vtkFieldData* fd, vtkDataArray* array, const std::string& unit) {
  if (!array || !array->GetName()) return;
  array->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), unit.c_str());
  auto* units = vtkStringArray::SafeDownCast(fd->GetAbstractArray("Units"));
  if (!units) {
    vtkNew<vtkStringArray> created;
    created->SetName("Units");
    fd->AddArray(created);
    units = created;
  }
  units->InsertNextValue(std::string(array->GetName()) + ": " + unit);
}

vtkSmartPointer<vtkPolyData> trajectory_polydata(const std::vector<TrajectorySample>& samples) {
  const vtkIdType count = vtkIdType(samples.size());
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(count);
  vtkNew<vtkDoubleArray> time;
  time->SetName("Time");
  time->SetNumberOfValues(count);
  vtkNew<vtkFloatArray> force, magnitude, depth;
  force->SetName("Force");
  force->SetNumberOfComponents(3);
  force->SetNumberOfTuples(count);
  magnitude->SetName("ForceMagnitude");
  magnitude->SetNumberOfValues(count);
  depth->SetName("Depth");
  depth->SetNumberOfValues(count);
  vtkNew<vtkIntArray> contact;
  contact->SetName("Contact");
  contact->SetNumberOfValues(count);
  vtkNew<vtkUnsignedIntArray> query_ns, safety;
  query_ns->SetName("QueryTime");
  query_ns->SetNumberOfValues(count);
  safety->SetName("SafetyFlags");
  safety->SetNumberOfValues(count);
  vtkNew<vtkCellArray> lines;
  if (count > 0) {
    lines->InsertNextCell(count);
    for (vtkIdType i = 0; i < count; ++i) lines->InsertCellPoint(i);
  }
  for (vtkIdType i = 0; i < count; ++i) {
    const TrajectorySample& s = samples[std::size_t(i)];
    points->SetPoint(i, s.tip.x(), s.tip.y(), s.tip.z());
    time->SetValue(i, s.time_s);
    force->SetTuple3(i, s.force.x(), s.force.y(), s.force.z());
    magnitude->SetValue(i, s.force.norm());
    depth->SetValue(i, s.depth);
    contact->SetValue(i, s.contact ? 1 : 0);
    query_ns->SetValue(i, s.query_ns);
    safety->SetValue(i, s.safety_flags);
  }
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  pd->SetPoints(points);
  pd->SetLines(lines);
  vtkPointData* ptd = pd->GetPointData();
  for (vtkDataArray* a : {static_cast<vtkDataArray*>(time), static_cast<vtkDataArray*>(force),
                          static_cast<vtkDataArray*>(magnitude), static_cast<vtkDataArray*>(depth),
                          static_cast<vtkDataArray*>(contact), static_cast<vtkDataArray*>(query_ns),
                          static_cast<vtkDataArray*>(safety)})
    ptd->AddArray(a);
  ptd->SetActiveScalars("ForceMagnitude");
  label_units(pd->GetFieldData(), time, "s");
  label_units(pd->GetFieldData(), force, "N");
  label_units(pd->GetFieldData(), magnitude, "N");
  label_units(pd->GetFieldData(), depth, "model units");
  label_units(pd->GetFieldData(), query_ns, "ns");
  return pd;
}

} // namespace hb::vtk
