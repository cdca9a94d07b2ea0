#pragma once
// Line and token cursors over a text buffer, and strict number parsing, shared by the
// text readers (OFF, ASCII STL, ASCII PLY, OBJ checks). Internal to src/mesh.
#include <charconv>
#include <cstddef>
#include <string_view>
#include <system_error>

namespace hb::detail {

/// Cursor over the non-blank, comment-stripped lines of a text buffer.
class LineReader {
public:
  /// `comment`: the character starting a comment to the end of the line ('\0': none).
  explicit LineReader(std::string_view text, char comment = '#') : text_(text), comment_(comment) {}

  /// Next line with content (comments removed, trimmed); false at the end.
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      std::string_view l = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      ++line_number_;
      if (comment_ != '\0') {
        const std::size_t hash = l.find(comment_);
        if (hash != std::string_view::npos) l = l.substr(0, hash);
      }
      l = trim(l);
      if (!l.empty()) {
        line = l;
        return true;
      }
    }
    return false;
  }
  /// 1-based number of the line last returned by next().
  std::size_t line_number() const { return line_number_; }
  /// Byte offset just past the line last returned by next() (its '\n' included).
  std::size_t position() const { return pos_ < text_.size() ? pos_ : text_.size(); }

  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
  static std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
  }

private:
  std::string_view text_;
  char comment_;
  std::size_t pos_ = 0;
  std::size_t line_number_ = 0;
};

/// Splits a line into whitespace-separated tokens, one at a time.
class Tokens {
public:
  explicit Tokens(std::string_view line) : s_(line) {}
  bool next(std::string_view& tok) {
    while (i_ < s_.size() && LineReader::is_space(s_[i_])) ++i_;
    if (i_ >= s_.size()) return false;
    const std::size_t b = i_;
    while (i_ < s_.size() && !LineReader::is_space(s_[i_])) ++i_;
    tok = s_.substr(b, i_ - b);
    return true;
  }

private:
  std::string_view s_;
  std::size_t i_ = 0;
};

/// Parses the whole token as a number (from_chars: no locale, no partial parse, a leading '+'
/// allowed). For floating point, out-of-range text ("1e39" into a float, "1e400") fails.
template <typename T>
bool parse_number(std::string_view tok, T& value) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;  // from_chars rejects a leading '+'
  const auto r = std::from_chars(b, e, value);
  return r.ec == std::errc() && r.ptr == e;
}

} // namespace hb::detail
