#pragma once
// Two queries asked the same probes: the same answers, probe for probe, bit for bit.
#include "contact/contact.h"
#include <gtest/gtest.h>
#include <cstddef>
#include <vector>

namespace hb::test {

/// Expects `a` and `b` to give the same contact flag on every probe and, in contact, the same
/// depth, force and normal; returns the probes in contact (stops at the first flag that differs).
inline std::size_t expect_same_answers(const ContactQuery& a, const ContactQuery& b, const std::vector<Segment>& probes,
                                       const ForceLaw& law) {
  std::size_t contacts = 0;
  for (const Segment& s : probes) {
    const Contact x = a.query(s, law), y = b.query(s, law);
    EXPECT_EQ(x.contact, y.contact);
    if (x.contact != y.contact) break;
    if (!x.contact) continue;
    ++contacts;
    EXPECT_EQ(x.depth, y.depth);
    EXPECT_EQ(x.force, y.force);
    EXPECT_EQ(x.normal, y.normal);
  }
  return contacts;
}

} // namespace hb::test
