/**
 * @class   vtkHapticBoxMeshReader
 * @brief   Reads a surface mesh in any format HapticBox handles, as triangle polydata.
 *
 * Everything goes through hb::vtk::load_model (model_loader.h), which also opens volumes
 * (NIfTI, MetaImage, NRRD, DICOM series), CAD solids (STEP, IGES) and Assimp scenes (glTF,
 * 3MF, FBX, Collada), all in millimetres.
 * Formats: everything the core reads (.off, .obj, .ply, .stl, .om, through hb::read_mesh:
 * the same triangles and normals as the hapticbox command, OFF included, which VTK 9.1
 * lacks) plus VTK's own .vtp (XML) and .vtk (legacy polydata). With UseVTKReaders on,
 * .stl/.obj/.ply go through vtkSTLReader/vtkOBJReader/vtkPLYReader instead.
 *
 * The output is always triangles (polygons fan-triangulated) with point "Normals" (the
 * core's area-weighted vertex normals unless the file carries normals); cell i is the
 * core's triangle i. Other point/cell arrays of VTK files are not carried over.
 * Errors (missing file, garbage, NaN, unknown extension) are reported with vtkErrorMacro
 * naming the file; the reader's warnings (open, non-manifold, dropped faces) with
 * vtkWarningMacro.
 */
#ifndef vtkHapticBoxMeshReader_h
#define vtkHapticBoxMeshReader_h

#include "model_loader.h"
#include <vtkPolyDataAlgorithm.h>

class vtkHapticBoxMeshReader : public vtkPolyDataAlgorithm {
public:
  static vtkHapticBoxMeshReader* New();
  vtkTypeMacro(vtkHapticBoxMeshReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to read.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Read .stl/.obj/.ply with VTK's readers rather than the core's (default off).
  vtkSetMacro(UseVTKReaders, bool);
  vtkGetMacro(UseVTKReaders, bool);
  vtkBooleanMacro(UseVTKReaders, bool);
  ///@}

  ///@{
  /// How volumes, CAD solids and units are handled (iso-value or label, smoothing,
  /// decimation, chordal deviation, unit); see hb::vtk::ModelOptions.
  void SetModelOptions(const hb::vtk::ModelOptions& options) {
    this->Options = options;
    this->Modified();
  }
  const hb::vtk::ModelOptions& GetModelOptions() const { return this->Options; }
  ///@}

  /// The model of the last successful read: its format, unit, facts (volume dimensions,
  /// spacing, value range, iso-value used; CAD solids and faces) and CAD face ids.
  const hb::vtk::LoadedModel& GetLoadedModel() const { return this->Model; }

  /// True when the extension of `fileName` is one this reader handles.
  static bool CanReadFile(const char* fileName);
  /// Why the last read failed (the file and the cause, as vtkErrorMacro reported it without
  /// its prefix), empty after a successful read; for front ends that show it to a user.
  const std::string& GetLastError() const { return this->LastError; }

protected:
  vtkHapticBoxMeshReader();
  ~vtkHapticBoxMeshReader() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  bool UseVTKReaders = false;
  hb::vtk::ModelOptions Options;
  hb::vtk::LoadedModel Model;
  std::string LastError;

private:
  vtkHapticBoxMeshReader(const vtkHapticBoxMeshReader&) = delete;
  void operator=(const vtkHapticBoxMeshReader&) = delete;
};

#endif
