// Exact refinement of haptic-box answers: triangle ids per sample, candidate triangles, the
// edge walk, and how refining boxes travel through compression and box files.
#include "decomposition/auto_decomposition.h"
#include "recipe/bake_recipe.h"
#include "errors.h"
#include "evaluation/comparison.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "scene/bake.h"
#include "store/box_file.h"
#include "surface/surface_triangles.h"
#include "mesh/generators.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cstring>
#include <limits>
#include <filesystem>
#include <fstream>
#include <random>

namespace hb {
namespace {

namespace fs = std::filesystem;
const ForceLaw kRefineLaw{1000.f, 1.f};

BoxScene bake_bumpy(bool refine, int m = 10, int n = 6) {
  static const TriangleMesh mesh = make_bumpy_sphere({1.f, 0.06f, 6, 4});
  BakeOptions options;
  options.params = {m, n};
  options.refine = refine;
  return bake_scene(mesh, {}, options, {"bumpy", 0, mesh.triangle_count(), mesh.bounds().diagonal()});
}

const TriangleMesh& bumpy_mesh() {
  static const TriangleMesh mesh = make_bumpy_sphere({1.f, 0.06f, 6, 4});
  return mesh;
}

TEST(RefinementTest, CoarseBoxesGiveTheExactAnswerWhereTheyRefine) {
  const TriangleMesh& mesh = bumpy_mesh();
  const ExactQuery exact(mesh);
  const auto probes = sample_probes(mesh, 3000);
  const float diagonal = mesh.bounds().diagonal();
  const ComparisonStats blended = compare_queries(bake_bumpy(false), exact, probes, kRefineLaw, diagonal);
  const ComparisonStats refined = compare_queries(bake_bumpy(true), exact, probes, kRefineLaw, diagonal);
  // A coarse box (m 10, n 6) blends visibly; refined, it lands on the exact triangles.
  EXPECT_GT(blended.force_error_median, 1e-3);
  EXPECT_LT(refined.force_error_median, 1e-4);
  EXPECT_LT(refined.force_error_p95, 0.1 * blended.force_error_p95);
  EXPECT_GE(refined.contact_agreement, blended.contact_agreement);
  EXPECT_LT(refined.angle_error_median_deg, 0.05);
}

TEST(RefinementTest, ASceneOfSeveralRefinedBoxesAnswersExactlyAndKeepsItsAgreement) {
  // A torus needs pieces; the scene refines the winning box and rescues misses in the others.
  const TriangleMesh torus = make_torus(1.f, 0.3f, 64, 20);
  const Decomposition d = decompose_auto(torus);
  ASSERT_GT(d.piece_count, 1u);
  BakeOptions options;
  options.params = {10, 6};
  const SourceInfo source{"torus", 0, torus.triangle_count(), torus.bounds().diagonal()};
  const auto lists = seamed_piece_lists(torus, d.piece_of_triangle, {}, BakeOptions{});  // seams in m=32 cells
  const BoxScene blended = bake_scene_from_lists(torus, lists, options, source);
  options.refine = true;
  const BoxScene refined = bake_scene_from_lists(torus, lists, options, source);
  const ExactQuery exact(torus);
  const auto probes = sample_probes(torus, 3000);
  const float diagonal = torus.bounds().diagonal();
  const ComparisonStats b = compare_queries(blended, exact, probes, kRefineLaw, diagonal);
  const ComparisonStats r = compare_queries(refined, exact, probes, kRefineLaw, diagonal);
  EXPECT_LT(r.force_error_median, 1e-4);
  EXPECT_LT(r.force_error_p95, 0.1 * b.force_error_p95);
  EXPECT_GE(r.contact_agreement, b.contact_agreement);
}

TEST(RefinementTest, TheWalkFindsTheCrossedTriangleFromANeighbourOfANeighbour) {
  // A cube whose +Z face (z = 1) is an 8 x 8 grid of quads, two triangles each.
  const TriangleMesh grid = make_cube(Vec3(1.f, 1.f, 1.f), 8);
  const SurfaceTriangles surface(grid);
  // Find a triangle on the +Z face and aim a ray two cells away from it.
  const float origin[3] = {0.31f, -0.27f, 2.f}, dir[3] = {0.f, 0.f, -1.f};
  std::uint32_t crossed = kNoTriangle, start = kNoTriangle;
  for (std::uint32_t t = 0; t < surface.size(); ++t) {
    float s = 0.f;
    Vec3 n;
    bool front = false;
    if (surface.intersect(t, origin, dir, 0.f, s, n, front)) crossed = t;
    const auto& r = surface.records()[t];
    const bool top = r.a[2] > 0.99f && std::fabs(r.e1[2]) < 1e-6f && std::fabs(r.e2[2]) < 1e-6f;
    if (top && std::fabs(r.a[0] - 0.f) < 1e-4f && std::fabs(r.a[1] - 0.f) < 1e-4f) start = t;
  }
  ASSERT_NE(crossed, kNoTriangle);
  ASSERT_NE(start, kNoTriangle);
  float s = 0.f, outside = 0.f;
  Vec3 n;
  bool front = false;
  if (start != crossed) {
    EXPECT_FALSE(surface.intersect(start, origin, dir, 0.f, s, n, front, &outside));
    EXPECT_GT(outside, 0.f);
  }
  ASSERT_TRUE(surface.walk(start, origin, dir, 0.f, 6, s, n, front));
  EXPECT_NEAR(s, 1.f, 1e-5f);
  EXPECT_TRUE(front);
  EXPECT_NEAR(n.z(), 1.f, 1e-4f);
  // Too few steps: no answer rather than a wrong one.
  EXPECT_FALSE(surface.walk(start, origin, dir, 0.f, 0, s, n, front) && start != crossed);
}

// Two faces meeting at a crease, each with vertices of its own (flat shading, triangle soup):
// the walk crosses from one to the other (their edge is joined by position).
TEST(RefinementTest, TheWalkCrossesACreaseBetweenFacesWithVerticesOfTheirOwn) {
  TriangleMesh m;
  // A in the plane z = 0 (outward +z), B in the plane x = 0 (outward -x); they share the edge
  // from (0, 0, 0) to (0, 1, 0) by position only.
  m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1)};
  m.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(-1, 0, 0), Vec3(-1, 0, 0), Vec3(-1, 0, 0)};
  m.triangles = {{0, 1, 2}, {3, 4, 5}};
  const SurfaceTriangles surface(m);
  const std::uint32_t a = surface.slot(0), b = surface.slot(1);
  bool joined = false;
  for (std::uint32_t nb : surface.records()[a].neighbour) joined |= nb == b;
  EXPECT_TRUE(joined);
  // A line meeting A's plane beyond the crease (x = -0.4) and crossing B at (0, 0.2, -0.2).
  const Vec3 dir = Vec3(1.f, 0.f, -0.5f).normalized();
  const float origin[3] = {-1.f, 0.2f, 0.3f}, d[3] = {dir.x(), dir.y(), dir.z()};
  float s = 0.f;
  Vec3 n;
  bool front = false;
  std::uint32_t crossed = kNoTriangle;
  EXPECT_FALSE(surface.intersect(a, origin, d, 0.f, s, n, front));
  ASSERT_TRUE(surface.walk(a, origin, d, 0.f, 2, s, n, front, &crossed));
  EXPECT_EQ(crossed, b);
  EXPECT_TRUE(front);
  EXPECT_NEAR(n.x(), -1.f, 1e-5f);
  EXPECT_NEAR(s, std::sqrt(1.25f), 1e-5f);
}

