#include "parallel/huge_pages.h"
#include <gtest/gtest.h>

namespace {

const char* const kMadvise = "always [madvise] never\n";

TEST(HugePageHeapTest, MadviseModeAddsTheTunableToAnEmptyOrExistingEnvironment) {
  EXPECT_EQ(hb::huge_page_tunables(nullptr, kMadvise), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(hb::huge_page_tunables("", kMadvise), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(hb::huge_page_tunables("glibc.malloc.arena_max=2", kMadvise),
            "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
}

TEST(HugePageHeapTest, AUsersOwnChoiceAndOtherKernelModesAreLeftAlone) {
  EXPECT_EQ(hb::huge_page_tunables("glibc.malloc.hugetlb=0", kMadvise), "");
  EXPECT_EQ(hb::huge_page_tunables("glibc.malloc.hugetlb=1", kMadvise), "");  // no second re-exec
  EXPECT_EQ(hb::huge_page_tunables(nullptr, "[always] madvise never\n"), "");
  EXPECT_EQ(hb::huge_page_tunables(nullptr, "always madvise [never]\n"), "");
  EXPECT_EQ(hb::huge_page_tunables(nullptr, ""), "");  // no THP file (an old or foreign kernel)
}

} // namespace
