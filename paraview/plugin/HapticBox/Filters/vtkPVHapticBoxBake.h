/**
 * @class   vtkPVHapticBoxBake
 * @brief   ParaView's "HapticBox Bake": the default bake of the input surface
 *          (vtkHapticBoxBakeFilter with hb::default_recipe(): automatic pieces, or those of an
 *          upstream HapticBox Decomposition, and the default error budget), saved to OutputFile
 *          when one is given. Output 0: the box outlines (cell data BoxId); output 1: the
 *          surface with cell data PieceId.
 */
#ifndef vtkPVHapticBoxBake_h
#define vtkPVHapticBoxBake_h
#include "HapticBoxFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

class HAPTICBOXFILTERS_EXPORT vtkPVHapticBoxBake : public vtkPolyDataAlgorithm {
public:
  static vtkPVHapticBoxBake* New();
  vtkTypeMacro(vtkPVHapticBoxBake, vtkPolyDataAlgorithm);
  /// Where to save the scene (.hbox); empty: not saved.
  vtkSetStringMacro(OutputFile);
  vtkGetStringMacro(OutputFile);
  /// The error budget (`bake --budget`, e.g. "felt=0.1"; empty: the default).
  vtkSetStringMacro(Budget);
  vtkGetStringMacro(Budget);

protected:
  vtkPVHapticBoxBake();
  ~vtkPVHapticBoxBake() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  char* OutputFile = nullptr;
  char* Budget = nullptr;

private:
  vtkPVHapticBoxBake(const vtkPVHapticBoxBake&) = delete;
  void operator=(const vtkPVHapticBoxBake&) = delete;
};
#endif
