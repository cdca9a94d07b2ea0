#pragma once
// Text in an error message that a damaged file or a third-party library chose: control and
// other unprintable bytes written as \xNN (a NUL would end the message where it stands, an
// escape sequence would drive the terminal), at most a given number of bytes, a longer text cut
// with its length given. One escaping for every message.
#include <cstddef>
#include <string>

namespace hb {

namespace detail {

// Bytes of the valid UTF-8 sequence of 2 to 4 bytes starting at text[i], 0 if there is none.
inline std::size_t utf8_sequence(const std::string& text, std::size_t i) {
  const unsigned char c = static_cast<unsigned char>(text[i]);
  const std::size_t n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  if (n == 0 || i + n > text.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return 0;
  return n;
}

inline std::string escaped(const std::string& text, std::size_t max, bool message) {
  static const char hex[] = "0123456789ABCDEF";
  std::string out;
  std::size_t i = 0;
  while (i < text.size() && out.size() < max) {  // `max` bounds what is written (an escaped byte takes 4)
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const std::size_t utf8 = message && c >= 0x80 ? utf8_sequence(text, i) : 0;
    if ((c >= 0x20 && c < 0x7F) || (message && c == '\n')) {
      out += char(c);
      ++i;
    } else if (utf8 > 0) {
      out.append(text, i, utf8);  // a name in another script stays readable
      i += utf8;
    } else {
      out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
      ++i;
    }
  }
  if (i < text.size()) out += "... (" + std::to_string(text.size()) + " bytes in all)";
  return out;
}

} // namespace detail

/// Text from a file quoted in a message: printable ASCII as is, every other byte as \xNN, about
/// `max` characters of it; a longer text is cut, "... (N bytes in all)" saying how long it was.
inline std::string quoted_text(const std::string& text, std::size_t max = 20) { return detail::escaped(text, max, false); }

/// A whole message whose parts a library or a file may have chosen (a reader's error text):
/// valid UTF-8 and line breaks kept, other control and invalid bytes as \xNN, about `max`
/// characters, cut with its length given.
inline std::string readable_message(const std::string& text, std::size_t max = 2000) { return detail::escaped(text, max, true); }

} // namespace hb