// One box (m 6, n 4) on a sphere of 20,480 triangles: its cells span many triangles, so the
// samples' hits can lie more bounded walks away from the crossing than a walk takes; the long
// walk from the nearest candidate confirms those contacts (without it: 19 of 3,000 missed).
TEST(RefinementTest, TheLongWalkConfirmsContactsFarFromTheSamplesHits) {
  const TriangleMesh mesh = make_bumpy_sphere({1.f, 0.06f, 6, 5});
  BakeOptions options;
  options.params = {6, 4};
  options.refine = true;
  const BoxScene scene = bake_scene(mesh, {}, options, {"bumpy", 0, mesh.triangle_count(), mesh.bounds().diagonal()});
  const ExactQuery exact(mesh);
  const auto probes = sample_probes(mesh, 3000);
  std::size_t missed[2] = {0, 0};
  for (int on = 0; on < 2; ++on) {
    std::vector<HapticBox> boxes = scene.parts().boxes;
    for (HapticBox& b : boxes) b.set_long_walk_steps(on ? 64 : 0);
    const ComparisonStats r =
        compare_queries(BoxScene(SceneParts(boxes, scene.parts().source)), exact, probes, kRefineLaw, mesh.bounds().diagonal());
    missed[on] = r.missed_contacts;
    if (on) {
      EXPECT_EQ(r.false_contacts, 0u);
    }
  }
  EXPECT_GT(missed[0], 0u);
  EXPECT_LT(missed[1], missed[0] / 4 + 1);
  EXPECT_EQ(scene.parts().boxes[0].long_walk_steps(), 256);  // the default
}

