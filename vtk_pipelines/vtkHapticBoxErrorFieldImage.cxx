// 1. check that X opens (Debian's VTK has no EGL/OSMesa path: without X a render window aborts);
// 2. two renderers (front and back views) over one mapper coloured by the error array;
// 3. render off screen, grab with vtkWindowToImageFilter, write with vtkPNGWriter.
#include "vtkHapticBoxErrorFieldImage.h"
#include "error_colour_map.h"
#include "vtkHapticBoxUtilities.h"
#include <vtkActor.h>
#include <vtkAutoInit.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkFloatArray.h>
#include <vtkLookupTable.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>
// The OpenGL render window and font factories, whatever the executable's autoinit covers.
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType);

// Last: Xlib defines macros (None, Bool, Status) that clash with VTK headers.
#include <X11/Xlib.h>

bool vtkHapticBoxErrorFieldImage::DisplayAvailable(std::string* why) {
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name) {
    if (why) *why = "no display ($DISPLAY is not set); run under xvfb-run -a for an image";
    return false;
  }
  // An X server that is resetting (Xvfb does so when its last client leaves) refuses new
  // connections for a moment: try a few times before calling the display absent.
  Display* display = nullptr;
  for (int attempt = 0; attempt < 20 && !display; ++attempt) {
    if (attempt > 0) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    display = XOpenDisplay(name);
  }
  if (!display) {
    if (why) *why = std::string("cannot open the X display ") + name;
    return false;
  }
  XCloseDisplay(display);
  return true;
}

bool vtkHapticBoxErrorFieldImage::Render(vtkPolyData* field, const std::string& arrayName, double rangeMax,
                                         const std::string& title, const std::string& pngPath, int width,
                                         int height, std::string* note) {
  return RenderScale(field, arrayName, false, rangeMax, title, pngPath, width, height, note);
}

bool vtkHapticBoxErrorFieldImage::RenderPerceptible(vtkPolyData* field, const std::string& arrayName,
                                                    const std::string& pngPath, int width, int height, std::string* note) {
  return RenderScale(field, arrayName, true, hb::vtk::kPerceptibleTop, hb::vtk::perceptible_title(), pngPath, width,
                     height, note);
}

bool vtkHapticBoxErrorFieldImage::RenderScale(vtkPolyData* field, const std::string& arrayName, bool perceptible,
                                              double rangeMax, const std::string& title, const std::string& pngPath,
                                              int width, int height, std::string* note) {
  try {
    std::string why;
    if (!DisplayAvailable(&why)) {
      if (note) *note = why;
      return false;
    }
    if (!field || !field->GetPointData()->GetArray(arrayName.c_str())) {
      if (note) *note = "the field has no array " + arrayName;
      return false;
    }
    double plain[3];
    hb::vtk::plain_surface_colour(plain);
    vtkSmartPointer<vtkLookupTable> lut = perceptible ? hb::vtk::perceptible_table(plain) : hb::vtk::viridis_table(rangeMax);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(field);
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray(arrayName.c_str());
    mapper->SetLookupTable(lut);
    mapper->UseLookupTableScalarRangeOn();
    mapper->ScalarVisibilityOn();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    vtkNew<vtkRenderWindow> window;
    window->SetShowWindow(false);  // renders to an offscreen framebuffer; still needs X here
    window->SetSize(width, height);
    window->SetMultiSamples(0);
    // Front and back views above, the colour bar in a strip of its own below: the bar's title
    // never lands on the model and reads at full size.
    const double strip = 0.17;
    for (int view = 0; view < 2; ++view) {
      vtkNew<vtkRenderer> renderer;
      renderer->SetViewport(0.5 * view, strip, 0.5 * (view + 1), 1.0);
      renderer->SetBackground(1.0, 1.0, 1.0);
      renderer->AddActor(actor);
      renderer->ResetCamera();
      if (view == 1) renderer->GetActiveCamera()->Azimuth(180.0);
      renderer->GetActiveCamera()->Zoom(1.3);
      renderer->ResetCameraClippingRange();
      window->AddRenderer(renderer);
    }
    vtkNew<vtkRenderer> legend;
    legend->SetViewport(0.0, 0.0, 1.0, strip);
    legend->SetBackground(1.0, 1.0, 1.0);
    vtkNew<vtkScalarBarActor> bar;
    if (perceptible) hb::vtk::style_perceptible_bar(bar, lut);
    else hb::vtk::style_scalar_bar(bar, lut, title, false);
    bar->SetOrientationToHorizontal();
    bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    bar->GetPositionCoordinate()->SetValue(0.15, 0.05);
    bar->SetWidth(0.7);
    bar->SetHeight(0.9);
    bar->SetBarRatio(0.35);
    bar->GetTitleTextProperty()->SetFontSize(18);
    legend->AddActor2D(bar);
    window->AddRenderer(legend);
    window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    grab->Update();
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(pngPath.c_str());
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    if (!std::ifstream(pngPath).good()) {
      if (note) *note = "could not write " + pngPath;
      return false;
    }
    return true;
  } catch (const std::exception& e) {
    if (note) *note = e.what();
    return false;
  }
}

bool vtkHapticBoxErrorFieldImage::RenderField(const hb::TriangleMesh& mesh, const std::vector<float>& perceptibleRatio,
                                              double, const std::string& pngPath, std::string* note) {
  if (!DisplayAvailable(note)) return false;
  vtkSmartPointer<vtkPolyData> pd = vtkHapticBoxUtilities::ToPolyData(mesh);
  pd->GetPointData()->AddArray(vtkHapticBoxUtilities::ToScalarArray("PerceptibleRatio", perceptibleRatio));
  return RenderPerceptible(pd, "PerceptibleRatio", pngPath, 1200, 700, note);
}
