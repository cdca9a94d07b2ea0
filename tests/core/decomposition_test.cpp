// Decomposition: pocket measure, automatic pieces, seams, manual pieces, scenes of many boxes.
#include "decomposition/auto_decomposition.h"
#include "decomposition/piece_file.h"
#include "decomposition/plane_split.h"
#include "decomposition/pocket_measure.h"
#include "decomposition/seam_overlap.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "recipe/bake_recipe.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <fstream>
#include <set>

namespace hb {
namespace {

const ForceLaw kDecompositionLaw{1000.f, 1.f};

BoxScene bake_lists(const TriangleMesh& mesh, const std::vector<std::vector<std::uint32_t>>& lists, int m, int n) {
  BakeOptions options;
  options.params = {m, n};
  return bake_scene_from_lists(mesh, lists, options, {});
}

// The pieces grown past their seams by `rings` and `cells` cells of an m-box's grid.
std::vector<std::vector<std::uint32_t>> seamed(const TriangleMesh& mesh, const std::vector<std::uint32_t>& ids,
                                               int rings, float cells, int m = 32) {
  SeamOptions s;
  s.rings = rings;
  s.cells = cells;
  BakeOptions options;
  options.params.m = m;
  return seamed_piece_lists(mesh, ids, s, options);
}

std::size_t count_pieces(const std::vector<std::uint32_t>& ids) {
  return std::set<std::uint32_t>(ids.begin(), ids.end()).size();
}

std::string temp_path(const std::string& name) {
  return testing::TempDir() + "hb_decomposition_" + name;
}

TEST(PocketMeasureTest, BumpySphereScoresWellBelowTorus) {
  BumpySphereOptions bumpy;
  bumpy.subdivisions = 4;
  const PocketScore sphere = measure_pockets(make_bumpy_sphere(bumpy));
  const PocketScore torus = measure_pockets(make_torus(1.f, 0.3f, 64, 24));
  EXPECT_LT(sphere.probability, 0.01);
  EXPECT_GT(torus.probability, 0.02);
  EXPECT_GT(torus.mean_depth, 0.0);
  EXPECT_LE(torus.mean_depth, torus.max_depth);
  EXPECT_LE(torus.max_depth, 1.0);
}

TEST(PocketMeasureTest, ConvexShapesHaveNoPockets) {
  EXPECT_EQ(measure_pockets(make_sphere(1.f, 3)).probability, 0.0);
  EXPECT_EQ(measure_pockets(make_cube(Vec3(1.f, 2.f, 0.5f), 3)).probability, 0.0);
}

// The score is a function of the seed alone: the lines are drawn per index from the seed and
// summed in order, so one thread and four give the same score bit for bit; another seed draws
// other lines (a different score, within the measure's small variance).
TEST(PocketMeasureTest, SameSeedSameScoreOnAnyThreadCount) {
  const TriangleMesh torus = make_torus(1.f, 0.3f, 48, 16);
  PocketScore one_thread, four_threads;
  tbb::task_arena(1).execute([&] { one_thread = measure_pockets(torus); });
  tbb::task_arena(4).execute([&] { four_threads = measure_pockets(torus); });
  EXPECT_EQ(one_thread.probability, four_threads.probability);
  EXPECT_EQ(one_thread.mean_depth, four_threads.mean_depth);
  EXPECT_EQ(one_thread.max_depth, four_threads.max_depth);
  EXPECT_EQ(one_thread.lines, four_threads.lines);
  PocketOptions other;
  other.seed = 2;
  const PocketScore reseeded = measure_pockets(torus, {}, other);
  EXPECT_NE(reseeded.probability, one_thread.probability) << "the seed does not choose the lines";
  EXPECT_NEAR(reseeded.probability, one_thread.probability, 0.2 * one_thread.probability);
}

TEST(AutoDecompositionTest, ConvexShapeStaysOnePiece) {
  for (const TriangleMesh& mesh : {make_sphere(1.f, 3), make_ellipsoid(Vec3(2.f, 1.f, 0.5f), 3),
                                   make_cube(Vec3(1.f, 1.f, 1.f), 6)}) {
    const Decomposition d = decompose_auto(mesh);
    EXPECT_EQ(d.piece_count, 1u);
    EXPECT_EQ(count_pieces(d.piece_of_triangle), 1u);
  }
}

TEST(AutoDecompositionTest, TorusSplitsAndPocketErrorsVanish) {
  const TriangleMesh torus = make_torus(1.f, 0.3f, 64, 20);
  const Decomposition d = decompose_auto(torus);
  ASSERT_GE(d.piece_count, 2u);
  EXPECT_LE(d.piece_count, 12u);
  const double whole = measure_pockets(torus).probability;
  for (const auto& piece : seamed(torus, d.piece_of_triangle, 0, 0.f))
    EXPECT_LT(measure_pockets(torus, piece).probability, 0.25 * whole);

  // Probes from the hole to the inner wall of the ring: a single box stores the far side of
  // the ring first (behind the handle) and loses them; the pieces do not.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<Segment> probes;
  for (int k = 0; k < 400; ++k) {
    const float phi = 2.f * float(M_PI) * u(rng), rho = 0.3f * u(rng), z = 0.1f * (u(rng) - 0.5f);
    const Vec3 start(rho * std::cos(phi), rho * std::sin(phi), z);
    const float psi = phi + 0.3f * (u(rng) - 0.5f);
    const Vec3 end(0.78f * std::cos(psi), 0.78f * std::sin(psi), z + 0.1f * (u(rng) - 0.5f));
    probes.push_back({start, end});
  }
  const ExactQuery exact(torus);
  const int m = 12, n = 8;
  const BoxScene single = bake_lists(torus, piece_triangle_lists(torus, {}), m, n);
  const BoxScene split = bake_lists(torus, seamed(torus, d.piece_of_triangle, 1, 1.5f, m), m, n);
  int exact_contacts = 0, single_missed = 0, split_missed = 0;
  for (const Segment& s : probes) {
    if (!exact.query(s, kDecompositionLaw).contact) continue;
    ++exact_contacts;
    single_missed += single.query(s, kDecompositionLaw).contact ? 0 : 1;
    split_missed += split.query(s, kDecompositionLaw).contact ? 0 : 1;
  }
  EXPECT_GT(exact_contacts, 300);
  EXPECT_GT(single_missed, exact_contacts / 2);
  EXPECT_LE(split_missed, exact_contacts / 50);
}

TEST(AutoDecompositionTest, LShapeSplits) {
  // Two boxes glued into an L (a closed mesh is not needed for the measure: two overlapping
  // closed cubes give the same pocket structure).
  TriangleMesh a = make_cube(Vec3(2.f, 0.5f, 0.5f), 8), b = make_cube(Vec3(0.5f, 2.f, 0.5f), 8);
  TriangleMesh l = a;
  const Vec3 shift_a(2.f, 0.f, 0.f), shift_b(0.f, 2.f, 0.f);
  for (auto& p : l.positions) p += shift_a;
  const std::uint32_t base = std::uint32_t(l.positions.size());
  for (auto p : b.positions) l.positions.push_back(p + shift_b);
  for (auto t : b.triangles) l.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  l.compute_vertex_normals();
  EXPECT_GT(measure_pockets(l).probability, 0.01);
  const Decomposition d = decompose_auto(l);
  EXPECT_GE(d.piece_count, 2u);
}

TEST(AutoDecompositionTest, DeterministicForSameInput) {
  const TriangleMesh torus = make_torus(1.f, 0.35f, 48, 16);
  const Decomposition first = decompose_auto(torus);
  Decomposition serial;
  tbb::task_arena one(1);
  one.execute([&] { serial = decompose_auto(torus); });
  EXPECT_EQ(first.piece_of_triangle, serial.piece_of_triangle);
  EXPECT_EQ(first.piece_of_triangle, decompose_auto(torus).piece_of_triangle);
}

TEST(AutoDecompositionTest, MaxPiecesHolds) {
  AutoDecompositionOptions options;
  options.threshold = 0.0;
  options.max_pieces = 3;
  const Decomposition d = decompose_auto(make_torus(1.f, 0.3f, 48, 16), options);
  EXPECT_LE(d.piece_count, 3u);
  EXPECT_GE(d.piece_count, 1u);
}

TEST(AutoDecompositionTest, ProgressAdvancesThroughEveryPhaseAndCancelStopsEarly) {
  // A window's bar moves while the decomposition runs (not 0% then 100%) and a cancel is seen
  // within a small share of the work, also while the random lines are cast.
  const TriangleMesh torus = make_torus(1.f, 0.35f, 48, 16);
  std::vector<double> seen;
  AutoDecompositionOptions options;
  options.lines = 30000;  // quick; still 24 chunks of lines
  const Decomposition expected = decompose_auto(torus, options);
  options.progress = [&](double f) {
    seen.push_back(f);
    return true;
  };
  EXPECT_EQ(decompose_auto(torus, options).piece_of_triangle, expected.piece_of_triangle);  // chunks change nothing
  ASSERT_FALSE(seen.empty());
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]) << "report " << i;
  std::size_t during_lines = 0, before_merging = 0;
  for (double f : seen) {
    during_lines += f > 0.05 && f < 0.3;
    before_merging += f > 0.4 && f < 0.5;
  }
  EXPECT_GE(during_lines, 10u);
  EXPECT_GE(before_merging, 1u);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  int calls = 0;
  options.progress = [&](double f) { return ++calls < 3 && f < 0.1; };  // cancel while the lines are cast
  EXPECT_THROW(decompose_auto(torus, options), Cancelled);
  EXPECT_EQ(calls, 3);
}