// Bit-for-bit equality of two answers (contact flag, every float, the distance).
void expect_same_answer(const Contact& a, float along_a, const Contact& b, float along_b, std::size_t probe) {
  const auto bits = [](float x) {
    std::uint32_t u;
    std::memcpy(&u, &x, sizeof u);
    return u;
  };
  ASSERT_EQ(a.contact, b.contact) << "probe " << probe;
  if (!a.contact) return;
  ASSERT_EQ(bits(a.depth), bits(b.depth)) << "probe " << probe;
  ASSERT_EQ(bits(along_a), bits(along_b)) << "probe " << probe;
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(bits(a.point[k]), bits(b.point[k])) << "probe " << probe;
    ASSERT_EQ(bits(a.normal[k]), bits(b.normal[k])) << "probe " << probe;
    ASSERT_EQ(bits(a.force[k]), bits(b.force[k])) << "probe " << probe;
  }
}

// Step 7 shades the candidate crossed nearest alone and answers at once when it is accepted;
// the loop that shades every nearer crossing in candidate order gives the same answers, bit
// for bit, on random probes, on probes aimed at mesh vertices (several candidates crossed at
// one point: ties), backwards from inside and with every refinement mode.
TEST(RefinementTest, ShadingTheNearestCrossingFirstGivesTheSameAnswersBitForBit) {
  const TriangleMesh& mesh = bumpy_mesh();
  const BoxScene scene = bake_bumpy(true, 8, 4);
  std::vector<Segment> probes = sample_probes(mesh, 3000);
  ProbeOptions grazing;
  grazing.cone_degrees = 85.f;
  for (const Segment& s : sample_probes(mesh, 2000, grazing)) probes.push_back(s);
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::size_t> vertex(0, mesh.positions.size() - 1);
  std::normal_distribution<float> gauss;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 p = mesh.positions[vertex(rng)];
    const Vec3 d = Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    probes.push_back({p - 0.2f * d, p + 0.05f * d});  // through a vertex
    probes.push_back({p + 0.05f * d, p - 0.2f * d});  // from inside out
  }
  for (const HapticBox& fast : scene.parts().boxes) {
    ASSERT_TRUE(fast.nearest_first());
    HapticBox loop = fast;
    loop.set_nearest_first(false);
    std::size_t contacts = 0;
    for (std::size_t i = 0; i < probes.size(); ++i) {
      for (Refine mode : {Refine::all, Refine::misses}) {
        Contact a, b;
        float along_a = 0.f, along_b = 0.f;
        bool refined_a = false, refined_b = false;
        std::uint32_t tri_a = 0, tri_b = 1;
        fast.query_into(probes[i], kRefineLaw, a, along_a, mode, &refined_a, &tri_a);
        loop.query_into(probes[i], kRefineLaw, b, along_b, mode, &refined_b, &tri_b);
        expect_same_answer(a, along_a, b, along_b, i);
        ASSERT_EQ(refined_a, refined_b) << "probe " << i;
        ASSERT_EQ(tri_a, tri_b) << "probe " << i;
        contacts += a.contact ? 1 : 0;
      }
      Contact a, b;
      float along_a = 0.f, along_b = 0.f;
      std::uint32_t tri_a = 0, tri_b = 1;
      fast.query_refined(probes[i], kRefineLaw, a, along_a, &tri_a);
      loop.query_refined(probes[i], kRefineLaw, b, along_b, &tri_b);
      expect_same_answer(a, along_a, b, along_b, i);
      ASSERT_EQ(tri_a, tri_b) << "probe " << i;
    }
    EXPECT_GT(contacts, probes.size() / 4);  // the probes do reach the surface
  }
}

