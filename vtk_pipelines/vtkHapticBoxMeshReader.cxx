// hb::vtk::load_model picks the reader (the core's for its formats, VTK's for .vtp/.vtk or
// when asked, volumes, CAD, Assimp scenes); every output goes through the core mesh once, so
// it has the same form: triangles, point normals, no degenerate cells, millimetres.
#include "vtkHapticBoxMeshReader.h"
#include "errors.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

vtkStandardNewMacro(vtkHapticBoxMeshReader);

vtkHapticBoxMeshReader::vtkHapticBoxMeshReader() { this->SetNumberOfInputPorts(0); }

vtkHapticBoxMeshReader::~vtkHapticBoxMeshReader() { this->SetFileName(nullptr); }

bool vtkHapticBoxMeshReader::CanReadFile(const char* fileName) {
  if (!fileName) return false;
  const std::string ext = vtkHapticBoxUtilities::Extension(fileName);
  return ext == ".off" || ext == ".obj" || ext == ".ply" || ext == ".stl" || ext == ".om" || ext == ".vtp" ||
         ext == ".vtk" || hb::vtk::is_volume_or_cad(fileName);
}

int vtkHapticBoxMeshReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector) {
  this->LastError.clear();
  try {
    vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
    if (!this->FileName || !*this->FileName) throw hb::InvalidInput("no file name set");
    this->UpdateProgress(0.0);
    hb::vtk::ModelOptions options = this->Options;
    options.use_vtk_readers = this->UseVTKReaders;
    this->Model = hb::vtk::load_model(this->FileName, options);
    for (const std::string& w : this->Model.report.warnings) vtkWarningMacro(<< w);
    output->ShallowCopy(vtkHapticBoxUtilities::ToPolyData(this->Model.mesh));
    this->UpdateProgress(1.0);
    return 1;
  } catch (const std::exception& e) {
    this->LastError = e.what();
    vtkErrorMacro(<< e.what());
    return 0;
  }
}

void vtkHapticBoxMeshReader::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "UseVTKReaders: " << this->UseVTKReaders << "\n";
}
