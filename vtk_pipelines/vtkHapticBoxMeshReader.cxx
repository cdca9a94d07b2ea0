// 1. pick the reader by the file's extension (the core's for its formats, VTK's for .vtp/.vtk
//    or when asked);
// 2. VTK data goes through the core mesh once, so every output has the same form: triangles,
//    point normals, no degenerate cells.
#include "vtkHapticBoxMeshReader.h"
#include "errors.h"
#include "mesh/mesh_io.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkOBJReader.h>
#include <vtkObjectFactory.h>
#include <vtkPLYReader.h>
#include <vtkPolyData.h>
#include <vtkPolyDataReader.h>
#include <vtkSTLReader.h>
#include <vtkXMLPolyDataReader.h>
#include <fstream>

vtkStandardNewMacro(vtkHapticBoxMeshReader);

vtkHapticBoxMeshReader::vtkHapticBoxMeshReader() { this->SetNumberOfInputPorts(0); }

vtkHapticBoxMeshReader::~vtkHapticBoxMeshReader() { this->SetFileName(nullptr); }

bool vtkHapticBoxMeshReader::CanReadFile(const char* fileName) {
  if (!fileName) return false;
  const std::string ext = vtkHapticBoxUtilities::Extension(fileName);
  return ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".om" || ext == ".vtp" ||
         ext == ".vtk";
}

namespace {

// Runs a VTK reader, turning its error events into an exception naming the file.
template <class Reader>
vtkSmartPointer<vtkPolyData> ReadWithVTK(const std::string& path) {
  vtkNew<Reader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  if (reader->GetErrorCode() != 0)
    throw hb::InvalidInput(path + ": VTK reader failed (error code " + std::to_string(reader->GetErrorCode()) + ")");
  vtkSmartPointer<vtkPolyData> out = reader->GetOutput();
  if (!out || out->GetNumberOfPoints() == 0) throw hb::InvalidInput(path + ": no points read");
  return out;
}

} // namespace

int vtkHapticBoxMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector) {
  try {
    vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
    if (!this->FileName || !*this->FileName) throw hb::InvalidInput("no file name set");
    const std::string path = this->FileName;
    const std::string ext = vtkHapticBoxUtilities::Extension(path);
    if (!std::ifstream(path).good()) throw hb::IoError(path + ": cannot open the file");
    this->UpdateProgress(0.0);
    hb::TriangleMesh mesh;
    const bool vtkFormat = ext == ".vtp" || ext == ".vtk";
    const bool viaVTK = vtkFormat || (this->UseVTKReaders && (ext == ".stl" || ext == ".obj" || ext == ".ply"));
    if (viaVTK) {
      vtkSmartPointer<vtkPolyData> raw;
      if (ext == ".vtp") raw = ReadWithVTK<vtkXMLPolyDataReader>(path);
      else if (ext == ".vtk") raw = ReadWithVTK<vtkPolyDataReader>(path);
      else if (ext == ".stl") raw = ReadWithVTK<vtkSTLReader>(path);
      else if (ext == ".obj") raw = ReadWithVTK<vtkOBJReader>(path);
      else raw = ReadWithVTK<vtkPLYReader>(path);
      try {
        mesh = vtkHapticBoxUtilities::ToTriangleMesh(raw);
      } catch (const hb::Error& e) {
        throw hb::InvalidInput(path + ": " + e.what());
      }
    } else {
      hb::MeshReadReport report;
      mesh = hb::read_mesh(path, &report);
      for (const std::string& w : report.warnings) vtkWarningMacro(<< w);
    }
    output->ShallowCopy(vtkHapticBoxUtilities::ToPolyData(mesh));
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
}

void vtkHapticBoxMeshReader::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "UseVTKReaders: " << this->UseVTKReaders << "\n";
}