// The contact rule of a refined answer is exact's: a front-face crossing on the segment, even
// where the shaded normal faces along the line (a thin sheet's rim, a tilted stylus).
TEST(RefinementTest, ARefinedContactIsAFrontFaceCrossingWhateverTheShadedNormal) {
  TriangleMesh m;
  // A square in z = 0 facing +z; the normals of its +x corners tilted 85 degrees towards +x
  // (samples from the -x half see a surface facing them, so the box holds candidates there).
  const Vec3 up(0.f, 0.f, 1.f), tilted(std::sin(1.48f), 0.f, std::cos(1.48f));
  m.positions = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
  m.normals = {up, tilted, tilted, up};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  BakeOptions options;
  options.params = {8, 4};
  options.refine = true;
  const BoxScene scene = bake_scene(m, {}, options, {"square", 0, m.triangle_count(), m.bounds().diagonal()});
  const ExactQuery exact(m);
  // 30 degrees from -z towards +x: l . n_shaded > 0 at p, l . n_geometric < 0. Exact has the
  // contact (with no force under the normal depth law); before, the box had none.
  const Vec3 l(0.5f, 0.f, -0.866f);
  const Vec3 p(0.6f, 0.2f, 0.f);
  const Segment probe{p - 0.5f * l, p + 0.1f * l};
  const Contact e = exact.query(probe, kRefineLaw), b = scene.query(probe, kRefineLaw);
  ASSERT_TRUE(e.contact);
  ASSERT_TRUE(b.contact);
  EXPECT_NEAR(b.depth, e.depth, 1e-5f);
  EXPECT_NEAR((b.force - e.force).norm(), 0.f, 1e-4f);
}

TEST(RefinementTest, ATriangleWithHugeEdgesStillGivesAUnitNormal) {
  // Edges of 1e13: the geometric normal's squared length overflows float (a damaged box file
  // had such records; the fuzzer found the normal coming out zero).
  TriangleMesh m;
  m.positions = {Vec3(-1e13f, -1e13f, 0), Vec3(1e13f, -1e13f, 0), Vec3(0, 1e13f, 0)};
  m.normals = {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 0, -1)};  // shading that cancels out
  m.triangles = {{0, 1, 2}};
  const SurfaceTriangles surface(m);
  const float o[3] = {0.f, 0.f, 5.f}, d[3] = {0.f, 0.f, -1.f};
  float s = 0.f;
  Vec3 normal;
  bool front = false;
  ASSERT_TRUE(surface.intersect(0, o, d, 0.f, s, normal, front));
  EXPECT_FLOAT_EQ(s, 5.f);
  EXPECT_TRUE(front);
  EXPECT_NEAR(normal.norm(), 1.f, 1e-5f);
  EXPECT_NEAR(normal.z(), 1.f, 1e-5f);
}

TEST(RefinementTest, CompressionKeepsTheRefinement) {
  const BoxScene raw = bake_bumpy(true);
  CodecOptions codec;
  codec.codec = CodecId::block;
  const BoxScene block(compressed(raw, codec));
  ASSERT_TRUE(block.parts().boxes[0].refines());
  const auto probes = sample_probes(bumpy_mesh(), 500);
  int refined_equal = 0, contacts = 0;
  for (const Segment& s : probes) {
    const Contact a = raw.query(s, kRefineLaw), b = block.query(s, kRefineLaw);
    if (!a.contact || !b.contact) continue;
    ++contacts;
    refined_equal += std::fabs(a.depth - b.depth) < 1e-5f;
  }
  // Both land on the same exact triangles almost everywhere.
  EXPECT_GT(refined_equal, contacts * 95 / 100);
}

