// Simplification within a deviation bound (hb::decimate) and the budgeted bake that refines
// against the simplified surface while it is judged on the full mesh.
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "evaluation/surface_deviation.h"
#include "exact/exact_query.h"
#include "recipe/bake_recipe.h"
#include "recipe/budget_surface.h"
#include "mesh/decimation.h"
#include "mesh/generators.h"
#include "mesh/subdivision.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace hb {
namespace {

// A cube's faces split finely: flat, so it comes back to a few triangles per face; its
// vertices are original vertices and the surface does not move.
TEST(DecimationTest, FlatSubdivisionComesBackWithinTheBound) {
  const TriangleMesh fine = subdivide_midpoint(make_cube(Vec3(1.f, 2.f, 0.5f), 2), 3);  // 1,536 triangles
  DecimationOptions o;
  o.max_deviation = 1e-4 * double(fine.bounds().diagonal());
  const DecimationResult r = decimate(fine, o);
  EXPECT_LE(r.mesh.triangle_count(), 200u) << r.mesh.triangle_count();
  EXPECT_GE(r.mesh.triangle_count(), 12u);
  std::set<std::tuple<float, float, float>> original;
  for (const Vec3& p : fine.positions) original.insert({p.x(), p.y(), p.z()});
  for (const Vec3& p : r.mesh.positions) EXPECT_TRUE(original.count({p.x(), p.y(), p.z()}));
  EXPECT_EQ(r.mesh.normals.size(), r.mesh.positions.size());
  const SurfaceDeviation d = measure_deviation(fine, r.mesh, 5000, 0.01 * double(fine.bounds().diagonal()));
  EXPECT_EQ(d.samples, 5000u);
  EXPECT_LE(d.max, 1e-5 * double(fine.bounds().diagonal()));
  EXPECT_NEAR(r.mesh.area(), fine.area(), 1e-4 * fine.area());
}

// A sphere is curved everywhere: a tight bound keeps most of it, a loose one removes more,
// and the measured deviation stays near the bound (the quadric bounds the kept vertices'
// distance to the merged planes; a face between them can sag further: the bake reports the
// measured figure); a bound of 0 changes nothing.
TEST(DecimationTest, TheBoundLimitsHowFarTheSurfaceMoves) {
  const TriangleMesh sphere = make_sphere(1.f, 4);  // 5,120 triangles
  const double diagonal = double(sphere.bounds().diagonal());
  DecimationOptions none;
  EXPECT_EQ(decimate(sphere, none).mesh.triangle_count(), sphere.triangle_count());
  DecimationOptions tight, loose;
  tight.max_deviation = 1e-4 * diagonal;
  loose.max_deviation = 3e-3 * diagonal;
  const DecimationResult t = decimate(sphere, tight), l = decimate(sphere, loose);
  EXPECT_LT(l.mesh.triangle_count(), t.mesh.triangle_count());
  EXPECT_LT(l.mesh.triangle_count(), sphere.triangle_count() / 2);
  const SurfaceDeviation dl = measure_deviation(sphere, l.mesh, 5000, 0.05 * diagonal);
  // The shading check: a flat-subdivided sphere's vertex normals are faceted (a midpoint
  // vertex has its face's normal), so a 2-degree check keeps most of it.
  const TriangleMesh faceted = subdivide_midpoint(sphere, 1);
  DecimationOptions shaded = loose, unshaded = loose;
  shaded.max_shading_deviation_deg = 2.0;
  EXPECT_GT(decimate(faceted, shaded).mesh.triangle_count(), 2 * decimate(faceted, unshaded).mesh.triangle_count());
  EXPECT_GT(dl.max, 0.0);
  EXPECT_LE(dl.max, 6.0 * loose.max_deviation) << dl.max;
  EXPECT_THROW(decimate(TriangleMesh{}, tight), InvalidInput);
  DecimationOptions bad;
  bad.max_deviation = -1;
  EXPECT_THROW(decimate(sphere, bad), InvalidInput);
}

// Chunks decimated in parallel and joined give a closed surface as small as one pass's,
// within the same bound.
TEST(DecimationTest, ChunkedDecimationJoinsItsChunks) {
  const TriangleMesh fine = subdivide_midpoint(make_sphere(1.f, 3), 2);  // 20,480 triangles
  const double diagonal = double(fine.bounds().diagonal());
  DecimationOptions one, chunked;
  one.max_deviation = chunked.max_deviation = 1e-3 * diagonal;
  one.chunk_triangles = 0;
  chunked.chunk_triangles = 3000;
  const DecimationResult a = decimate(fine, one), b = decimate(fine, chunked);
  EXPECT_EQ(a.chunks, 1u);
  EXPECT_EQ(b.chunks, 7u);
  EXPECT_LT(b.mesh.triangle_count(), fine.triangle_count() / 4);
  EXPECT_LT(double(b.mesh.triangle_count()), 1.5 * double(a.mesh.triangle_count()));
  // Closed: every edge has two faces.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const Triangle& t : b.mesh.triangles)
    for (int k = 0; k < 3; ++k) ++edges[std::minmax(t[std::size_t(k)], t[std::size_t((k + 1) % 3)])];
  for (const auto& [e, count] : edges) EXPECT_EQ(count, 2);
  EXPECT_LE(measure_deviation(fine, b.mesh, 5000, 0.05 * diagonal).max, 6.0 * chunked.max_deviation);
}

// The budgeted bake of a finely subdivided sphere refines against a simplified surface,
// reports it, and its budget report is the scene's error against the FULL mesh.
TEST(DecimationTest, BudgetedBakeRefinesAgainstTheSimplifiedSurfaceAndIsJudgedOnTheFullMesh) {
  const TriangleMesh fine = subdivide_midpoint(make_sphere(1.f, 3), 2);  // 20,480 triangles
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::none;
  recipe.budget.probes = 2000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.simplify = true;
  recipe.budget.simplify_above = 10000;
  recipe.budget.simplify_shading_deg = 180;  // the subdivided sphere's shading is faceted
  recipe.budget.fastest_exact = false;       // the simplified surface's scene, not Embree's
  const BakeResult baked = bake(fine, recipe);
  const BudgetReport& rep = baked.scene.parts().budget;
  ASSERT_TRUE(rep.present);
  EXPECT_EQ(rep.full_triangles, fine.triangle_count());
  EXPECT_GT(rep.surface_triangles, 0u);
  EXPECT_LT(rep.surface_triangles, fine.triangle_count());
  EXPECT_DOUBLE_EQ(rep.surface_bound, simplification_bound(recipe.budget.budget) * double(fine.bounds().diagonal()));
  EXPECT_GT(rep.surface_deviation_max, 0.0);
  ASSERT_EQ(baked.scene.parts().boxes.size(), 1u);
  EXPECT_TRUE(baked.scene.parts().boxes[0].refines());
  EXPECT_EQ(baked.scene.parts().source.triangles, fine.triangle_count());
  EXPECT_NE(rep.summary().find("refined against"), std::string::npos) << rep.summary();
  // What eval would say on the full mesh with the check's seed.
  ProbeOptions po;
  po.seed = recipe.budget.check_seed;
  const ExactQuery exact(fine);
  // At the workspace scale the bake judges at.
  const ComparisonStats s = compare_queries(baked.scene, exact, sample_probes(fine, 2000, po),
                                            make_workspace(fine.bounds().diagonal()).law(), fine.bounds().diagonal());
  EXPECT_DOUBLE_EQ(s.contact_agreement, rep.agreement);
  EXPECT_DOUBLE_EQ(s.force_error_p95, rep.force_p95);
  EXPECT_TRUE(rep.met) << rep.summary();
  const BudgetReport back = BudgetReport::parse(rep.serialize());
  EXPECT_EQ(back.surface_triangles, rep.surface_triangles);
  EXPECT_NEAR(back.surface_deviation_max, rep.surface_deviation_max, 1e-8 * rep.surface_deviation_max);
  // Below the threshold the full mesh is the surface.
  recipe.budget.simplify_above = fine.triangle_count();
  EXPECT_EQ(bake(fine, recipe).scene.parts().budget.surface_triangles, 0u);
}

// The window decomposes the full mesh before its bake (the VTK decomposition filter hands the
// ids on as PiecesRecipe::resolved); a large mesh's bake then works on a simplified surface,
// which is cut anew: the full mesh's ids are not its triangles' (the window failed to bake the
// 832K armadillo: "832000 decomposed piece ids for 52020 triangles").
TEST(DecimationTest, PiecesResolvedOnTheFullMeshAreCutAnewOnASimplifiedSurface) {
  const TriangleMesh fine = subdivide_midpoint(make_sphere(1.f, 3), 2);  // 20,480 triangles
  BakeRecipe recipe = default_recipe();
  ASSERT_EQ(recipe.pieces.kind, PiecesRecipe::Kind::automatic);
  recipe.pieces.resolved.assign(fine.triangle_count(), 0);
  for (std::size_t t = 0; t < fine.triangle_count(); ++t)
    if (fine.positions[fine.triangles[t][0]].x() > 0.f) recipe.pieces.resolved[t] = 1;
  recipe.budget.budget.raw = false;  // the pieces' path, not the raw box over the whole model
  recipe.budget.probes = 2000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.simplify_above = 10000;
  recipe.budget.simplify_shading_deg = 180;
  recipe.budget.fastest_exact = false;
  const BakeResult baked = bake(fine, recipe);
  const BudgetReport& rep = baked.scene.parts().budget;
  EXPECT_GT(rep.surface_triangles, 0u) << rep.summary();
  EXPECT_LT(rep.surface_triangles, fine.triangle_count());
  EXPECT_FALSE(baked.scene.parts().boxes.empty());
}

// A simplified surface that misses the budget is simplified again within a quarter of the
// bound (twice at most) before the full mesh is baked, and the report names the surface it
// dropped: a sphere simplified far too coarsely comes back within a tighter bound; a lathe
// surface that a hand sliding over it would feel drop out (T2's trajectories) at every bound
// tried falls back to the full mesh.
TEST(DecimationTest, ASimplifiedSurfaceThatMissesTheBudgetIsSimplifiedAgainWithinATighterBound) {
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::none;
  recipe.budget.probes = 3000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.simplify_above = 5000;
  recipe.budget.fastest_exact = false;  // the simplified surfaces' scenes, not Embree's
  {
    const TriangleMesh fine = subdivide_midpoint(make_sphere(1.f, 3), 2);  // 20,480 triangles
    recipe.budget.simplify_deviation = 4e-4;  // far looser than the automatic bound
    std::vector<std::string> notes;  // said as each surface is dropped
    recipe.budget.on_note = [&](const std::string& note) { notes.push_back(note); };
    const BudgetReport rep = bake(fine, recipe).scene.parts().budget;
    recipe.budget.on_note = nullptr;
    EXPECT_TRUE(rep.met) << rep.summary();
    EXPECT_GT(rep.surface_rejected, 0u) << rep.summary();
    EXPECT_GT(rep.surface_triangles, 0u) << rep.summary();
    const double asked = recipe.budget.simplify_deviation * double(fine.bounds().diagonal());
    const double ratio = rep.surface_bound / asked;  // a quarter per retry
    EXPECT_TRUE(std::fabs(ratio - 0.25) < 1e-9 || std::fabs(ratio - 0.0625) < 1e-9) << ratio;
    EXPECT_NE(rep.summary().find("simplified again within a tighter bound"), std::string::npos) << rep.summary();
    // Every surface dropped is on record, tighter one after another, the last the one named.
    ASSERT_FALSE(rep.surfaces_missed.empty());
    EXPECT_EQ(rep.surfaces_missed.back().triangles, rep.surface_rejected);
    EXPECT_EQ(rep.surfaces_missed.back().why, rep.surface_rejected_why);
    ASSERT_EQ(notes.size(), rep.surfaces_missed.size());
    EXPECT_NE(notes.back().find(std::to_string(rep.surface_rejected) + " triangles"), std::string::npos) << notes.back();
    EXPECT_NE(notes.back().find(rep.surface_rejected_why), std::string::npos) << notes.back();
    for (std::size_t i = 1; i < rep.surfaces_missed.size(); ++i)
      EXPECT_NEAR(rep.surfaces_missed[i].bound, 0.25 * rep.surfaces_missed[i - 1].bound, 1e-12);
    // What the dropped surface missed, named: a figure over the budget on the fresh probes,
    // or T2's metrics.
    EXPECT_TRUE(rep.surface_rejected_why.rfind("fresh probes: ", 0) == 0 ||
                rep.surface_rejected_why.rfind("T2's trajectories: ", 0) == 0)
        << rep.surface_rejected_why;
  }
  {
    ChessPieceOptions options;
    options.profile_samples = 120;
    options.segments = 80;
    const TriangleMesh piece = make_chess_piece(options);
    recipe.pieces = default_recipe().pieces;  // several pieces: the full mesh meets the budget
    recipe.budget.simplify_deviation = 1.6e-4;
    DecimationOptions first;
    first.max_deviation = recipe.budget.simplify_deviation * double(piece.bounds().diagonal());
    const std::size_t first_try = decimate(piece, first).mesh.triangle_count();
    const BudgetReport rep = bake(piece, recipe).scene.parts().budget;
    EXPECT_TRUE(rep.met) << rep.summary();
    EXPECT_EQ(rep.surface_triangles, 0u) << rep.summary();
    EXPECT_GT(rep.surface_rejected, first_try) << "the last surface dropped is a tighter one";
    EXPECT_NE(rep.summary().find("baked on the full mesh"), std::string::npos) << rep.summary();
    EXPECT_FALSE(rep.surface_rejected_why.empty());
    EXPECT_NE(rep.summary().find(rep.surface_rejected_why), std::string::npos) << rep.summary();
  }
}

// Above BudgetRecipe::simplify_once_above triangles the full mesh is decimated once, within
// the last retry's bound, and each attempt's surface from that one: a retry then costs a
// decimation of the simplified surface, not of the full mesh, and the surfaces are as close
// to the full one as those decimated from it directly.
TEST(DecimationTest, AHugeMeshIsDecimatedOnceHoweverOftenTheBoundIsTightened) {
  const TriangleMesh fine = make_sphere(1.f, 5);  // 20,480 triangles, curved everywhere
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::none;
  recipe.budget.simplify_above = 5000;
  recipe.budget.simplify_deviation = 4e-4;
  const double diagonal = double(fine.bounds().diagonal());
  {
    // The surface step alone: the first call makes the finest surface (a sixteenth of the
    // bound), every call simplifies from it; a bound that leaves 90% of the triangles or
    // more uses none (the finest here keeps 95%).
    BudgetReference ref;
    ref.finest_fraction = 1.0 / 16.0;
    std::vector<std::string> stages;
    const BudgetStageDone done = [&](const char* name, double) { stages.push_back(name); };
    BudgetReport rep;
    const BudgetSurface first = simplify_for_budget(fine, recipe, rep, done, ref);
    ASSERT_TRUE(ref.finest.has_value());
    EXPECT_NEAR(ref.finest->bound, diagonal * 4e-4 / 16.0, 1e-12);
    EXPECT_NEAR(rep.surface_bound, diagonal * 4e-4, 1e-12) << "the report states the whole bound";
    EXPECT_LT(first.simplified.triangle_count(), ref.finest->mesh.triangle_count());
    EXPECT_EQ(std::count(stages.begin(), stages.end(), std::string("decimate")), 1);
    EXPECT_EQ(std::count(stages.begin(), stages.end(), std::string("redecimate")), 1);
    const TriangleMesh* finest = &ref.finest->mesh;
    recipe.budget.simplify_deviation = 4e-4 / 4.0;
    const BudgetSurface second = simplify_for_budget(fine, recipe, rep, done, ref);
    EXPECT_EQ(&ref.finest->mesh, finest) << "made once";
    EXPECT_GT(second.simplified.triangle_count(), first.simplified.triangle_count());
    recipe.budget.simplify_deviation = 4e-4 / 16.0;
    EXPECT_FALSE(simplify_for_budget(fine, recipe, rep, done, ref).use_simplified);
    EXPECT_EQ(std::count(stages.begin(), stages.end(), std::string("decimate")), 1) << "the full mesh once";
    // As close to the full surface as one decimation within the whole bound, measured (the
    // quadric bounds the kept vertices' distance to the merged planes; a curved surface
    // sags between them by more: both are about 4x the bound at p99 here).
    DecimationOptions direct;
    direct.max_deviation = diagonal * 4e-4;
    const TriangleMesh once = decimate(fine, direct).mesh;
    const SurfaceDeviation cascade = measure_deviation(fine, first.simplified, 5000, 0.01 * diagonal);
    const SurfaceDeviation single = measure_deviation(fine, once, 5000, 0.01 * diagonal);
    EXPECT_LE(cascade.p99, 1.25 * single.p99) << single.p99;
    EXPECT_LE(cascade.max, 1.25 * single.max) << single.max;
    EXPECT_NEAR(double(first.simplified.triangle_count()), double(once.triangle_count()), 0.2 * double(once.triangle_count()));
  }
  recipe.budget.simplify_deviation = 4e-4;
  // The whole bake on the cascade meets the budget, every attempt's stages in its record.
  recipe.budget.probes = 3000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.fastest_exact = false;
  recipe.budget.simplify_once_above = 5000;
  const BudgetReport rep = bake(fine, recipe).scene.parts().budget;
  EXPECT_TRUE(rep.met) << rep.summary();
  bool redecimated = false;
  for (const auto& [name, seconds] : rep.stage_seconds) redecimated = redecimated || name == "redecimate";
  EXPECT_TRUE(redecimated) << "every attempt's stages are in the record";
}

// A simplified surface whose exact scene answers slower than Embree over the full mesh serves
// neither time nor accuracy: it is dropped at once (no tighter bound tried) and the full
// mesh is baked, answered by the faster exact route. Timed on this machine, so the test holds
// whichever side wins: the record agrees with the timing.
TEST(DecimationTest, ASimplifiedSurfaceSlowerThanEmbreeIsDroppedForTheFullMeshAtOnce) {
  const TriangleMesh fine = subdivide_midpoint(make_sphere(1.f, 3), 2);  // 20,480 triangles
  BakeRecipe recipe = default_recipe();
  recipe.pieces.kind = PiecesRecipe::Kind::none;
  recipe.budget.probes = 3000;
  recipe.budget.samplings = {{0.1f, 6}};
  recipe.budget.simplify_above = 5000;
  const BudgetReport rep = bake(fine, recipe).scene.parts().budget;
  EXPECT_TRUE(rep.met) << rep.summary();
  const std::string slower = "the simplified surface's exact scene (";
  if (rep.surface_rejected_why.rfind(slower, 0) == 0) {
    EXPECT_EQ(rep.surface_triangles, 0u) << rep.summary();
    DecimationOptions first;
    first.max_deviation = simplification_bound(recipe.budget.budget) * double(fine.bounds().diagonal());
    EXPECT_EQ(rep.surface_rejected, decimate(fine, first).mesh.triangle_count()) << "no tighter surface tried";
    EXPECT_NE(rep.summary().find("baked on the full mesh"), std::string::npos) << rep.summary();
    EXPECT_TRUE(rep.answer == Answerer::embree || rep.answer == Answerer::boxes) << answerer_name(rep.answer);
    EXPECT_LE(rep.answer_ns, rep.exact_ns * 1.0000001) << rep.summary();
  } else {
    // Its scene was the faster: kept, or dropped for what it missed (T2, the fresh probes).
    EXPECT_TRUE(rep.surface_triangles > 0 || !rep.surface_rejected_why.empty()) << rep.summary();
  }
}

} // namespace
} // namespace hb
