// The surface of a budgeted bake (see budget_surface.h).
//  1. Above BudgetRecipe::simplify_above triangles (pieces of the bake's own), the mesh is
//     decimated within the deviation bound (BudgetRecipe::simplify_deviation, or
//     simplification_bound()), with the shading check the recipe asks for (none beyond the
//     budget's when a normal map carries the shading).
//     Above BudgetRecipe::simplify_once_above triangles (bake_to_budget's cascade) the full mesh is decimated once, within
//     the last retry's bound, and every attempt's surface from that one.
//  2. A simplification that keeps 90% of the triangles or more is not used.
//  3. Without a normal map the simplified surface takes corner normals fitted to the full
//     mesh's shading (fit_shading); either way its deviation from the full surface is measured
//     and recorded in the budget report.
//  4. The refinement records: the cast mesh's SurfaceTriangles, with a simplified surface's
//     normal map of the full mesh's shading (side 0: the power of two nearest above
//     sqrt(full / simplified triangles) less 5%, at most 32).
#include "recipe/budget_surface.h"
#include "errors.h"
#include "evaluation/surface_deviation.h"
#include "mesh/decimation.h"
#include "stopwatch.h"
#include <chrono>
#include <cmath>
#include <string>

namespace hb {

BudgetSurface simplify_for_budget(const TriangleMesh& mesh, const BakeRecipe& recipe, BudgetReport& rep,
                                  const BudgetStageDone& stage_done, BudgetReference& ref) {
  const BudgetRecipe& br = recipe.budget;
  BudgetSurface out;
  // Piece files and given ids name the full mesh's triangles: those bakes keep it.
  const bool own_pieces = recipe.pieces.kind == PiecesRecipe::Kind::automatic || recipe.pieces.kind == PiecesRecipe::Kind::none;
  if (!(br.simplify && own_pieces && mesh.triangle_count() > br.simplify_above)) return out;
  if (!(br.simplify_deviation >= 0.0 && br.simplify_deviation < 0.1))
    throw InvalidInput("bake: simplify deviation " + std::to_string(br.simplify_deviation) +
                       " out of range [0, 0.1) of the diagonal");
  const float diagonal = mesh.bounds().diagonal();
  const auto ts = std::chrono::steady_clock::now();
  DecimationOptions d;
  d.max_deviation = double(diagonal) * (br.simplify_deviation > 0 ? br.simplify_deviation : simplification_bound(br.budget));
  d.shading_check = br.simplify_shading_check;
  const bool fit_check = d.shading_check == DecimationOptions::ShadingCheck::fit;
  d.max_shading_deviation_deg = br.simplify_shading_deg > 0 ? br.simplify_shading_deg
                                : br.shading_map_side >= 0   ? 180.0  // the map carries the shading
                                                             : (fit_check ? 0.3 : 0.2) * br.budget.direction_p99_deg;
  const double bound = d.max_deviation;
  auto tstage = std::chrono::steady_clock::now();
  // The cascade (BudgetReference::finest): the full mesh decimated once, within the tightest
  // bound an attempt may ask; each attempt's surface decimated from that one within the rest of
  // its bound (a point of it is then within the two bounds' sum of the full surface).
  if (ref.finest_fraction > 0.0 && !ref.finest) {
    DecimationOptions f = d;
    f.max_deviation = bound * ref.finest_fraction;
    ref.finest = BudgetReference::Simplified{decimate(mesh, f).mesh, f.max_deviation};
    stage_done("decimate", seconds_since(tstage));
    tstage = std::chrono::steady_clock::now();
  }
  const bool from_finest = ref.finest && ref.finest->bound <= bound;
  DecimationResult dr;
  if (from_finest && bound - ref.finest->bound <= 1e-9 * bound) {
    dr.mesh = ref.finest->mesh;
  } else {
    if (from_finest) d.max_deviation = bound - ref.finest->bound;
    dr = decimate(from_finest ? ref.finest->mesh : mesh, d);
  }
  stage_done(from_finest ? "redecimate" : "decimate", seconds_since(tstage));
  if (double(dr.mesh.triangle_count()) < 0.9 * double(mesh.triangle_count())) {
    out.simplified = std::move(dr.mesh);
    out.use_simplified = true;
    // The exact answers shade with the full mesh's normals. With a normal map (the
    // default) the refinement shades through it (built once the exact BVH is) and the rays'
    // samples keep the simplified mesh's own normals (they serve only the boxes' route and
    // the blend view); without one, the refinement records and the rays' samples take corner
    // normals fitted to them (the decomposition, the lists and the grid keep the
    // shared-vertex surface; same triangles in the same order).
    if (br.shading_map_side < 0) {
      tstage = std::chrono::steady_clock::now();
      out.shaded = fit_shading(mesh, out.simplified, 0.002 * double(diagonal));
      stage_done("fit_shading", seconds_since(tstage));
    }
    tstage = std::chrono::steady_clock::now();
    const SurfaceDeviation dev =
        measure_deviation(mesh, br.shading_map_side < 0 ? out.shaded : out.simplified, 100000, 0.002 * double(diagonal));
    stage_done("deviation", seconds_since(tstage));
    rep.full_triangles = mesh.triangle_count();
    rep.surface_triangles = out.simplified.triangle_count();
    rep.surface_bound = bound;
    rep.surface_deviation_mean = dev.mean;
    rep.surface_deviation_p99 = dev.p99;
    rep.surface_deviation_max = dev.max;
    // The fitted corner normals' angles; a map's shading is judged by the fresh check.
    rep.surface_normal_median_deg = br.shading_map_side < 0 ? dev.normal_median_deg : 0.0;
    rep.surface_normal_p99_deg = br.shading_map_side < 0 ? dev.normal_p99_deg : 0.0;
  }
  rep.simplify_seconds = seconds_since(ts);
  return out;
}

std::shared_ptr<const SurfaceTriangles> refinement_surface(const TriangleMesh& mesh, const BudgetSurface& surface,
                                                           const BudgetRecipe& br, const EmbreeScene& full,
                                                           BudgetReport& rep, const BudgetStageDone& stage_done) {
  auto records = std::make_shared<SurfaceTriangles>(surface.cast(mesh, br));
  if (surface.use_simplified && br.shading_map_side >= 0) {
    // The full mesh's shading on a lattice over each simplified triangle.
    const TriangleMesh& base = surface.base(mesh);
    int side = br.shading_map_side;
    if (side == 0) {
      const double ratio = std::sqrt(double(mesh.triangle_count()) / double(base.triangle_count()));
      side = 1;
      while (side < 32 && double(side) < ratio / 1.05) side *= 2;  // within 5%: 52K of 13.3M is side 16
    }
    const auto tm = std::chrono::steady_clock::now();
    const float diagonal = mesh.bounds().diagonal();
    records->set_normal_map(side, fit_normal_map(mesh, base, side, 0.002 * double(diagonal), &full));
    rep.surface_map_side = std::uint32_t(side);
    stage_done("normal_map", seconds_since(tm));
  }
  return records;
}

} // namespace hb