TEST(RefinementTest, IdsAreSixteenBitWhenThePieceSpansFewSlots) {
  std::vector<std::uint32_t> ids = {70000u, kNoTriangle, 70010u, 135000u};
  std::shared_ptr<const void> owner;
  TriangleIds narrow = pack_triangle_ids(ids, owner);
  EXPECT_EQ(narrow.width, 2);
  for (std::size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(narrow.at(k), ids[k]) << k;
  ids.push_back(70000u + 0xffffu);
  const TriangleIds wide = pack_triangle_ids(ids, owner);
  EXPECT_EQ(wide.width, 4);
  for (std::size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(wide.at(k), ids[k]) << k;
}

TEST(RefinementTest, WrongIdCountOrUnknownTriangleIsInvalidInput) {
  BoxScene scene = bake_bumpy(true, 4, 3);
  HapticBox box = scene.parts().boxes[0];
  std::vector<std::uint32_t> ids(box.params().sample_count() - 1, kNoTriangle);
  EXPECT_THROW(box.attach_surface({ids.data(), 4, 0}, ids.size(), nullptr, box.surface()), InvalidInput);
  EXPECT_THROW(box.attach_surface({ids.data(), 3, 0}, ids.size() + 1, nullptr, box.surface()), InvalidInput);
  ids.assign(box.params().sample_count(), kNoTriangle);
  ids[7] = std::uint32_t(box.surface()->size());
  try {
    box.attach_surface({ids.data(), 4, 0}, ids.size(), nullptr, box.surface());
    FAIL() << "no error for an unknown triangle";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("sample 7"), std::string::npos) << e.what();
  }
}

class RefinedBoxFileTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hb_refined_box_file_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    scene_ = bake_bumpy(true, 6, 4);
    path_ = (dir_ / "bumpy.hbox").string();
    save_box_file(scene_, path_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  BoxScene scene_;
  std::string path_;
};

TEST_F(RefinedBoxFileTest, RoundTripKeepsTheRefinementAndTheAnswers) {
  for (const bool huge : {false, true}) {
    LoadOptions options;
    options.verify = true;
    options.huge_pages = huge;
    const BoxScene loaded = load_box_file(path_, options);
    ASSERT_TRUE(loaded.parts().boxes[0].refines());
    EXPECT_EQ(loaded.parts().boxes[0].surface()->size(), bumpy_mesh().triangle_count());
    for (const Segment& s : sample_probes(bumpy_mesh(), 300)) {
      const Contact a = scene_.query(s, kRefineLaw), b = loaded.query(s, kRefineLaw);
      ASSERT_EQ(a.contact, b.contact);
      EXPECT_EQ(a.depth, b.depth);
      EXPECT_EQ(a.normal, b.normal);
    }
  }
}

TEST_F(RefinedBoxFileTest, CorruptTriangleIdsAreCaughtByVerifyAndNeverReadOutOfBounds) {
  std::vector<char> data;
  {
    std::ifstream in(path_, std::ios::binary);
    data.assign(std::istreambuf_iterator<char>(in), {});
  }
  // The ids follow the table: overwrite every id word after the table with huge values.
  const HapticBox& box = scene_.parts().boxes[0];
  const std::size_t id_bytes = box.triangle_id_bytes();
  const std::size_t surface_bytes = box.surface()->bytes();
  const std::size_t ids_at = data.size() - surface_bytes - id_bytes;  // both end 64-aligned
  // Values beyond every slot whatever the file offset (16-bit ids: base + offset past the
  // surface's count; a pattern from the offset alone could land inside it).
  ASSERT_LT(box.surface()->size() + box.triangle_ids().base, 0xfb00u);
  for (std::size_t k = ids_at; k + 4 <= ids_at + id_bytes; k += 4) {
    const std::uint32_t bad = box.triangle_ids().width == 2
                                  ? (0xfff0u - std::uint32_t((k / 2) & 1023u)) * 0x10001u
                                  : 0xfffffff0u - std::uint32_t(k);
    std::memcpy(&data[k], &bad, 4);
  }
  const std::string bad_path = (dir_ / "bad.hbox").string();
  std::ofstream(bad_path, std::ios::binary).write(data.data(), std::streamsize(data.size()));
  try {
    load_box_file(bad_path, LoadOptions{true});
    FAIL() << "no error for corrupt ids";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("triangle ids"), std::string::npos) << e.what();
  }
  // Lazily opened, the corrupt ids are bounds-checked: no refinement confirms anything, so the
  // scene answers no contact (an unconfirmed blend never answers).
  const BoxScene lazy = load_box_file(bad_path);
  for (const Segment& s : sample_probes(bumpy_mesh(), 50)) EXPECT_FALSE(lazy.query(s, kRefineLaw).contact);
}


