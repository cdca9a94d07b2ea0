#pragma once
// A whole file mapped read-only (RAII): the text readers that parse big files in parallel
// (no copy into a string, and the pages of parts already parsed can be handed back to the
// kernel so a 500 MB file does not stay resident next to the mesh it becomes) and the box
// file, whose tables the queries read in place.
#include <cstddef>
#include <string>
#include <string_view>

namespace hb::detail {

class MappedFile {
public:
  /// How the pages will be read: front to back (read-ahead asked for) or in any order.
  enum class Access { sequential, random };
  /// Maps `path`. Throws hb::IoError (cannot open, not a regular file, empty, cannot map);
  /// the message names the file and the cause.
  explicit MappedFile(const std::string& path, Access access = Access::sequential);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;

  std::string_view text() const { return {data_, size_}; }
  const char* data() const { return data_; }
  std::size_t size() const { return size_; }

  /// Drops the whole pages inside [begin, end) (byte offsets) from this process's resident
  /// set; reading them again later is still valid (they fault back in from the file).
  void release(std::size_t begin, std::size_t end) const noexcept;

private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

} // namespace hb::detail
