/**
 * @class   vtkHapticBoxBakeFilter
 * @brief   Bakes haptic boxes for a surface (a thin adapter over hb::bake with a
 *          hb::BakeRecipe: the same bake as `hapticbox bake` and the window).
 *
 * Input: a triangle surface; when it carries an integer cell array named PieceArrayName
 * (default "PieceId", e.g. from the decomposition filter), one box is baked per piece
 * (distinct values are numbered 0..K-1 in increasing order; neighbouring pieces share their
 * seams per the recipe), otherwise one box in all, or the recipe's own pieces (automatic or
 * a piece file) when it names some.
 * Outputs:
 *  0: vtkHapticBoxSet, the boxes (an hb::BoxScene), for vtkHapticBoxErrorFieldFilter;
 *  1: vtkPolyData, the PBB outlines (12 lines per box, cell data "BoxId");
 *  2: vtkPolyData, the position points (vertex cells; point data "BoxId" and "Face").
 * Field data "BakeSeconds" and "TableBytes" on output 1. Progress events; abort honoured
 * (the bake stops within a few hundred rays per thread and the filter fails with an error).
 */
#ifndef vtkHapticBoxBakeFilter_h
#define vtkHapticBoxBakeFilter_h

#include "haptic_box/bake_recipe.h"
#include <vtkPolyDataAlgorithm.h>

class vtkHapticBoxSet;

class vtkHapticBoxBakeFilter : public vtkPolyDataAlgorithm {
public:
  static vtkHapticBoxBakeFilter* New();
  vtkTypeMacro(vtkHapticBoxBakeFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The whole recipe (densities, padding, refinement, pieces, seams, codec); the setters
  /// below change single fields of it. Its progress callbacks are the filter's own.
  void SetRecipe(const hb::BakeRecipe& recipe);
  const hb::BakeRecipe& GetRecipe() const { return this->Recipe; }
  ///@}

  ///@{
  /// Position points per PBB face edge (m, default 32, in [2, 1024]).
  void SetM(int m);
  int GetM() const { return this->Recipe.options.params.m; }
  ///@}

  ///@{
  /// Directional points per sub-block face edge (n, default 16, in [2, 256]).
  void SetN(int n);
  int GetN() const { return this->Recipe.options.params.n; }
  ///@}

  ///@{
  /// PBB padding, fraction of the fitted box's diagonal (default 0.01).
  void SetPadding(double padding);
  double GetPadding() const { return this->Recipe.options.obb.padding; }
  ///@}

  ///@{
  /// Store the triangle each sample hit so queries refine exactly (hb::BakeOptions::refine,
  /// docs/refinement.md); default off.
  void SetRefine(bool refine);
  bool GetRefine() const { return this->Recipe.options.refine; }
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

  hb::BakeRecipe Recipe;
  char* PieceArrayName = nullptr;
  double BakeSeconds = 0.0;

private:
  vtkHapticBoxBakeFilter(const vtkHapticBoxBakeFilter&) = delete;
  void operator=(const vtkHapticBoxBakeFilter&) = delete;
};

#endif
