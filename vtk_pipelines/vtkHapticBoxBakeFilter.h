/**
 * @class   vtkHapticBoxBakeFilter
 * @brief   Bakes haptic boxes for a surface (a thin adapter over hb::bake_scene).
 *
 * Input: a triangle surface; when it carries an integer cell array named PieceArrayName
 * (default "PieceId", e.g. from the decomposition filter), one box is baked per piece
 * (distinct values are numbered 0..K-1 in increasing order), otherwise one box in all.
 * Outputs:
 *  0: vtkHapticBoxSet, the boxes (an hb::BoxScene), for vtkHapticBoxErrorFieldFilter;
 *  1: vtkPolyData, the PBB outlines (12 lines per box, cell data "BoxId");
 *  2: vtkPolyData, the position points (vertex cells; point data "BoxId" and "Face").
 * Field data "BakeSeconds" and "TableBytes" on output 1. Progress events; abort honoured
 * (the bake stops within a few hundred rays per thread and the filter fails with an error).
 */
#ifndef vtkHapticBoxBakeFilter_h
#define vtkHapticBoxBakeFilter_h

#include <vtkPolyDataAlgorithm.h>

class vtkHapticBoxSet;

class vtkHapticBoxBakeFilter : public vtkPolyDataAlgorithm {
public:
  static vtkHapticBoxBakeFilter* New();
  vtkTypeMacro(vtkHapticBoxBakeFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Position points per PBB face edge (m, default 32, >= 2).
  vtkSetClampMacro(M, int, 2, 4096);
  vtkGetMacro(M, int);
  ///@}

  ///@{
  /// Directional points per sub-block face edge (n, default 16, >= 2).
  vtkSetClampMacro(N, int, 2, 1024);
  vtkGetMacro(N, int);
  ///@}

  ///@{
  /// PBB padding, fraction of the fitted box's diagonal (default 0.01).
  vtkSetClampMacro(Padding, double, 0.0, 1.0);
  vtkGetMacro(Padding, double);
  ///@}

  ///@{
  /// Store the triangle each sample hit so queries refine exactly (hb::BakeOptions::refine,
  /// docs/refinement.md); default off.
  vtkSetMacro(Refine, bool);
  vtkGetMacro(Refine, bool);
  vtkBooleanMacro(Refine, bool);
  ///@}

  ///@{
  /// Name of the integer cell array holding a piece id per triangle (default "PieceId").
  vtkSetStringMacro(PieceArrayName);
  vtkGetStringMacro(PieceArrayName);
  ///@}

  /// The boxes of the last update (output 0).
  vtkHapticBoxSet* GetBoxSet();
  /// Seconds the last bake took.
  vtkGetMacro(BakeSeconds, double);

protected:
  vtkHapticBoxBakeFilter();
  ~vtkHapticBoxBakeFilter() override;
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int M = 32;
  int N = 16;
  double Padding = 0.01;
  bool Refine = false;
  char* PieceArrayName = nullptr;
  double BakeSeconds = 0.0;

private:
  vtkHapticBoxBakeFilter(const vtkHapticBoxBakeFilter&) = delete;
  void operator=(const vtkHapticBoxBakeFilter&) = delete;
};

#endif
