// Needs an X display: labelled `gui` in CTest and run under xvfb-run -a; skipped without one.
#include "test_meshes.h"
#include "vtkHapticBoxErrorFieldImage.h"
#include <gtest/gtest.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>

TEST(ErrorFieldImageTest, RendersAPngWithADisplay) {
  std::string why;
  if (!vtkHapticBoxErrorFieldImage::DisplayAvailable(&why)) GTEST_SKIP() << why;
  vtkSmartPointer<vtkPolyData> pd = hb::test::SpherePolyData(3);
  std::vector<float> values(std::size_t(pd->GetNumberOfPoints()));
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = float(i % 10) / 10.f;
  pd->GetPointData()->AddArray(vtkHapticBoxUtilities::ToScalarArray("RelativeForceError", values));
  const std::string png = hb::test::ScratchPath("field.png");
  std::string note;
  ASSERT_TRUE(vtkHapticBoxErrorFieldImage::Render(pd, "RelativeForceError", 1.0, "error", png, 400, 200, &note)) << note;
  std::ifstream in(png, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  EXPECT_EQ(std::string(sig + 1, 3), "PNG");
  std::remove(png.c_str());
}

TEST(ErrorFieldImageTest, WithoutADisplayItDeclinesWithANote) {
  const char* saved = std::getenv("DISPLAY");
  const std::string keep = saved ? saved : "";
  ::unsetenv("DISPLAY");
  std::string note;
  EXPECT_FALSE(vtkHapticBoxErrorFieldImage::Render(hb::test::SpherePolyData(1), "X", 1.0, "", "/tmp/vtk_never.png", 10, 10, &note));
  EXPECT_NE(note.find("DISPLAY"), std::string::npos);
  if (saved) ::setenv("DISPLAY", keep.c_str(), 1);
}
