#pragma once
// Tool poses from a CSV file (the `query --tool --poses` input): a header naming the columns
// x,y,z (the tool's centre, model units) and optionally qw,qx,qy,qz (its orientation), in any
// order; one pose a row.
#include "tool/tool_contact.h"
#include <string>
#include <string_view>
#include <vector>

namespace hb {

/// The pose of x, y, z (model units) and the orientation qw, qx, qy, qz (normalised): `v` holds
/// the seven values. Throws hb::InvalidInput, `where` then the cause, for a quaternion of no
/// length (below 1e-6, or not finite). The CSV reader and the Python module both make poses here.
ToolPose tool_pose(const float v[7], const std::string& where);

/// Parses poses CSV text (a UTF-8 byte order mark, CRLF line ends, blank lines and spaces
/// around cells accepted). A quaternion is normalised; one of length below 1e-6 is refused.
/// Throws hb::InvalidInput naming `name`, the line, the column and the cause.
std::vector<ToolPose> parse_tool_poses_csv(std::string_view text, const std::string& name);

/// Reads a poses CSV. Throws hb::IoError when `path` is missing or unreadable,
/// hb::InvalidInput for its content.
std::vector<ToolPose> read_tool_poses_csv(const std::string& path);

} // namespace hb
