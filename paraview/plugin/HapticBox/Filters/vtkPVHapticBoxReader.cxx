#include "vtkPVHapticBoxReader.h"
#include "polydata_files.h"
#include "pv_scene_source.h"
#include <vtkFieldData.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <exception>
#include <fstream>

vtkStandardNewMacro(vtkPVHapticBoxReader);

vtkPVHapticBoxReader::vtkPVHapticBoxReader() { this->SetNumberOfInputPorts(0); }

vtkPVHapticBoxReader::~vtkPVHapticBoxReader() { this->SetFileName(nullptr); }

int vtkPVHapticBoxReader::CanReadFile(const char* name) {
  std::ifstream in(name ? name : "", std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return in.gcount() == 8 && std::string(magic, 8) == "HBOXFILE" ? 1 : 0;
}

int vtkPVHapticBoxReader::RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  try {
    if (!this->FileName || !*this->FileName) throw std::runtime_error("no FileName");
    const auto scene = hb::paraview::scene_for(this->FileName, nullptr);
    output->ShallowCopy(hb::vtk::box_outline_polydata(*scene));
    hb::vtk::add_provenance(output->GetFieldData(), {{{"HapticBoxVersion", HB_VERSION}, {"BoxFile", this->FileName}}, {}});
  } catch (const std::exception& e) {
    vtkErrorMacro(<< e.what());
    return 0;
  }
  return 1;
}
