// 1. check that X opens (Debian's VTK has no EGL/OSMesa path: without X a render window aborts);
// 2. two renderers (front and back views) over one mapper coloured by the error array;
// 3. render off screen, grab with vtkWindowToImageFilter, write with vtkPNGWriter.
#include "vtkHapticBoxErrorFieldImage.h"
#include <vtkActor.h>
#include <vtkAutoInit.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
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
    vtkNew<vtkLookupTable> lut;
    lut->SetHueRange(0.667, 0.0);
    lut->SetTableRange(0.0, rangeMax > 0.0 ? rangeMax : 1.0);
    lut->SetNanColor(0.6, 0.6, 0.6, 1.0);
    lut->UseAboveRangeColorOn();
    lut->SetAboveRangeColor(0.5, 0.0, 0.0, 1.0);
    lut->Build();
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
    for (int view = 0; view < 2; ++view) {
      vtkNew<vtkRenderer> renderer;
      renderer->SetViewport(0.5 * view, 0.0, 0.5 * (view + 1), 1.0);
      renderer->SetBackground(1.0, 1.0, 1.0);
      renderer->AddActor(actor);
      renderer->ResetCamera();
      if (view == 1) renderer->GetActiveCamera()->Azimuth(180.0);
      renderer->GetActiveCamera()->Zoom(1.4);
      renderer->ResetCameraClippingRange();
      if (view == 1) {
        vtkNew<vtkScalarBarActor> bar;
        bar->SetLookupTable(lut);
        bar->SetTitle(title.c_str());
        bar->SetNumberOfLabels(5);
        bar->GetTitleTextProperty()->SetColor(0, 0, 0);
        bar->GetLabelTextProperty()->SetColor(0, 0, 0);
        bar->SetWidth(0.12);
        bar->SetHeight(0.7);
        bar->SetPosition(0.86, 0.15);
        renderer->AddActor2D(bar);
      }
      window->AddRenderer(renderer);
    }
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