// first_crossing() keeps plane_hits()' lane tests in the registers; it must still pick the
// crossing a plain loop over intersect() picks: the same parameter bits, the same triangle
// (the first listed on a tie), the same facing, including ids out of range and lists whose
// length is not a multiple of four.
TEST(RefinementTest, FirstCrossingPicksTheNearestCrossingOfAPlainIntersectLoopBitForBit) {
  const TriangleMesh& mesh = bumpy_mesh();
  const SurfaceTriangles surface(mesh);
  std::vector<Segment> probes = sample_probes(mesh, 3000);
  std::mt19937 rng(11);
  std::uniform_int_distribution<std::uint32_t> slot(0, std::uint32_t(surface.size()) + 3);
  std::uniform_int_distribution<int> length(1, 37);
  std::uniform_real_distribution<float> range(0.f, 1.f);
  std::size_t found = 0;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Segment& seg = probes[i];
    const float o[3] = {seg.start.x(), seg.start.y(), seg.start.z()};
    const float d[3] = {seg.end.x() - o[0], seg.end.y() - o[1], seg.end.z() - o[2]};
    // The triangles near the segment (so that some lists are crossed), some far, some twice,
    // some out of range.
    std::vector<std::uint32_t> ids;
    const int n = length(rng);
    for (int k = 0; k < n; ++k) ids.push_back(slot(rng));
    for (std::uint32_t t = 0; t < surface.size() && ids.size() < 64; ++t) {
      float s = 0.f, outside = 0.f;
      Vec3 normal;
      bool front = false;
      surface.intersect(t, o, d, -1.f, s, normal, front, &outside);
      if (outside < 0.05f) ids.push_back(t);
    }
    if (i % 3 == 0 && !ids.empty()) ids.push_back(ids.front());
    std::shuffle(ids.begin(), ids.end(), rng);
    const float s_min = i % 4 == 0 ? 0.1f * range(rng) : 0.f, s_max = i % 5 == 0 ? range(rng) : 1.f;
    float want = std::numeric_limits<float>::infinity();
    std::uint32_t want_id = kNoTriangle;
    bool want_front = false;
    for (std::uint32_t t : ids) {
      float s = 0.f;
      Vec3 normal;
      bool front = false;
      if (!surface.intersect(t, o, d, s_min, s, normal, front) || !(s <= s_max) || !(s < want)) continue;
      want = s, want_id = t, want_front = front;
    }
    float s = 0.f;
    bool front = false;
    std::uint32_t id = kNoTriangle;
    const bool hit = surface.first_crossing(ids.data(), ids.size(), o, d, s_min, s_max, s, front, id);
    ASSERT_EQ(hit, want_id != kNoTriangle) << "probe " << i;
    if (!hit) continue;
    ++found;
    ASSERT_EQ(id, want_id) << "probe " << i;
    ASSERT_EQ(std::memcmp(&s, &want, sizeof s), 0) << "probe " << i;
    ASSERT_EQ(front, want_front) << "probe " << i;
  }
  EXPECT_GT(found, probes.size() / 4);
}

} // namespace
} // namespace hb
