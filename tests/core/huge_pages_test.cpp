#include "parallel/huge_pages.h"
#include <gtest/gtest.h>

namespace {

const char* const kMadvise = "always [madvise] never\n";
constexpr std::uint64_t kBig = hb::kHugePageInputBytes;

TEST(HugePageHeapTest, MadviseModeAddsTheTunableToAnEmptyOrExistingEnvironment) {
  EXPECT_EQ(hb::huge_page_tunables(nullptr, kMadvise, kBig), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(hb::huge_page_tunables("", kMadvise, kBig), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(hb::huge_page_tunables("glibc.malloc.arena_max=2", kMadvise, kBig),
            "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
}

TEST(HugePageHeapTest, SmallInputsAUsersOwnChoiceAndOtherKernelModesAreLeftAlone) {
  EXPECT_EQ(hb::huge_page_tunables(nullptr, kMadvise, kBig - 1), "");  // a small mesh: no re-exec
  EXPECT_EQ(hb::huge_page_tunables("glibc.malloc.hugetlb=0", kMadvise, kBig), "");
  EXPECT_EQ(hb::huge_page_tunables("glibc.malloc.hugetlb=1", kMadvise, kBig), "");  // no second re-exec
  EXPECT_EQ(hb::huge_page_tunables(nullptr, "[always] madvise never\n", kBig), "");
  EXPECT_EQ(hb::huge_page_tunables(nullptr, "always madvise [never]\n", kBig), "");
  EXPECT_EQ(hb::huge_page_tunables(nullptr, "", kBig), "");  // no THP file (an old or foreign kernel)
}

} // namespace
