/**
 * @class   vtkHapticBoxBakeFilter
 * @brief   Bakes haptic boxes for a surface (a thin adapter over hb::bake_cached with a
 *          hb::BakeRecipe: the same bake and the same box cache as `hapticbox bake`, the
 *          sweep, the report and the window).
 *
 * Input: a triangle surface; when it carries an integer cell array named PieceArrayName
 * (default "PieceId"), one box is baked per piece (distinct values are numbered 0..K-1 in
 * increasing order; neighbouring pieces share their seams per the recipe). Pieces made by
 * vtkHapticBoxDecompositionFilter with the options of the recipe's automatic pieces (its
 * field data "DecompositionOptions") are taken as the recipe's own: the bake does not
 * decompose again and the recipe, hence the cache key, stays the automatic one. Without such
 * an array: one box in all, or the recipe's own pieces (automatic or a piece file).
 * With a cache directory (SetCacheDirectory, e.g. hb::default_box_cache_dir()) and a source
 * mesh hash (SetSource: hb::hash_model of the file), a scene cached for (hash, recipe) is
 * loaded instead of baked, and a bake is stored there (hb::bake_cached, hb::BoxCache).
 * Outputs:
 *  0: vtkHapticBoxSet, the boxes (an hb::BoxScene), for vtkHapticBoxErrorFieldFilter;
 *  1: vtkPolyData, the PBB outlines (12 lines per box, cell data "BoxId");
 *  2: vtkPolyData, the position points (vertex cells; point data "BoxId" and "Face");
 *  3: vtkPolyData, the input surface with cell data "PieceId": the scene's piece (box) of
 *     each triangle, 0 everywhere for one box (what the .hbox file stores, also when cached).
 * Field data "BakeSeconds", "TableBytes" and "FromCache" on output 1. Progress events; abort
 * honoured (the bake stops within a few hundred rays per thread and the filter fails with an
 * error).
 */
#ifndef vtkHapticBoxBakeFilter_h
#define vtkHapticBoxBakeFilter_h

#include "recipe/bake_recipe.h"
#include <vtkPolyDataAlgorithm.h>
#include <string>

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

  ///@{
  /// The source mesh the scene records (path, hb::hash_model hash; triangles and diagonal are
  /// the input's when zero). The cache is used only with a non-zero hash.
  void SetSource(const hb::SourceInfo& source);
  const hb::SourceInfo& GetSource() const { return this->Source; }
  ///@}

  ///@{
  /// The box cache directory (hb::BoxCache); null or empty (the default): no cache.
  vtkSetStringMacro(CacheDirectory);
  vtkGetStringMacro(CacheDirectory);
  ///@}

  ///@{
  /// Only load from the cache: when it holds no readable scene for the source and recipe the
  /// update fails ("no cached scene") instead of baking (default off). For a front end that
  /// opens a cached bake where a bake must not run (a window's GUI thread).
  vtkSetMacro(CacheOnly, bool);
  vtkGetMacro(CacheOnly, bool);
  vtkBooleanMacro(CacheOnly, bool);
  ///@}

  /// True when the cache holds a scene for the source hash and the recipe (a cheap check of
  /// the entry's file; it is read, and checked, by the next update).
  bool HasCachedScene() const;
  /// The cache entry of the last update (empty without a cache), whether its scene came
  /// from there, and why a baked scene could not be stored (empty when it was).
  const std::string& GetCachePath() const { return this->CachePath; }
  bool GetFromCache() const { return this->FromCache; }
  const std::string& GetCacheWarning() const { return this->CacheWarning; }

  /// The boxes of the last update (output 0).
  vtkHapticBoxSet* GetBoxSet();
  /// Seconds the last bake took (0 when the scene came from the cache).
  vtkGetMacro(BakeSeconds, double);
  /// Why the last update failed (as vtkErrorMacro reported it, without its prefix), or empty.
  const std::string& GetLastError() const { return this->LastError; }

protected:
  vtkHapticBoxBakeFilter();
  ~vtkHapticBoxBakeFilter() override;
  vtkTypeBool ProcessRequest(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  hb::BakeRecipe Recipe;
  char* PieceArrayName = nullptr;
  char* CacheDirectory = nullptr;
  hb::SourceInfo Source;
  double BakeSeconds = 0.0;
  bool CacheOnly = false;
  bool FromCache = false;
  std::string CachePath;
  std::string CacheWarning;
  std::string LastError;

private:
  vtkHapticBoxBakeFilter(const vtkHapticBoxBakeFilter&) = delete;
  void operator=(const vtkHapticBoxBakeFilter&) = delete;
};

#endif
