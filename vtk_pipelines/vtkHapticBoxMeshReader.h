/**
 * @class   vtkHapticBoxMeshReader
 * @brief   Reads a surface mesh in any format HapticBox handles, as triangle polydata.
 *
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

  /// True when the extension of `fileName` is one this reader handles.
  static bool CanReadFile(const char* fileName);

protected:
  vtkHapticBoxMeshReader();
  ~vtkHapticBoxMeshReader() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  bool UseVTKReaders = false;

private:
  vtkHapticBoxMeshReader(const vtkHapticBoxMeshReader&) = delete;
  void operator=(const vtkHapticBoxMeshReader&) = delete;
};

#endif
