#include "evaluation/probe_sampling.h"
#include "scene/bake.h"
#include "mesh/generators.h"
#include "report.h"
#include "test_meshes.h"
#include "vtkHapticBoxReferenceQueries.h"
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

std::string ReadText(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct ReportFixture : ::testing::Test {
  hb::TriangleMesh mesh = hb::make_ellipsoid(hb::Vec3(1.f, 0.7f, 0.5f), 3);
  hb::BoxScene scene;
  std::string dir = hb::test::ScratchPath("report");
  void SetUp() override {
    hb::BakeOptions bake;
    bake.params.m = 8;
    bake.params.n = 4;
    scene = hb::bake_scene(mesh, {}, bake, {"ellipsoid", 0, mesh.triangle_count(), mesh.bounds().diagonal()});
  }
  void TearDown() override { std::filesystem::remove_all(dir); }
};

} // namespace

TEST_F(ReportFixture, JsonCarriesTheFiguresEvalPrintsForTheSameSeed) {
  const vtkHapticBoxReferenceQueries refs(mesh);
  hb::ReportOptions options;
  options.samples = 2000;
  options.probes.seed = 42;
  options.timing_rounds = 1;
  options.sweep_configs = {{4, 4, "none"}};
  hb::ReportData data = hb::compute_report(mesh, {}, scene, 0.5, refs.References(), options);
  data.product_version = "test";
  data.mesh_path = "ellipsoid";
  hb::write_report(data, dir);

  // What `hapticbox eval` computes: compare_queries on sample_probes(mesh, samples, seed).
  const auto probes = hb::sample_probes(mesh, 2000, options.probes);
  const hb::ComparisonStats eval = hb::compare_queries(scene, refs.Exact(), probes, hb::make_workspace(mesh.bounds().diagonal()).law(),
                                                       mesh.bounds().diagonal());

  const nlohmann::json j = nlohmann::json::parse(ReadText(std::filesystem::path(dir) / "summary.json"));
  EXPECT_EQ(j["eval"]["samples"].get<std::size_t>(), eval.samples);
  EXPECT_EQ(j["eval"]["seed"].get<std::uint64_t>(), 42u);
  EXPECT_EQ(j["eval"]["exact_contacts"].get<std::size_t>(), eval.exact_contacts);
  EXPECT_DOUBLE_EQ(j["eval"]["contact_agreement"].get<double>(), eval.contact_agreement);
  EXPECT_DOUBLE_EQ(j["eval"]["force_error_median"].get<double>(), eval.force_error_median);
  EXPECT_DOUBLE_EQ(j["eval"]["force_error_p95"].get<double>(), eval.force_error_p95);
  EXPECT_DOUBLE_EQ(j["eval"]["angle_error_median_deg"].get<double>(), eval.angle_error_median_deg);
  EXPECT_EQ(j["product"]["version"], "test");
  EXPECT_EQ(j["box"]["m"], 8);
  EXPECT_EQ(j["model"]["triangles"].get<std::size_t>(), mesh.triangle_count());
  EXPECT_TRUE(j["timing"].contains("exact_embree_ns"));
  EXPECT_TRUE(j["timing"].contains("vtk_static_cell_locator_ns"));
  // References, one sweep configuration and the box itself; at least one on the front.
  ASSERT_EQ(j["sweep"].size(), 4u);
  bool any_pareto = false;
  for (const auto& row : j["sweep"]) any_pareto = any_pareto || row["pareto"].get<bool>();
  EXPECT_TRUE(any_pareto);
  EXPECT_EQ(j["error_field"]["points"].get<std::size_t>(), mesh.vertex_count());
  EXPECT_TRUE(j["tolerances"].contains("pass"));

  // samples.csv: a header and one row per probe.
  std::ifstream csv(std::filesystem::path(dir) / "samples.csv");
  std::size_t lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 2001u);
}

