#pragma once
// The bake recipe: everything that decides what a bake produces (densities, padding,
// refinement, pieces, seams, codec), and the one bake(mesh, recipe) that every front end,
// the VTK bake filter and the sweep call. Add a field here (and to the box cache's key,
// box_cache.cpp) rather than assembling a bake by hand.
#include "codec/codec.h"
#include "decomposition/auto_decomposition.h"
#include "decomposition/seam_overlap.h"
#include "scene/bake.h"
#include "recipe/error_budget.h"
#include "mesh/decimation.h"
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hb {

/// How the mesh is cut into pieces before one box per piece is baked.
struct PiecesRecipe {
  enum class Kind {
    none,       ///< one box of all triangles.
    automatic,  ///< hb::decompose_auto with `automatic`.
    file,       ///< a piece id per triangle read from `file` (hb::read_piece_file).
    given,      ///< the ids in `given` (a piece id per triangle, e.g. a VTK cell array).
  };
  Kind kind = Kind::none;
  std::string file;                       ///< Kind::file: .txt or .ply piece file (Kind::given: the file the ids came from, if any).
  AutoDecompositionOptions automatic;     ///< Kind::automatic (its progress is the decomposition's).
  std::vector<std::uint32_t> given;       ///< Kind::given: one id per triangle, any values.
  /// Kind::automatic only: the ids hb::decompose_auto gave for `automatic` on this mesh when
  /// the caller already ran it (the VTK decomposition filter upstream of the bake filter), so
  /// the bake does not run it again. Not part of the cache key (the same options give the
  /// same ids); empty: the bake decomposes.
  std::vector<std::uint32_t> resolved;
};

/// "none" (or empty): one box; "auto": automatic; anything else: a piece file path.
PiecesRecipe pieces_from_spec(const std::string& spec);
/// The inverse of pieces_from_spec ("given" for given ids).
std::string pieces_spec(const PiecesRecipe& pieces);

/// One sampling a budgeted bake may give a piece: its position cell (fraction of the mesh
/// diagonal, per-box m from it, PositionDensity) and n.
struct Sampling {
  float cell = 0.016f;
  int n = 8;
};

/// The budgeted bake (budgeted_bake.cpp): per piece, the cheapest of `samplings` (and
/// refined or not) whose error on the piece's probes, measured against exact Embree during
/// the bake, meets `budget`; then the scene is checked whole and measured on fresh probes
/// (BudgetReport). Sampling order is cost order, cheapest first. The defaults were measured
/// on the armadillo (docs/speed.md): a refined n=6 box at 3.2% cells already meets the
/// default budget on most pieces; 1.6% cells n=8 is `./run.sh`'s former recipe.
struct BudgetRecipe {
  bool enabled = false;
  ErrorBudget budget;
  std::vector<Sampling> samplings = {{0.032f, 6}, {0.024f, 6}, {0.024f, 8}, {0.016f, 8}};
  std::size_t probes = 20000;       ///< tuning probes, and fresh probes for the report.
  std::uint64_t tuning_seed = 101;  ///< seeds other than eval's usual 1 and 2.
  std::uint64_t check_seed = 102;
  /// A piece stays unrefined only when none of the tuning probes it owns is answered from
  /// off the surface: a contact exact does not have, or a surface point farther than this
  /// (fraction of the mesh diagonal, along the probe) from exact's. Such a blend is a ghost
  /// surface on a trajectory (stability test T2: 0.1 mm in the suite's 80 mm device space
  /// is 0.125% of the OBB diagonal). 0: no such check.
  double surface_tolerance = 0.001;
  /// The surface the boxes are baked and refined against (so that memory and bake time stop
  /// growing with the triangle count): with `simplify`, meshes of more than
  /// `simplify_above` triangles are simplified (hb::decimate) within a deviation bound, and
  /// the decomposition, the rays, the triangle ids, the refinement records and the scene grid
  /// all use the simplified surface. The tuning and the fresh check compare against exact
  /// Embree on the FULL mesh, so the budget report is what a user of the full mesh gets.
  /// The bound is `simplify_deviation` x the diagonal, or with 0 the budget's share
  /// (simplification_bound()). A simplification that keeps more than 90% of the triangles
  /// is not used, nor is one for pieces from a file or given ids (they name the full
  /// mesh's triangles).
  /// On by default (docs/speed.md, "The simplified surface's normal map"): with the normal
  /// map below, a finely subdivided mesh comes back to about the triangles of its coarse
  /// original with the full mesh's shading, at a fraction of the memory; without the map the
  /// exact answers would shade faceted (direction p99 near 18 degrees on the armadillo at
  /// 832K triangles). A simplified surface whose bake misses the
  /// budget on the fresh probes, or that the box alone fails along the stability suite's T2
  /// trajectories (BakeResult::surface_miss), is dropped (BudgetReport::
  /// surface_rejected) and the mesh simplified again within a quarter of the bound (twice
  /// at most), then the full mesh baked: the bake then costs the attempts too.
  bool simplify = true;
  std::size_t simplify_above = 200000;
  /// With `simplify`, above this many triangles the full mesh is decimated once, within the
  /// last retry's bound, and each attempt's surface is decimated from that one (within the
  /// rest of its bound): decimating a 13M-triangle mesh afresh for each attempt would be
  /// most of its bake, three times over. Below, each attempt decimates the full mesh (a
  /// surface that meets at once then costs one decimation, not two).
  std::size_t simplify_once_above = 2000000;
  /// With `simplify`: the simplified surface shades through a normal map of this side
  /// (SurfaceTriangles::set_normal_map, hb::fit_normal_map: the full mesh's shading on a
  /// lattice over each simplified triangle, continuous across its edges), so the decimation
  /// is bounded by geometry alone (no shading check unless simplify_shading_deg is given).
  /// 0: automatic, the power of two nearest above sqrt(full / simplified triangles) less 5%, at most
  /// 32 (a mesh flat-subdivided L times comes back with side 2^L, its shading exactly; a map
  /// coarser than that is felt: the armadillo at 832K with side 2 instead of 4, 0.32% of
  /// the fresh probes; at 53M with side 16 instead of 32, 1.5% of T2's slide ticks. Side 32
  /// costs 2.2 KB a simplified triangle);
  /// -1: no map (corner normals fitted per face, the checks above).
  int shading_map_side = 0;
  double simplify_deviation = 0.0;
  /// Shading check (DecimationOptions::max_shading_deviation_deg): degrees, 0 for the
  /// default (fit check: 0.3 x the budget's direction p99; ring check: 0.2 x), 180 for none.
  double simplify_shading_deg = 0.0;
  /// How the shading is checked while simplifying (DecimationOptions::shading_check): by
  /// default `fit` (each face's corner normals fitted to the shading of the vertices it
  /// replaced); `ring` compares each vertex ring's normals instead. Either way the simplified
  /// surface's corner normals are then fitted to the full mesh's shading (hb::fit_shading).
  DecimationOptions::ShadingCheck simplify_shading_check = DecimationOptions::ShadingCheck::fit;
  /// Whether the chosen scene keeps its boxes' triangle ids. By default a scene whose grid's
  /// surface cells answer (SceneRoute::cells, every scene of several pieces with a refined
  /// one) drops them (BoxScene::without_triangle_ids): the cells route never reads them, and
  /// they can be two thirds of a default file (the bunny: 20.4 of 32.2 MB); and a scene
  /// routed to Embree (BudgetReport::answer "embree") keeps only its boxes' frames, no tables
  /// nor ids (BoxScene::without_tables: Embree reads the surface alone). Keep them to compare
  /// `--route boxes` on the default recipe (`bake --keep-ids`).
  bool keep_triangle_ids = false;
  /// Bake every piece at every sampling and search them all even when the surface cells
  /// answer the scene exactly (budgeted_bake.cpp step 2a), to compare every sampling's
  /// figures (`bake --full-search`). Off: such a scene is baked at the coarsest
  /// sampling only, unless the coarsest blend alone already meets the budget.
  bool full_search = false;
  /// Time the surface cells against Embree over the scene's surface at bake time and answer
  /// by the faster (BudgetReport::answer; budgeted_bake.cpp step 5b). False: the cells
  /// always (tests of the cells' machinery; a decision that depends on no clock).
  bool fastest_exact = true;
  /// Called on the bake's thread as each stage's work finishes (name as in
  /// BudgetReport::stage_seconds, the seconds of that part): `bake` prints them as it goes, so
  /// a bake of minutes shows where it is spending them before it ends. May be empty.
  std::function<void(const std::string& stage, double seconds)> on_stage;
  /// Called as a simplified surface is dropped, with one line: its triangles, its bound and
  /// what it missed (BudgetReport::surfaces_missed), and what the bake tries next. May be empty.
  std::function<void(const std::string& note)> on_note;
};

/// The deviation (fraction of the mesh diagonal) a budgeted bake may simplify its surface by:
/// a tenth of the contact-agreement allowance and a fiftieth of the p95 force bound, of the
/// deepest default probe (ProbeOptions::max_depth_fraction, 3% of the diagonal). Probes
/// deeper than a deviation d see a relative depth error below d / depth, and probes shallower
/// than d may change contact: for the default budget 1.5e-5 of the diagonal, at most 0.05%
/// of the probes' contacts and 0.05% of force errors over 7% even where the whole deviation
/// is reached (most of the surface is much closer). That share is then quartered: the
/// quadric bound holds the kept vertices, not the faces between them, and the measured
/// deviation went past it (13M armadillo at 1.5e-5: max 8.5x the bound, ghost forces in the
/// stability suite); at a quarter (3.75e-6 by default) the 13M armadillo comes back to 53,848
/// triangles instead of 79,024, p99 0.4x the bound, and passes every box-only stability
/// test (docs/speed.md, "The simplified surface's normal map").
double simplification_bound(const ErrorBudget& budget);

/// Everything a bake needs besides the mesh. Defaults: one m=32 n=16 raw box; the product's
/// default (`hapticbox bake MESH`, the window's Bake, `./run.sh`) is default_recipe().
struct BakeRecipe {
  /// Densities (params, per-box density), PBB padding (obb), refinement and progress of the
  /// ray casting (see BakeOptions).
  BakeOptions options;
  PiecesRecipe pieces;
  /// How far neighbouring pieces share their seams (widths in each box's own position cells,
  /// so with options.density they follow each box's m).
  SeamOptions seams;
  /// The table codec, applied after the bake; CodecId::none keeps raw 8-byte samples.
  CodecOptions codec{CodecId::none};
  /// When enabled, bake() is bake_to_budget(): options.params.n, options.density.cell and
  /// options.refine are chosen per piece from budget.samplings.
  BudgetRecipe budget;
};

/// The default bake: automatic pieces (threshold 0.001), the block codec at its default bound
/// (0.05% of each box's diagonal), the default error budget (BudgetRecipe), max m 128.
BakeRecipe default_recipe();

/// A bake's result.
struct BakeResult {
  BoxScene scene;                  ///< carries the piece ids (BoxScene::piece_of_triangle).
  BakeStats stats;                 ///< of the ray casting.
  double decompose_seconds = 0.0;  ///< automatic pieces only.
  double compress_seconds = 0.0;   ///< with a codec only.
  /// Budgeted bakes on a simplified surface that missed the budget: what it missed, in one
  /// line (the fresh probes' figures over the budget, or the stability suite's T2 metrics
  /// (sliding along the model, box against exact) the box fails and exact passes); such a
  /// surface is dropped (bake_to_budget). Empty when it met it, or on the full mesh.
  std::string surface_miss;
  /// That surface's exact scene answered slower than Embree over the full mesh: no tighter
  /// simplification is tried, the full mesh is baked.
  bool surface_slower_than_exact = false;
};

/// A piece id per triangle for `pieces`, numbered 0..K-1 in increasing order of the original
/// ids (empty for Kind::none: one piece). Throws what the piece reader or the decomposition
/// throws, hb::InvalidInput when given ids do not match the triangle count.
/// `scene`: an Embree scene of all of `mesh` the automatic decomposition may cast against
/// (decompose_auto's), or null.
std::vector<std::uint32_t> resolve_piece_ids(const TriangleMesh& mesh, const PiecesRecipe& pieces,
                                             const EmbreeScene* scene = nullptr);

/// The triangle lists to bake, one per piece (compact ids 0..K-1, empty: one piece), each grown
/// past its seams by `seams` measured in the cells of the box `options` would bake for it.
std::vector<std::vector<std::uint32_t>> seamed_piece_lists(const TriangleMesh& mesh,
                                                           const std::vector<std::uint32_t>& piece_ids,
                                                           const SeamOptions& seams, const BakeOptions& options);

/// `base` for one of a search's own bakes, in this process (the budgeted bake's pieces at a
/// sampling, the raw trial's boxes): refined against `surface` (none: the blend alone), no
/// scene grid (the search builds its own), no communicator, no progress (the search reports
/// its own). The caller sets the sampling.
BakeOptions search_bake_options(BakeOptions base, std::shared_ptr<const SurfaceTriangles> surface);

/// Bakes `mesh` per `recipe`: pieces (resolve_piece_ids), seams (seamed_piece_lists), one box
/// per piece (bake_scene_from_lists), then the codec. The scene records `source` and the
/// piece ids. Throws hb::InvalidInput, hb::IoError (piece file), hb::Cancelled, hb::LibraryError.
/// With recipe.budget.enabled, bake_to_budget().
BakeResult bake(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source = {});

/// The budgeted bake (see BudgetRecipe and budgeted_bake.cpp); the scene carries its
/// BudgetReport. One process only (throws hb::InvalidInput with several ranks), and what
/// bake() throws.
BakeResult bake_to_budget(const TriangleMesh& mesh, const BakeRecipe& recipe, const SourceInfo& source = {});

} // namespace hb
