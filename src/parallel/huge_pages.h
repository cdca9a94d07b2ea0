#pragma once
// Huge pages for the process's heap. A 13M-triangle bake allocates and frees about 3.5 GB in
// vectors of hundreds of MB; in 4 KB pages the kernel spent a third of the bake faulting and
// zeroing them (sys 21-25 s of a 75-80 s wall, perf: clear_page, page faults under memset).
// glibc 2.35+ advises its own mmap'd chunks and heap for transparent huge pages with the
// tunable glibc.malloc.hugetlb=1, which it reads only at start-up, from the environment.
#include <cstdint>
#include <string>

namespace hb {

/// Inputs below this size leave the process as it is: their bakes and loads allocate too
/// little for the faults to matter, and the re-execution costs a start-up (0.17 s with the
/// VTK libraries).
constexpr std::uint64_t kHugePageInputBytes = std::uint64_t(16) << 20;

/// Called first thing in main(), before any thread or MPI start: when an argument names a
/// file of at least kHugePageInputBytes, transparent huge pages are in "madvise" mode
/// (Debian's default) and GLIBC_TUNABLES does not already name glibc.malloc.hugetlb (a
/// user's own choice, 0 included, is kept), re-executes this program (/proc/self/exe, the
/// same arguments) with glibc.malloc.hugetlb=1 added. Returns only when it did not
/// re-execute (small inputs, THP "always" or "never", already set, a sanitizer's allocator,
/// or exec failed: the process then runs as before).
void use_huge_page_heap(int argc, char** argv) noexcept;

/// The GLIBC_TUNABLES value use_huge_page_heap() would set given the current one (nullptr:
/// unset), or "" when it leaves the environment alone; `thp_enabled` is the text of
/// /sys/kernel/mm/transparent_hugepage/enabled, `largest_input` the size of the largest
/// file the arguments name.
std::string huge_page_tunables(const char* current, const std::string& thp_enabled, std::uint64_t largest_input);

/// What the heap of this process gets, for `hapticbox --version`: "transparent huge pages"
/// (THP "always", or "madvise" with glibc.malloc.hugetlb=1 in GLIBC_TUNABLES) or "4 KB pages".
std::string heap_pages();

} // namespace hb
