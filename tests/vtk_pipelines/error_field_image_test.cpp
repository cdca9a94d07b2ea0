// Needs an X display: labelled `gui` in CTest and run under xvfb-run -a; skipped without one.
#include "test_meshes.h"
#include "vtkHapticBoxErrorFieldImage.h"
#include "error_colour_map.h"
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <cmath>
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

namespace {

// Pixels of a rendered picture in the perceptible ramp's colours (amber to crimson: strong red,
// blue well below green and red), counted over the two model views (the bar's strip left out).
std::size_t rampPixels(const std::string& png) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  std::size_t n = 0;
  for (int y = int(0.2 * dims[1]); y < dims[1]; ++y)  // image rows start at the bottom
    for (int x = 0; x < dims[0]; ++x) {
      const auto* p = static_cast<unsigned char*>(image->GetScalarPointer(x, y, 0));
      if (p[0] > 90 && p[2] < 0.45 * p[0] && p[1] < 0.85 * p[0]) ++n;
    }
  return n;
}

}  // namespace

TEST(ErrorFieldImageTest, ThePerceptibleFieldShowsOnlyWhatAHandWouldFeel) {
  std::string why;
  if (!vtkHapticBoxErrorFieldImage::DisplayAvailable(&why)) GTEST_SKIP() << why;
  // The lookup table: below 1 the plain colour, 2 on the ramp.
  double plain[3];
  hb::vtk::plain_surface_colour(plain);
  vtkSmartPointer<vtkLookupTable> lut = hb::vtk::perceptible_table(plain);
  double rgb[3];
  for (double r : {0.0, 0.5, 0.99}) {
    lut->GetColor(r, rgb);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], plain[c], 1.0 / 255) << "ratio " << r;
  }
  lut->GetColor(2.0, rgb);
  EXPECT_GT(std::abs(rgb[2] - plain[2]), 0.3);
  // The exported pictures: a field under the threshold shows no ramp colour; one above it does.
  const hb::TriangleMesh mesh = hb::make_sphere(1.f, 3);
  const std::string below = hb::test::ScratchPath("below.png"), above = hb::test::ScratchPath("above.png");
  std::string note;
  std::vector<float> ratio(mesh.vertex_count());
  for (std::size_t i = 0; i < ratio.size(); ++i) ratio[i] = 0.99f * float(i % 10) / 9.f;
  ASSERT_TRUE(vtkHapticBoxErrorFieldImage::RenderField(mesh, ratio, 4.0, below, &note)) << note;
  for (float& r : ratio) r = 2.f;
  ASSERT_TRUE(vtkHapticBoxErrorFieldImage::RenderField(mesh, ratio, 4.0, above, &note)) << note;
  const std::size_t none = rampPixels(below), some = rampPixels(above);
  std::printf("ramp-coloured pixels: %zu with every ratio below 1, %zu at 2\n", none, some);
  EXPECT_EQ(none, 0u);
  EXPECT_GT(some, 5000u);
  std::remove(below.c_str());
  std::remove(above.c_str());
}
