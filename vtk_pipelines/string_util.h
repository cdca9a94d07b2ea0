#pragma once
// Small string helpers shared by the readers of this layer (extensions, units, zip entries).
#include <algorithm>
#include <cctype>
#include <string>

namespace hb::vtk {

/// `s` in ASCII lower case (extensions and unit names compare case-insensitively).
inline std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

/// True when `s` ends with `tail`.
inline bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

} // namespace hb::vtk
