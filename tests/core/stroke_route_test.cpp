// The stroke route (SceneParts::stroke, recipe/stroke_route.h): a probe's successive
// queries answered by exact Embree over the full mesh while the queries without a state keep
// the surface cells; kept through copies and box files; chosen by timing at bake time.
#include "contact/workspace.h"
#include "errors.h"
#include "evaluation/probe_sampling.h"
#include "exact/exact_query.h"
#include "store/box_file.h"
#include "recipe/route_rule.h"
#include "recipe/stroke_route.h"
#include "scratch_dir_test.h"
#include "two_spheres.h"
#include <gtest/gtest.h>
#include <xxhash.h>
#include <cstring>
#include <fstream>
#include <iterator>

namespace hb {
namespace {

BoxScene with_stroke_mesh(const BoxScene& scene, const TriangleMesh& mesh) {
  SceneParts parts = scene.parts();
  parts.stroke = make_stroke_route(mesh);
  return BoxScene(std::move(parts));
}

// What a servo loop's cache priming (BoxScene::prime) reads: the stroke route's answer.
Contact prime_answer(const BoxScene& scene, const Segment& s, const ForceLaw& law) {
  return strokes_by_full_mesh(scene) ? scene.parts().stroke->exact->query(s, law) : scene.query(s, law);
}

bool same_bits(const Contact& a, const Contact& b) {
  return a.contact == b.contact && a.depth == b.depth && a.force == b.force && a.point == b.point;
}

class StrokeRouteTest : public test::ScratchDirTest {
protected:
  StrokeRouteTest() : ScratchDirTest("hb_stroke_route_") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    cells_ = BoxScene(without_triangle_ids(test::refined_two_spheres(two_)));
    law_ = make_workspace(two_.mesh.bounds().diagonal()).law();
    strokes_ = sample_strokes(two_.mesh, 8, 100, 0.02f);
  }
  std::vector<char> read(const std::string& path) const {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  std::string write_bytes(const std::string& name, const std::vector<char>& data) const {
    return write(name, std::string(data.begin(), data.end()));
  }

  const test::TwoSpheres two_ = test::two_spheres(3.f);
  BoxScene cells_;
  ForceLaw law_;
  std::vector<Segment> strokes_;
};

TEST_F(StrokeRouteTest, AProbesTicksAreExactEmbreeOverTheFullMeshAndQueriesWithoutAStateKeepTheCells) {
  ASSERT_EQ(cells_.route(), SceneRoute::cells);
  BoxScene scene = cells_;
  scene = with_stroke_mesh(scene, two_.mesh);
  EXPECT_EQ(scene.stroke_route(), SceneRoute::embree);
  EXPECT_EQ(scene.route(), SceneRoute::cells);
  EXPECT_GT(scene.bytes().embree, cells_.bytes().embree);
  const ExactQuery exact(two_.mesh);
  SceneQueryState state;
  std::size_t contacts = 0, as_exact = 0, as_cells = 0, primed_as_exact = 0, primed_as_cells = 0;
  for (const Segment& s : strokes_) {
    const Contact ticked = scene.query(s, law_, state), e = exact.query(s, law_);
    contacts += e.contact ? 1 : 0;
    as_exact += same_bits(ticked, e) ? 1 : 0;
    as_cells += same_bits(scene.query(s, law_), cells_.query(s, law_)) ? 1 : 0;
    // A servo loop's cache priming (SceneProbe::prime) asks what the next tick reads.
    primed_as_exact += same_bits(prime_answer(scene, s, law_), e) ? 1 : 0;
    primed_as_cells += same_bits(prime_answer(cells_, s, law_), cells_.query(s, law_)) ? 1 : 0;
  }
  EXPECT_EQ(primed_as_exact, strokes_.size());
  EXPECT_EQ(primed_as_cells, strokes_.size());
  EXPECT_GT(contacts, strokes_.size() / 4);
  EXPECT_EQ(as_exact, strokes_.size());
  EXPECT_EQ(as_cells, strokes_.size());
  // Copies keep it; parts without it drop it; other routes ignore it.
  const BoxScene copy = scene;
  EXPECT_NE(stroke_mesh(copy), nullptr);
  SceneParts without = scene.parts();
  without.stroke.reset();
  EXPECT_EQ(BoxScene(without).stroke_route(), SceneRoute::cells);
  const BoxScene embree = with_route(scene, SceneRoute::embree);
  EXPECT_EQ(embree.stroke_route(), SceneRoute::embree);
  BoxScene boxes = with_route(test::refined_two_spheres(two_), SceneRoute::boxes);
  boxes = with_stroke_mesh(boxes, two_.mesh);
  EXPECT_EQ(boxes.stroke_route(), SceneRoute::boxes);
}

TEST_F(StrokeRouteTest, AMeshWithoutTrianglesOrNormalsIsRefusedNamingWhy) {
  BoxScene scene = cells_;
  TriangleMesh no_normals = two_.mesh;
  no_normals.normals.clear();
  try {
    scene = with_stroke_mesh(scene, no_normals);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("vertex normals"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scene = with_stroke_mesh(scene, TriangleMesh{}), InvalidInput);
  EXPECT_EQ(stroke_mesh(scene), nullptr);
}

TEST_F(StrokeRouteTest, ABoxFileKeepsTheFullMeshAndAFileWithoutOneIsWrittenAsBefore) {
  BoxScene scene = cells_;
  scene = with_stroke_mesh(scene, two_.mesh);
  const std::string with = (dir_ / "with.hbox").string(), without = (dir_ / "without.hbox").string();
  save_box_file(scene, with);
  save_box_file(cells_, without);
  std::uint32_t version = 0;
  std::memcpy(&version, read(with).data() + 8, 4);
  EXPECT_EQ(version, 9u);
  std::memcpy(&version, read(without).data() + 8, 4);
  EXPECT_EQ(version, 7u);
  const BoxScene loaded = load_box_file(with, LoadOptions{true});
  ASSERT_NE(stroke_mesh(loaded), nullptr);
  EXPECT_EQ(stroke_mesh(loaded)->triangle_count(), two_.mesh.triangle_count());
  EXPECT_EQ(stroke_mesh(load_box_file(without)), nullptr);
  SceneQueryState a, b;
  std::size_t same = 0;
  for (const Segment& s : strokes_) same += same_bits(loaded.query(s, law_, a), scene.query(s, law_, b)) ? 1 : 0;
  EXPECT_EQ(same, strokes_.size());
}

TEST_F(StrokeRouteTest, AStrokeMeshNamingAVertexItDoesNotHoldIsRefusedAtLoad) {
  BoxScene scene = cells_;
  scene = with_stroke_mesh(scene, two_.mesh);
  const std::string path = (dir_ / "good.hbox").string();
  save_box_file(scene, path);
  std::vector<char> data = read(path);
  // The stroke mesh is the file's last section; its (offset, bytes, hash) end the header,
  // just before the header's own hash.
  const std::uint64_t bytes = 8 + two_.mesh.positions.size() * 24 + two_.mesh.triangle_count() * 12;
  const std::uint64_t offset = data.size() - bytes;
  std::size_t field = 0;
  for (std::size_t p = 0; p + 16 <= offset; ++p)
    if (std::memcmp(&data[p], &offset, 8) == 0 && std::memcmp(&data[p + 8], &bytes, 8) == 0) field = p;
  ASSERT_GT(field, 0u);
  const std::uint32_t far = 1u << 30;
  std::memcpy(&data[data.size() - 8], &far, 4);  // the last triangle's second index
  const std::uint64_t section_hash = XXH3_64bits(&data[offset], bytes);
  std::memcpy(&data[field + 16], &section_hash, 8);
  const std::uint64_t header_hash = XXH3_64bits(data.data(), field + 24);
  std::memcpy(&data[field + 24], &header_hash, 8);
  const std::string bad = write_bytes("bad.hbox", data);
  try {
    load_box_file(bad);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("stroke mesh triangle"), std::string::npos) << e.what();
  }
  // Unsigned, the same change is a checksum mismatch.
  std::vector<char> unsigned_change = read(path);
  unsigned_change[unsigned_change.size() - 8] = 0x7f;
  try {
    load_box_file(write_bytes("unsigned.hbox", unsigned_change));
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("stroke mesh checksum"), std::string::npos) << e.what();
  }
}

TEST_F(StrokeRouteTest, TheBakeKeepsTheCellsForStrokesOnlyWhereTheyAreClearlyFaster) {
  BoxScene scene = cells_;
  BudgetReport report;
  choose_stroke_route(scene, two_.mesh, law_, 7, report);
  ASSERT_GT(report.stroke_cells_ns, 0.0);
  ASSERT_GT(report.stroke_embree_ns, 0.0);
  EXPECT_EQ(stroke_mesh(scene) != nullptr, report.stroke_answer == Answerer::embree);
  EXPECT_EQ(report.stroke_answer == Answerer::cells,
            clearly_faster_than_embree(report.stroke_cells_ns, report.stroke_embree_ns));
  // The report carries the choice through its file form; a scene the cells do not answer is
  // left as it is, untimed.
  report.present = true;
  const BudgetReport back = BudgetReport::parse(report.serialize());
  EXPECT_EQ(back.stroke_answer, report.stroke_answer);
  EXPECT_DOUBLE_EQ(back.stroke_cells_ns, report.stroke_cells_ns);
  EXPECT_EQ(back.without_times().stroke_embree_ns, 0.0);
  EXPECT_THROW(BudgetReport::parse("stroke_answer=boxes\n"), InvalidInput);
  BoxScene embree = with_route(cells_, SceneRoute::embree);
  BudgetReport untouched;
  choose_stroke_route(embree, two_.mesh, law_, 7, untouched);
  EXPECT_EQ(untouched.stroke_answer, Answerer::none);
  EXPECT_EQ(stroke_mesh(embree), nullptr);
}

} // namespace
} // namespace hb
