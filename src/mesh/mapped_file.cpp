// MappedFile: mmap of a whole file, read-only and private; release() is madvise(DONTNEED),
// which on a clean file-backed page only unmaps it from the process (the data stays valid).
#include "mesh/mapped_file.h"

#include "errors.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace hb::detail {

MappedFile::MappedFile(const std::string& path, Access access) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError(path + ": cannot open for reading (" + std::strerror(errno) + ")");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw IoError(path + ": not a regular file");
  }
  if (st.st_size <= 0) {
    ::close(fd);
    throw IoError(path + ": file is empty");
  }
  size_ = std::size_t(st.st_size);
  void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
  const int map_errno = errno;
  ::close(fd);
  if (p == MAP_FAILED) throw IoError(path + ": cannot map the file (" + std::strerror(map_errno) + ")");
  data_ = static_cast<const char*>(p);
  // The parsers read front to back (each thread its own run of chunks): ask for read-ahead.
  if (access == Access::sequential) ::madvise(p, size_, MADV_SEQUENTIAL);
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<char*>(data_), size_);
}

void MappedFile::release(std::size_t begin, std::size_t end) const noexcept {
  static const std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
  if (end > size_) end = size_;
  // Only whole pages: a page shared with a neighbouring range may still be read.
  const std::size_t first = (begin + page - 1) / page * page;
  const std::size_t last = end == size_ ? (size_ + page - 1) / page * page : end / page * page;
  if (last > first) ::madvise(const_cast<char*>(data_) + first, last - first, MADV_DONTNEED);
}

} // namespace hb::detail
