#pragma once
// Probe segments from a CSV file (the `query --segments` input), and the strict number
// parsing shared by the command line's numeric options.
#include "geometry/segment.h"
#include <string>
#include <string_view>
#include <vector>

namespace hb {

/// Parses a whole token as a float: decimal or scientific notation, an optional sign
/// (leading '+' allowed), no locale, no trailing characters. Values below float's range
/// (1e-40, 1e-300, 1e-400) become the nearest float (denormal or zero); a value beyond it
/// ("1e39"), "nan", "inf" and anything else are refused (returns false).
bool parse_finite_float(std::string_view token, float& value);

/// Largest |coordinate| of a probe segment read from a file or the command line, model units:
/// 4 x kMaxCoordinate covers every box around a mesh, and keeps k x depth x metres per unit
/// finite for every force law the command line accepts.
constexpr float kMaxSegmentCoordinate = 4e15f;

/// Parses CSV text with the header sx,sy,sz,ex,ey,ez (spaces allowed around cells; a UTF-8
/// byte order mark, CRLF line ends and blank lines accepted) and six finite numbers a row,
/// each within kMaxSegmentCoordinate.
/// Throws hb::InvalidInput naming `name`, the line and the cause.
std::vector<Segment> parse_segments_csv(std::string_view text, const std::string& name);

/// The whole text of `path`, a `what` file (e.g. "segments"). Throws hb::IoError when it is
/// missing, a folder or unreadable.
std::string read_text_file(const std::string& path, const std::string& what);

/// Reads a segments CSV (see parse_segments_csv). Throws hb::IoError when `path` is missing,
/// a folder or unreadable, hb::InvalidInput for its content.
std::vector<Segment> read_segments_csv(const std::string& path);

} // namespace hb