TEST_F(ReportFixture, HtmlEmbedsItsChartsAndLoadsNoExternalFile) {
  const vtkHapticBoxReferenceQueries refs(mesh);
  hb::ReportOptions options;
  options.samples = 500;
  options.timing_rounds = 1;
  hb::ReportData data = hb::compute_report(mesh, {}, scene, 0.0, refs.References(), options);
  data.error_field_note = "no display in this test";
  hb::write_report(data, dir);
  const std::string html = ReadText(std::filesystem::path(dir) / "report.html");
  ASSERT_FALSE(html.empty());
  // Two charts (speed-vs-accuracy, histogram) as SVG data URIs (vector: sharp when printed);
  // "PHN2Zy" / "PD94bW" are base64 of "<svg" / "<?xml".
  // (Plain searches: std::regex recurses per character and overflows on megabyte strings.)
  auto count = [&html](const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = html.find(what); at != std::string::npos; at = html.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("src=\"data:image/svg+xml;base64,PD94bW") + count("src=\"data:image/svg+xml;base64,PHN2Zy"), 3u);
  // Nothing else is loaded: every src is a data URI, no stylesheet or script links.
  EXPECT_EQ(count("src=\""), count("src=\"data:"));
  EXPECT_EQ(count("href="), 0u);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("no display in this test"), std::string::npos);
  EXPECT_NE(html.find("vtk_static_cell_locator"), std::string::npos);
}

TEST_F(ReportFixture, CompressionCurveIsEmbeddedWhenGiven) {
  const vtkHapticBoxReferenceQueries refs(mesh);
  hb::ReportOptions options;
  options.samples = 300;
  options.timing_rounds = 1;
  options.error_field_probes_per_vertex = 0;
  hb::ReportData data = hb::compute_report(mesh, {}, scene, 0.0, refs.References(), options);
  data.compression_curve = {{2.0, 0.001}, {5.0, 0.004}, {9.0, 0.02}};
  hb::write_report(data, dir);
  const std::string html = ReadText(std::filesystem::path(dir) / "report.html");
  std::size_t n = 0;
  for (std::size_t at = html.find("data:image/svg+xml;base64,"); at != std::string::npos;
       at = html.find("data:image/svg+xml;base64,", at + 1))
    ++n;
  EXPECT_EQ(n, 4u);
  const nlohmann::json j = nlohmann::json::parse(ReadText(std::filesystem::path(dir) / "summary.json"));
  EXPECT_EQ(j["compression_curve"].size(), 3u);
  EXPECT_EQ(j["error_field"]["points"], 0);
}

// A scene whose strokes exact Embree over the full mesh answers (the bake's stroke route):
// the report says so beside the route its figures were measured on, in every output.
TEST_F(ReportFixture, AStrokeRouteIsNamedBesideTheRouteTheFiguresWereMeasuredOn) {
  hb::TriangleMesh halves = mesh;
  std::vector<std::uint32_t> piece(halves.triangle_count(), 0);
  for (std::size_t t = 0; t < piece.size(); ++t)
    if (halves.positions[halves.triangles[t][0]].x() > 0.f) piece[t] = 1;
  hb::BakeOptions bake;
  bake.params = {8, 4};
  bake.refine = true;
  const hb::BoxScene plain_cells(hb::without_triangle_ids(
      hb::bake_scene(halves, piece, bake, {"ellipsoid", 0, halves.triangle_count(), halves.bounds().diagonal()})));
  ASSERT_EQ(plain_cells.route(), hb::SceneRoute::cells);
  hb::SceneParts parts = plain_cells.parts();
  parts.stroke = hb::make_stroke_route(halves);
  const hb::BoxScene cells(std::move(parts));
  const vtkHapticBoxReferenceQueries refs(halves);
  hb::ReportOptions options;
  options.samples = 300;
  options.timing_rounds = 1;
  options.error_field_probes_per_vertex = 0;
  hb::ReportData data = hb::compute_report(halves, {}, cells, 0.0, refs.References(), options);
  hb::write_report(data, dir);
  const nlohmann::json j = nlohmann::json::parse(ReadText(std::filesystem::path(dir) / "summary.json"));
  EXPECT_EQ(j["box"]["route"], "cells");
  EXPECT_EQ(j["box"]["stroke_route"], "embree");
  EXPECT_NE(ReadText(std::filesystem::path(dir) / "summary.txt").find("along strokes"), std::string::npos);
  EXPECT_NE(ReadText(std::filesystem::path(dir) / "report.html").find("exact Embree over the full mesh"), std::string::npos);
  // Without it, the stroke route is the route.
  hb::ReportData plain = hb::compute_report(halves, {}, plain_cells, 0.0, refs.References(), options);
  EXPECT_EQ(plain.stroke_route, hb::Answerer::cells);
}
