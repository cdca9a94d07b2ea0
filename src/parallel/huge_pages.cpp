#include "parallel/huge_pages.h"
#include <sys/stat.h>
#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace hb {
namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitizerHeap = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
constexpr bool kSanitizerHeap = true;
#else
constexpr bool kSanitizerHeap = false;
#endif
#else
constexpr bool kSanitizerHeap = false;
#endif

std::string thp_enabled() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::stringstream text;
  if (in) text << in.rdbuf();
  return text.str();
}

} // namespace

std::string huge_page_tunables(const char* current, const std::string& thp_enabled, std::uint64_t largest_input) {
  if (largest_input < kHugePageInputBytes) return "";
  // Only "madvise" needs the advice: "always" gives huge pages without it, "never" refuses.
  if (thp_enabled.find("[madvise]") == std::string::npos) return "";
  const std::string now = current ? current : "";
  if (now.find("glibc.malloc.hugetlb") != std::string::npos) return "";
  return now.empty() ? "glibc.malloc.hugetlb=1" : now + ":glibc.malloc.hugetlb=1";
}

void use_huge_page_heap(int argc, char** argv) noexcept {
  if (kSanitizerHeap || argv == nullptr || argv[0] == nullptr) return;  // not glibc's malloc
  try {
    std::uint64_t largest = 0;
    for (int i = 1; i < argc; ++i) {
      struct stat st;
      if (argv[i] && ::stat(argv[i], &st) == 0 && S_ISREG(st.st_mode))
        largest = std::max<std::uint64_t>(largest, std::uint64_t(st.st_size));
    }
    if (largest < kHugePageInputBytes) return;
    const std::string value = huge_page_tunables(std::getenv("GLIBC_TUNABLES"), thp_enabled(), largest);
    if (value.empty()) return;
    if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    ::execv("/proc/self/exe", argv);
    // exec failed: the tunable in the environment now stops any retry; run as we are.
  } catch (...) {
  }
}

std::string heap_pages() {
  const std::string thp = thp_enabled();
  const char* env = std::getenv("GLIBC_TUNABLES");
  const bool advised = env && std::string(env).find("glibc.malloc.hugetlb=1") != std::string::npos;
  if (kSanitizerHeap) return "a sanitizer's heap";
  if (thp.find("[always]") != std::string::npos || (advised && thp.find("[madvise]") != std::string::npos))
    return "transparent huge pages";
  return "4 KB pages";
}

} // namespace hb
