// The --volume spec both front ends take (hapticbox and hapticbox-gui): hb::vtk::parse_volume_spec.
#include "volume_spec.h"
#include "errors.h"
#include <gtest/gtest.h>
#include <string>

namespace {

std::string refusal(const std::string& spec) {
  hb::vtk::VolumeSurfaceOptions o;
  try {
    hb::vtk::parse_volume_spec(spec, o);
  } catch (const hb::InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(VolumeSpecTest, EveryKeySetsItsOptionInAnyOrder) {
  hb::vtk::VolumeSurfaceOptions o;
  hb::vtk::parse_volume_spec("triangles=20000,smooth=15,iso=-480", o);
  ASSERT_TRUE(o.iso.has_value());
  EXPECT_DOUBLE_EQ(*o.iso, -480.0);
  EXPECT_FALSE(o.label.has_value());
  EXPECT_EQ(o.smooth_iterations, 15);
  EXPECT_EQ(o.target_triangles, 20000u);
  hb::vtk::VolumeSurfaceOptions l;
  hb::vtk::parse_volume_spec("label=2", l);
  ASSERT_TRUE(l.label.has_value());
  EXPECT_EQ(*l.label, 2);
  EXPECT_EQ(l.smooth_iterations, 0);
}

TEST(VolumeSpecTest, BadSpecsAreRefusedNamingTheKey) {
  EXPECT_EQ(refusal("iso=1,label=2"), "--volume: iso and label exclude each other (give one)");
  EXPECT_EQ(refusal("isovalue=3"), "--volume: unknown key 'isovalue' (keys: iso, label, smooth, triangles)");
  EXPECT_EQ(refusal("label=2.5"), "--volume label: '2.5' is not a whole number");
  EXPECT_NE(refusal("smooth=1001").find("--volume smooth: '1001' is not a number in [0, 1000]"), std::string::npos);
  EXPECT_NE(refusal("iso=nan").find("--volume iso: 'nan'"), std::string::npos);
  EXPECT_EQ(refusal(""), "");
}

} // namespace
