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

/// The non-blank lines of CSV text in order, a UTF-8 byte order mark dropped and CRLF line ends
/// accepted: next() gives each line, number() its 1-based number in the text.
class CsvLines {
public:
  explicit CsvLines(std::string_view text) : text_(text) {
    if (text_.size() >= 3 && text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
  }
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++number_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      if (line.find_first_not_of(" \t") != std::string_view::npos) return true;
    }
    return false;
  }
  std::size_t number() const { return number_; }

private:
  std::string_view text_;
  std::size_t pos_ = 0, number_ = 0;
};

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
