// The OFF reader parses chunks of about 1 MB in parallel and triangulates and analyses edges
// in parallel: these tests pin its output to known content (element for element, in order)
// on small files with every lexical oddity the format allows, and on files big enough to
// span many chunks, triangulation blocks and vertex ranges, including the line numbers and
// the first-error rule of its messages.
#include "mesh/mesh_io.h"

#include "errors.h"

#include "scratch_dir_test.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace hb {
namespace {

namespace fs = std::filesystem;

class OffReaderTest : public test::ScratchDirTest {
protected:
  OffReaderTest() : ScratchDirTest("hb_off_reader_") {}
  /// The message read_mesh throws for `path` (empty when it reads).
  static std::string error_of(const std::string& path) {
    try {
      read_mesh(path);
    } catch (const Error& e) {
      return e.what();
    }
    return {};
  }
};

/// A planar grid of nx x ny vertices written as OFF with the oddities a reader meets in the
/// field, and the mesh it must give (positions, triangles in order, counts).
struct GridOff {
  std::string text;
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  std::size_t faces = 0, polygons = 0, degenerate = 0, short_faces = 0;
};

std::string number(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

GridOff grid_off(int nx, int ny) {
  GridOff g;
  std::vector<std::string> face_lines;
  const auto id = [&](int i, int j) { return std::uint32_t(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const std::uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      const std::size_t f = face_lines.size();
      if (f % 1000 == 999) {  // a repeated corner: dropped as degenerate
        face_lines.push_back("3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(a));
        ++g.degenerate;
      } else if (f % 777 == 5) {  // two corners: skipped, counted
        face_lines.push_back("2 " + std::to_string(a) + " " + std::to_string(b));
        ++g.short_faces;
      } else if (f % 3 == 0) {  // a quad with a colour after it: fan-triangulated
        face_lines.push_back("4\t" + std::to_string(a) + "  " + std::to_string(b) + " " + std::to_string(c) + " " +
                             std::to_string(d) + " 0.5 0.5 0.5 1");
        g.triangles.push_back({a, b, c});
        g.triangles.push_back({a, c, d});
        ++g.polygons;
      } else {
        face_lines.push_back("3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c));
        face_lines.push_back("3 " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d));
        g.triangles.push_back({a, b, c});
        g.triangles.push_back({a, c, d});
      }
    }
  g.faces = face_lines.size();
  g.text = "# a grid\nOFF\n\n" + std::to_string(nx * ny) + " " + std::to_string(g.faces) + " 0\n";
  std::size_t line = 0;
  const auto odd_line_end = [&] {  // comments, blank lines, CRLF and stray spaces now and then
    ++line;
    if (line % 501 == 0) return std::string("  # a comment on its own line\n\n");
    if (line % 97 == 0) return std::string("\r\n");
    if (line % 89 == 0) return std::string(" \t# trailing comment\n");
    return std::string("\n");
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = 0.25 * i, y = -0.125 * j, z = 0.1 * ((i * 7 + j * 3) % 11);
      g.positions.emplace_back(float(x), float(y), float(z));
      g.text += std::string(j % 4 == 0 ? "+" : "") + number(x) + (i % 5 == 0 ? "\t" : " ") + number(y) + " " + number(z) +
                (i % 13 == 0 ? " 1 0 0" : "") + odd_line_end();
    }
  for (const std::string& f : face_lines) g.text += (line % 7 == 0 ? "   " : "") + f + odd_line_end();
  g.text += "# anything after the faces is not read\nnot a face\n";
  return g;
}

// --- known content ---------------------------------------------------------------------

TEST_F(OffReaderTest, SmallFileWithEveryOddityGivesKnownMesh) {
  // Comments (whole line and trailing), blank lines, CRLF, tabs, form feeds, '+' signs,
  // extra vertex values, a colour after the indices, a quad, a pentagon, a 2-corner face,
  // a degenerate triangle, counts on their own line, lines after the faces.
  const std::string off =
      "# made by hand\r\n"
      "OFF # keyword\r\n"
      "\r\n"
      "  7\t6   0  \r\n"
      "0 0 0\r\n"
      "1\t0 0   # x axis\r\n"
      "+1 1 0 0.1 0.2 0.3\n"
      "\f0 1 0\v\n"
      "# between vertices\n"
      "2 0 0\n"
      "2 1 1e0\n"
      "0.5 2 -0\n"
      "4 0 1 2 3 255 0 0\n"
      "5 1 4 5 6 3\n"
      "3 0 1 2\n"
      "2 0 1\n"
      "3 1 1 2\n"
      "   3   0 2 3\t\n"
      "garbage after the declared faces\n";
  MeshReadReport report;
  const TriangleMesh m = read_mesh(write("odd.off", off), &report);
  const std::vector<Vec3> positions{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 1}, {0.5f, 2, 0}};
  const std::vector<Triangle> triangles{{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 6}, {1, 6, 3}, {0, 1, 2}, {0, 2, 3}};
  EXPECT_EQ(m.positions, positions);
  EXPECT_EQ(m.triangles, triangles);
  EXPECT_EQ(m.normals.size(), positions.size());
  EXPECT_EQ(report.input_vertices, 7u);
  EXPECT_EQ(report.input_faces, 6u);
  EXPECT_EQ(report.polygons_triangulated, 2u);
  EXPECT_EQ(report.degenerate_dropped, 1u);
  EXPECT_EQ(report.faces_rejected, 1u);
  EXPECT_TRUE(report.non_manifold);  // edges 0-1, 0-2, 1-2 and 2-3 are listed more than twice
}

TEST_F(OffReaderTest, ManyChunksGiveTheMeshElementForElement) {
  // About 5 MB: many 1 MB chunks, more than one triangulation block (65,536 faces) and
  // several vertex ranges of the edge analysis.
  const GridOff g = grid_off(500, 420);
  ASSERT_GT(g.text.size(), std::size_t(4) << 20);
  MeshReadReport report;
  const TriangleMesh m = read_mesh(write("grid.off", g.text), &report);
  ASSERT_EQ(m.positions.size(), g.positions.size());
  EXPECT_TRUE(m.positions == g.positions);
  ASSERT_EQ(m.triangles.size(), g.triangles.size());
  EXPECT_TRUE(m.triangles == g.triangles);
  EXPECT_EQ(report.input_vertices, g.positions.size());
  EXPECT_EQ(report.input_faces, g.faces);
  EXPECT_EQ(report.polygons_triangulated, g.polygons);
  EXPECT_EQ(report.degenerate_dropped, g.degenerate);
  EXPECT_EQ(report.faces_rejected, g.short_faces);
  // The holes left by the dropped and skipped faces, and the rim, are boundary edges; the
  // grid is consistently oriented and manifold.
  EXPECT_TRUE(report.open);
  EXPECT_FALSE(report.non_manifold);
  EXPECT_FALSE(report.inconsistent_orientation);
}

TEST_F(OffReaderTest, BoundaryEdgeCountIsExactOnABigGrid) {
  // No dropped faces: only the rim is open, 2 (nx - 1) + 2 (ny - 1) edges.
  const int nx = 300, ny = 200;
  std::string off = "OFF\n" + std::to_string(nx * ny) + " " + std::to_string(2 * (nx - 1) * (ny - 1)) + " 0\n";
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) off += std::to_string(i) + " " + std::to_string(j) + " 0\n";
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const int a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
      off += "3 " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\n";
      off += "3 " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  const std::string p = write("rim.off", off);
  MeshReadReport report;
  read_mesh(p, &report);
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_EQ(report.warnings[0], p + ": open mesh: " + std::to_string(2 * (nx - 1) + 2 * (ny - 1)) + " boundary edges");
}

// --- error messages: file, line and cause, the first in the file -------------------------

TEST_F(OffReaderTest, ErrorMessagesNameFileLineAndCause) {
  const std::string head = "OFF\n# comment\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  std::string p = write("coord.off", "OFF\n4 2 0\n0 0 0\n1 x 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 3\n");
  EXPECT_EQ(error_of(p), p + ":4: vertex 1: expected 3 numeric coordinates");
  p = write("short.off", "OFF\n4 2 0\n0 0 0\n1 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 2 3\n");
  EXPECT_EQ(error_of(p), p + ":4: vertex 1: expected 3 numeric coordinates");
  p = write("index.off", head + "3 0 1 2\n\n3 0 2 7\n");
  EXPECT_EQ(error_of(p), p + ":10: face 1: vertex index 7 out of range [0, 4)");
  p = write("negative.off", head + "3 0 -1 2\n3 0 2 3\n");
  EXPECT_EQ(error_of(p), p + ":8: face 0: vertex index -1 out of range [0, 4)");
  p = write("count.off", head + "3 0 1 2\nx 0 2 3\n");
  EXPECT_EQ(error_of(p), p + ":9: face 1: expected a corner count");
  p = write("missing.off", head + "3 0 1 2\n4 0 2 3\n");
  EXPECT_EQ(error_of(p), p + ":9: face 1: expected 4 integer vertex indices");
  p = write("huge.off", head + "2000000000 0 1 2\n3 0 2 3\n");
  EXPECT_EQ(error_of(p), p + ":8: face 0: corner count 2000000000 exceeds the line");
  p = write("truncated.off", head + "3 0 1 2\n");
  EXPECT_EQ(error_of(p), p + ": truncated: header declares 4 vertices and 2 faces but only 5 data lines follow");
  p = write("crlf.off", "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 9\r\n");
  EXPECT_EQ(error_of(p), p + ":6: face 0: vertex index 9 out of range [0, 3)");
  // Parse errors come first, then the coordinate checks (as the sequential reader did).
  p = write("order.off", "OFF\n3 2 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 5\n");
  EXPECT_EQ(error_of(p), p + ":7: face 1: vertex index 5 out of range [0, 3)");
  p = write("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(error_of(p), p + ": vertex 1 has a non-finite (NaN or Inf) coordinate");
}

TEST_F(OffReaderTest, TheFirstErrorOfABigFileIsReportedWithItsLine) {
  // Two bad lines megabytes apart, in different chunks: the earlier one is reported, with the
  // number it has in the file.
  const GridOff g = grid_off(400, 400);
  const auto line_of = [&](std::size_t pos) { return std::size_t(std::count(g.text.begin(), g.text.begin() + pos, '\n')) + 1; };
  // A face line near the end and a vertex line megabytes before it.
  const std::size_t late = g.text.rfind("\n3 ", g.text.size() - 100000) + 1;
  const std::size_t late_line = line_of(late);
  std::size_t mid = 0;  // about half-way through the vertex lines
  for (std::size_t l = 0; l < g.positions.size() / 2; ++l) mid = g.text.find('\n', mid) + 1;
  while (!std::isdigit(static_cast<unsigned char>(g.text[mid])) && g.text[mid] != '+') mid = g.text.find('\n', mid) + 1;
  const std::size_t mid_line = line_of(mid);
  ASSERT_LT(mid_line, late_line);
  std::string bad = g.text;
  bad.replace(late, 1, "x");
  const std::string p1 = write("late.off", bad);
  const std::string e1 = error_of(p1);
  EXPECT_EQ(e1.rfind(p1 + ":" + std::to_string(late_line) + ": face ", 0), 0u) << e1;
  EXPECT_NE(e1.find(": expected a corner count"), std::string::npos) << e1;
  // Now also break a vertex line earlier in the file.
  const std::size_t mid_end = bad.find('\n', mid);
  bad.replace(mid, mid_end - mid, "1 2");
  const std::string p2 = write("two.off", bad);
  const std::string e2 = error_of(p2);
  EXPECT_EQ(e2.rfind(p2 + ":" + std::to_string(mid_line) + ": vertex ", 0), 0u) << e2;
  EXPECT_NE(e2.find(": expected 3 numeric coordinates"), std::string::npos) << e2;
}

} // namespace
} // namespace hb
