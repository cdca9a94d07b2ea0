// The model options as text, as the command line, the window and the Python module give them:
// hb::vtk::model_options_from_specs and hb::vtk::parse_cad_spec.
#include "model_spec.h"
#include "errors.h"
#include <gtest/gtest.h>
#include <string>

namespace {

std::string refusal(const std::string& unit, const std::string& volume, const std::string& cad) {
  try {
    hb::vtk::model_options_from_specs(unit, volume, cad);
  } catch (const hb::InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(ModelSpecTest, TheThreeTextsSetTheLoadersOptions) {
  const hb::vtk::ModelOptions o = hb::vtk::model_options_from_specs("cm", "iso=300,smooth=5", "chordal-mm=0.05,accept-lost-faces");
  EXPECT_EQ(o.unit, "cm");
  ASSERT_TRUE(o.volume.iso.has_value());
  EXPECT_DOUBLE_EQ(*o.volume.iso, 300.0);
  EXPECT_EQ(o.volume.smooth_iterations, 5);
  EXPECT_DOUBLE_EQ(o.cad.chordal_deviation_mm, 0.05);
  EXPECT_TRUE(o.cad.accept_lost_faces);
  const hb::vtk::ModelOptions d = hb::vtk::model_options_from_specs("", "", "");
  EXPECT_TRUE(d.unit.empty());
  EXPECT_FALSE(d.volume.iso.has_value());
  EXPECT_EQ(d.cad.chordal_deviation_mm, hb::vtk::CadOptions{}.chordal_deviation_mm);
  EXPECT_FALSE(d.cad.accept_lost_faces);
}

TEST(ModelSpecTest, ABadValueIsRefusedNamingTheOptionAndTheKey) {
  EXPECT_NE(refusal("furlong", "", "").find("unknown unit 'furlong'"), std::string::npos);
  EXPECT_NE(refusal("", "colour=red", "").find("--volume"), std::string::npos);
  const std::string chordal = refusal("", "", "chordal-mm=-1");
  EXPECT_NE(chordal.find("--cad chordal-mm"), std::string::npos) << chordal;
  EXPECT_NE(refusal("", "", "force-tolerance=0").find("--cad force-tolerance"), std::string::npos);
  EXPECT_NE(refusal("", "", "accept-lost-faces=maybe").find("is not on or off"), std::string::npos);
  EXPECT_NE(refusal("", "", "tolerance=3").find("unknown key 'tolerance'"), std::string::npos);
}

TEST(ModelSpecTest, AMissingFileIsAnIoErrorNamingIt) {
  try {
    hb::vtk::load_model_guarded("/nonexistent/model.off");
    FAIL() << "no error";
  } catch (const hb::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/model.off"), std::string::npos);
  }
}

} // namespace
