/**
 * @class   vtkPVHapticBoxDecomposition
 * @brief   ParaView's "HapticBox Decomposition": vtkHapticBoxDecompositionFilter (automatic
 *          pieces, cell data "PieceId") with its properties; the bake takes the pieces as its own.
 */
#ifndef vtkPVHapticBoxDecomposition_h
#define vtkPVHapticBoxDecomposition_h
#include "HapticBoxFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

class HAPTICBOXFILTERS_EXPORT vtkPVHapticBoxDecomposition : public vtkPolyDataAlgorithm {
public:
  static vtkPVHapticBoxDecomposition* New();
  vtkTypeMacro(vtkPVHapticBoxDecomposition, vtkPolyDataAlgorithm);
  /// Pocket threshold (the default bake's: 0.001), the most pieces, the seed.
  vtkSetClampMacro(Threshold, double, 0.0, 1.0);
  vtkGetMacro(Threshold, double);
  vtkSetClampMacro(MaxPieces, int, 1, 1 << 20);
  vtkGetMacro(MaxPieces, int);
  vtkSetClampMacro(Seed, int, 0, VTK_INT_MAX);
  vtkGetMacro(Seed, int);

protected:
  vtkPVHapticBoxDecomposition();
  ~vtkPVHapticBoxDecomposition() override = default;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  double Threshold = 0.001;
  int MaxPieces = 64;
  int Seed = 1;

private:
  vtkPVHapticBoxDecomposition(const vtkPVHapticBoxDecomposition&) = delete;
  void operator=(const vtkPVHapticBoxDecomposition&) = delete;
};
#endif
