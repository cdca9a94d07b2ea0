#pragma once
// Text from a damaged file quoted in an error message: control and non-ASCII bytes written as
// \xNN (a NUL would end the message where it stands), at most a given number of bytes.
#include <cstddef>
#include <string>

namespace hb {

inline std::string quoted_text(const std::string& text, std::size_t max = 20) {
  static const char hex[] = "0123456789ABCDEF";
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < max; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7F) out += char(c);
    else out += std::string("\\x") + hex[c >> 4] + hex[c & 15];
  }
  return out;
}

} // namespace hb