TEST(AutoDecompositionTest, RejectsBadOptions) {
  AutoDecompositionOptions options;
  options.max_pieces = 0;
  EXPECT_THROW(decompose_auto(make_sphere(1.f, 1), options), InvalidInput);
  EXPECT_THROW(decompose_auto(TriangleMesh{}), InvalidInput);
}

TEST(SeamOverlapTest, RingsShareSeamTriangles) {
  const TriangleMesh sphere = make_sphere(1.f, 3);
  const auto ids = split_by_planes(sphere, {{Vec3::Zero(), Vec3::UnitZ()}});
  const auto disjoint = seamed(sphere, ids, 0, 0.f);
  const auto shared = seamed(sphere, ids, 1, 0.f);
  ASSERT_EQ(disjoint.size(), 2u);
  ASSERT_EQ(shared.size(), 2u);
  EXPECT_EQ(disjoint[0].size() + disjoint[1].size(), sphere.triangle_count());
  EXPECT_GT(shared[0].size(), disjoint[0].size());
  EXPECT_GT(shared[1].size(), disjoint[1].size());
}

TEST(SeamOverlapTest, SeamCrossingKeepsContact) {
  // A sphere cut at its equator into two boxes; probes aimed at (and sliding across) the
  // seam from outside must all keep contact with the right depth.
  const float r = 1.f;
  const TriangleMesh sphere = make_sphere(r, 5);
  const auto ids = split_by_planes(sphere, {{Vec3::Zero(), Vec3::UnitZ()}});
  const BoxScene scene = bake_lists(sphere, seamed(sphere, ids, 1, 1.5f, 16), 16, 8);
  ASSERT_EQ(scene.parts().boxes.size(), 2u);
  const ExactQuery exact(sphere);
  int checked = 0;
  for (int k = 0; k < 72; ++k) {
    const float phi = float(k) * 2.f * float(M_PI) / 72.f;
    const Vec3 radial(std::cos(phi), std::sin(phi), 0.f);
    for (float z = -0.06f; z <= 0.061f; z += 0.02f) {
      // Tilted up/down so the segment crosses the seam plane inside the sphere.
      const Vec3 target = 0.9f * r * radial;
      const Vec3 start = 1.5f * r * radial + Vec3(0.f, 0.f, z * 4.f);
      const Segment s{start, target - Vec3(0.f, 0.f, z)};
      const Contact e = exact.query(s, kDecompositionLaw);
      if (!e.contact) continue;
      const Contact c = scene.query(s, kDecompositionLaw);
      ++checked;
      ASSERT_TRUE(c.contact) << "phi " << phi << " z " << z;
      EXPECT_NEAR(c.depth, e.depth, 0.01f * r);
    }
  }
  EXPECT_GT(checked, 400);
}

