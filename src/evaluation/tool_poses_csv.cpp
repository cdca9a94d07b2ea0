// Poses CSV: a header of named columns, then a number a column a row; errors name the line.
#include "evaluation/tool_poses_csv.h"
#include "errors.h"
#include "evaluation/segments_csv.h"
#include <cmath>

namespace hb {
namespace {

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    std::string_view cell = line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    while (!cell.empty() && (cell.front() == ' ' || cell.front() == '\t')) cell.remove_prefix(1);
    while (!cell.empty() && (cell.back() == ' ' || cell.back() == '\t')) cell.remove_suffix(1);
    cells.push_back(cell);
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

std::string printable(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
  if (s.size() > 40) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

} // namespace

std::vector<ToolPose> parse_tool_poses_csv(std::string_view text, const std::string& name) {
  static const char* const kNames[7] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
  int column[7] = {-1, -1, -1, -1, -1, -1, -1};
  std::size_t columns = 0;
  bool header_seen = false;
  std::vector<ToolPose> out;
  CsvLines lines(text);
  std::string_view line;
  const auto where = [&] { return name + ":" + std::to_string(lines.number()) + ": "; };
  while (lines.next(line)) {
    const std::vector<std::string_view> cells = split_cells(line);
    if (!header_seen) {
      header_seen = true;
      columns = cells.size();
      for (std::size_t c = 0; c < cells.size(); ++c) {
        int k = 0;
        while (k < 7 && cells[c] != kNames[k]) ++k;
        if (k == 7)
          throw InvalidInput(where() + "unknown column '" + printable(cells[c]) + "' (columns: x,y,z and optionally qw,qx,qy,qz)");
        if (column[k] >= 0) throw InvalidInput(where() + "column '" + kNames[k] + "' appears twice");
        column[k] = int(c);
      }
      for (int k = 0; k < 3; ++k)
        if (column[k] < 0) throw InvalidInput(where() + "the header has no column '" + kNames[k] + "' (x,y,z are required)");
      const int q = (column[3] >= 0) + (column[4] >= 0) + (column[5] >= 0) + (column[6] >= 0);
      if (q != 0 && q != 4) throw InvalidInput(where() + "an orientation needs all four columns qw,qx,qy,qz");
      continue;
    }
    if (cells.size() != columns)
      throw InvalidInput(where() + "expected " + std::to_string(columns) + " values, got " + std::to_string(cells.size()));
    float v[7] = {0, 0, 0, 1, 0, 0, 0};
    for (int k = 0; k < 7; ++k) {
      if (column[k] < 0) continue;
      const std::string_view cell = cells[std::size_t(column[k])];
      if (!parse_finite_float(cell, v[k]))
        throw InvalidInput(where() + kNames[k] + " is not a finite number: '" + printable(cell) + "'");
      if (k < 3 && std::fabs(v[k]) > kMaxSegmentCoordinate)
        throw InvalidInput(where() + kNames[k] + " is beyond the supported range (|x| <= 4e15)");
    }
    out.push_back(tool_pose(v, where()));
  }
  if (!header_seen) throw InvalidInput(name + ": empty poses file (expected a header with x,y,z)");
  return out;
}

ToolPose tool_pose(const float v[7], const std::string& where) {
  Eigen::Quaternionf q(v[3], v[4], v[5], v[6]);
  const float length = q.norm();
  if (!(length > 1e-6f) || !std::isfinite(length))
    throw InvalidInput(where + "the orientation qw,qx,qy,qz has no length (give a unit quaternion)");
  ToolPose pose;
  pose.position = Vec3(v[0], v[1], v[2]);
  pose.orientation = Eigen::Quaternionf(q.coeffs() / length);
  return pose;
}

std::vector<ToolPose> read_tool_poses_csv(const std::string& path) {
  return parse_tool_poses_csv(read_text_file(path, "poses"), path);
}

} // namespace hb
