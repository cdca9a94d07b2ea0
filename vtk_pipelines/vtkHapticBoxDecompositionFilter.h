/**
 * @class   vtkHapticBoxDecompositionFilter
 * @brief   Splits a surface into quasi-convex pieces (a thin adapter over hb::decompose_auto).
 *
 * Input: a triangle surface. Output: the triangulated surface (cell i = core triangle i) with
 * cell data "PieceId" (int, 0..K-1, what vtkHapticBoxBakeFilter reads) and
 * "PocketProbability" (the piece's estimated pocket probability), field data "PieceCount"
 * and "DecompositionOptions" (vtkHapticBoxUtilities::DecompositionSignature of the options:
 * vtkHapticBoxBakeFilter takes these pieces as its automatic recipe's own when they match).
 * Progress events; abort honoured.
 */
#ifndef vtkHapticBoxDecompositionFilter_h
#define vtkHapticBoxDecompositionFilter_h

#include "decomposition/auto_decomposition.h"
#include <vtkPolyDataAlgorithm.h>
#include <string>

class vtkHapticBoxDecompositionFilter : public vtkPolyDataAlgorithm {
public:
  static vtkHapticBoxDecompositionFilter* New();
  vtkTypeMacro(vtkHapticBoxDecompositionFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Largest pocket probability of a merged piece, [0, 1] (core default 0.004).
  vtkSetClampMacro(Threshold, double, 0.0, 1.0);
  vtkGetMacro(Threshold, double);
  ///@}
  ///@{
  /// Pieces below this fraction of the area are merged into a neighbour, [0, 1) (0.002).
  vtkSetClampMacro(MinAreaFraction, double, 0.0, 0.999);
  vtkGetMacro(MinAreaFraction, double);
  ///@}
  ///@{
  /// Upper bound on the number of pieces (32).
  vtkSetClampMacro(MaxPieces, int, 1, 1 << 20);
  vtkGetMacro(MaxPieces, int);
  ///@}
  ///@{
  /// Leaf clusters of the initial tree (768) and random lines of the pocket estimate (300000).
  vtkSetClampMacro(Leaves, int, 1, 1 << 24);
  vtkGetMacro(Leaves, int);
  vtkSetClampMacro(Lines, int, 1000, 1 << 30);
  vtkGetMacro(Lines, int);
  ///@}
  ///@{
  /// Seed (1): same mesh, options and seed, same pieces.
  vtkSetMacro(Seed, vtkTypeUInt64);
  vtkGetMacro(Seed, vtkTypeUInt64);
  ///@}

  ///@{
  /// All of the above at once, as the core names them (a bake recipe's
  /// hb::PiecesRecipe::automatic); the progress callback is ignored (the filter's own).
  void SetOptions(const hb::AutoDecompositionOptions& options);
  hb::AutoDecompositionOptions GetOptions() const;
  ///@}

  /// Why the last update failed (as vtkErrorMacro reported it, without its prefix), or empty.
  const std::string& GetLastError() const { return this->LastError; }

protected:
  vtkHapticBoxDecompositionFilter();
  ~vtkHapticBoxDecompositionFilter() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double Threshold = 0.004;
  double MinAreaFraction = 0.002;
  int MaxPieces = 32;
  int Leaves = 768;
  int Lines = 300000;
  vtkTypeUInt64 Seed = 1;
  std::string LastError;

private:
  vtkHapticBoxDecompositionFilter(const vtkHapticBoxDecompositionFilter&) = delete;
  void operator=(const vtkHapticBoxDecompositionFilter&) = delete;
};

#endif
