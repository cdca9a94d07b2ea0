/**
 * @class   vtkPVHapticBoxReader
 * @brief   Reads a .hbox file as its boxes: the PBB outlines (12 lines a box) with cell data
 *          "PieceId" (box index), "M" and "N" (hb::vtk::box_outline_polydata, the outlines
 *          `hapticbox field` writes beside a field), and field data on the source model.
 */
#ifndef vtkPVHapticBoxReader_h
#define vtkPVHapticBoxReader_h
#include "HapticBoxFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

class HAPTICBOXFILTERS_EXPORT vtkPVHapticBoxReader : public vtkPolyDataAlgorithm {
public:
  static vtkPVHapticBoxReader* New();
  vtkTypeMacro(vtkPVHapticBoxReader, vtkPolyDataAlgorithm);
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  /// 1 when the file starts with a box file's magic (ParaView asks before it reads).
  int CanReadFile(const char* name);

protected:
  vtkPVHapticBoxReader();
  ~vtkPVHapticBoxReader() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  char* FileName = nullptr;

private:
  vtkPVHapticBoxReader(const vtkPVHapticBoxReader&) = delete;
  void operator=(const vtkPVHapticBoxReader&) = delete;
};
#endif