TEST(BoxSceneTest, NearestValidContactWinsAndBoxesMetCount) {
  // Two separate spheres on the x axis; a segment through both meets two boxes and the
  // contact is with the first sphere.
  TriangleMesh two = make_sphere(0.5f, 3);
  const std::uint32_t base = std::uint32_t(two.positions.size());
  const TriangleMesh other = make_sphere(0.5f, 3);
  for (auto& p : two.positions) p.x() -= 1.f;
  for (auto p : other.positions) two.positions.push_back(p + Vec3(1.f, 0.f, 0.f));
  for (auto t : other.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  two.compute_vertex_normals();
  std::vector<std::uint32_t> ids(two.triangle_count(), 0);
  for (std::size_t t = two.triangle_count() / 2; t < two.triangle_count(); ++t) ids[t] = 1;
  const BoxScene scene = bake_lists(two, seamed(two, ids, 0, 0.f), 12, 8);
  const Segment through{Vec3(-2.f, 0.01f, 0.f), Vec3(1.2f, 0.01f, 0.f)};
  EXPECT_EQ(boxes_met(scene, through), 2u);
  const Contact c = scene.query(through, kDecompositionLaw);
  ASSERT_TRUE(c.contact);
  EXPECT_NEAR(c.point.x(), -1.5f, 0.01f);
  const Segment one{Vec3(2.f, 0.01f, 0.f), Vec3(1.3f, 0.01f, 0.f)};
  EXPECT_EQ(boxes_met(scene, one), 1u);
  EXPECT_TRUE(scene.query(one, kDecompositionLaw).contact);
  EXPECT_EQ(boxes_met(scene, {Vec3(0.f, 3.f, 0.f), Vec3(0.f, 4.f, 0.f)}), 0u);
  // A handle inside the first sphere: the first surface from it is an inside one, so the
  // second sphere's surface ahead is no contact (as for the exact answer).
  const Segment inside{Vec3(-1.1f, 0.01f, 0.f), Vec3(0.8f, 0.01f, 0.f)};
  EXPECT_FALSE(ExactQuery(two).query(inside, kDecompositionLaw).contact);
  EXPECT_FALSE(scene.query(inside, kDecompositionLaw).contact);
}

TEST(PlaneSplitTest, TwoPlanesGiveFourPieces) {
  const TriangleMesh sphere = make_sphere(1.f, 3);
  const auto ids = split_by_planes(sphere, {{Vec3::Zero(), Vec3::UnitX()}, {Vec3::Zero(), Vec3::UnitY()}});
  EXPECT_EQ(count_pieces(ids), 4u);
  EXPECT_EQ(*std::max_element(ids.begin(), ids.end()), 3u);
  EXPECT_THROW(split_by_planes(sphere, {{Vec3::Zero(), Vec3::Zero()}}), InvalidInput);
}

TEST(PieceFileTest, TextAndPlyRoundTrip) {
  const TriangleMesh cube = make_cube(Vec3(1.f, 1.f, 1.f), 2);
  std::vector<std::uint32_t> ids(cube.triangle_count());
  for (std::size_t t = 0; t < ids.size(); ++t) ids[t] = std::uint32_t(t % 5);
  for (const char* ext : {".txt", ".ply"}) {
    const std::string path = temp_path(std::string("roundtrip") + ext);
    write_piece_file(path, cube, ids);
    EXPECT_EQ(read_piece_file(path, cube.triangle_count()), ids) << ext;
    std::remove(path.c_str());
  }
}

TEST(PieceFileTest, BinaryPlyWithQuadFaces) {
  const std::string path = temp_path("quads.ply");
  {
    std::ofstream out(path, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
           "property float z\nelement face 2\nproperty list uchar int vertex_indices\nproperty int label\n"
           "end_header\n";
    const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    out.write(reinterpret_cast<const char*>(v), sizeof(v));
    const unsigned char four = 4, three = 3;
    const int quad[4] = {0, 1, 2, 3}, tri[3] = {0, 2, 3}, id0 = 7, id1 = 2;
    out.write(reinterpret_cast<const char*>(&four), 1);
    out.write(reinterpret_cast<const char*>(quad), sizeof(quad));
    out.write(reinterpret_cast<const char*>(&id0), 4);
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(tri), sizeof(tri));
    out.write(reinterpret_cast<const char*>(&id1), 4);
  }
  EXPECT_EQ(read_piece_file(path, 3), (std::vector<std::uint32_t>{7, 7, 2}));
  EXPECT_THROW(read_piece_file(path, 4), InvalidInput);
  std::remove(path.c_str());
}

TEST(PieceFileTest, BinaryPlyWhoseCountsAndBytesDisagreeIsRefused) {
  // A cube's 12 triangles in 6 pieces, binary; then bytes shifted, added or a count changed.
  const TriangleMesh cube = make_cube(Vec3(1.f, 1.f, 1.f), 1);
  std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(cube.vertex_count()) +
                       "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(cube.triangle_count()) +
                       "\nproperty list uchar int vertex_indices\nproperty int piece\nend_header\n";
  std::string body;
  for (const Vec3& p : cube.positions) body.append(reinterpret_cast<const char*>(p.data()), 12);
  const std::size_t faces = body.size();
  for (std::size_t t = 0; t < cube.triangle_count(); ++t) {
    body += char(3);
    body.append(reinterpret_cast<const char*>(cube.triangles[t].data()), 12);
    const std::int32_t id = std::int32_t(t / 2);
    body.append(reinterpret_cast<const char*>(&id), 4);
  }
  auto refusal = [&](const std::string& name, const std::string& bytes) -> std::string {
    const std::string path = temp_path(name);
    std::ofstream(path, std::ios::binary) << bytes;
    try {
      const std::vector<std::uint32_t> ids = read_piece_file(path, cube.triangle_count());
      return "read " + std::to_string(*std::max_element(ids.begin(), ids.end()) + 1) + " pieces";
    } catch (const InvalidInput& e) {
      return e.what();
    }
  };
  EXPECT_EQ(refusal("good.ply", header + body), "read 6 pieces");
  // A byte shifted inside the faces (one dropped, one added at the end: the same size).
  std::string shifted = body;
  shifted.erase(faces + 17 * 5 + 3, 1);
  shifted += '\0';
  EXPECT_NE(refusal("shifted.ply", header + shifted).find("shifted.ply: face 5 "), std::string::npos) << refusal("shifted.ply", header + shifted);
  // Bytes past the last element.
  EXPECT_NE(refusal("extra.ply", header + body + "0000").find("extra.ply: 4 bytes follow the last PLY element"), std::string::npos)
      << refusal("extra.ply", header + body + "0000");
  // One vertex fewer declared: its bytes are read as faces.
  std::string fewer = header;
  const std::string declared = "vertex " + std::to_string(cube.vertex_count());
  fewer.replace(fewer.find(declared), declared.size(), "vertex " + std::to_string(cube.vertex_count() - 1));
  EXPECT_NE(refusal("fewer.ply", fewer + body).find("fewer.ply: face 0 "), std::string::npos) << refusal("fewer.ply", fewer + body);
}

TEST(PieceFileTest, RejectsGarbageWrongCountAndMissingFile) {
  const std::string path = temp_path("bad.txt");
  {
    std::ofstream out(path);
    out << "# comment\n0\n1\n\n-1\n";
  }
  EXPECT_THROW(read_piece_file(path, 3), InvalidInput);
  {
    std::ofstream out(path);
    out << "0\n1\n";
  }
  EXPECT_THROW(read_piece_file(path, 3), InvalidInput);
  EXPECT_EQ(read_piece_file(path, 2).size(), 2u);
  {
    std::ofstream out(path);
    out << "0\nabc\n";
  }
  EXPECT_THROW(read_piece_file(path, 2), InvalidInput);
  std::remove(path.c_str());
  EXPECT_THROW(read_piece_file(temp_path("missing.txt"), 2), IoError);
  const std::string ply = temp_path("nopiece.ply");
  {
    std::ofstream out(ply);
    out << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  }
  EXPECT_THROW(read_piece_file(ply, 1), InvalidInput);
  std::remove(ply.c_str());
}

} // namespace
} // namespace hb
