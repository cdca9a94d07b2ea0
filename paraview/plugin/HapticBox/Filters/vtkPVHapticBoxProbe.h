/**
 * @class   vtkPVHapticBoxProbe
 * @brief   ParaView's "HapticBox Probe": the segment of a line widget (Point1 the handle,
 *          Point2 the tip, model units) answered by the boxes of a .hbox file (or the default
 *          bake of the input surface) and by exact Embree on the input surface, at the
 *          workspace of its diagonal. Output: points 0 handle, 1 tip (a line cell), then the
 *          exact and the box contact points (vertex cells) with point data "Force" (N, 3
 *          components; glyph it), "Depth" and "Method" (0 exact, 1 box); field data
 *          "Perceptible" (the verdict: none, magnitude, direction, contact), "ExactForceN" and
 *          "BoxForceN" (magnitudes).
 */
#ifndef vtkPVHapticBoxProbe_h
#define vtkPVHapticBoxProbe_h
#include "HapticBoxFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

class HAPTICBOXFILTERS_EXPORT vtkPVHapticBoxProbe : public vtkPolyDataAlgorithm {
public:
  static vtkPVHapticBoxProbe* New();
  vtkTypeMacro(vtkPVHapticBoxProbe, vtkPolyDataAlgorithm);
  vtkSetStringMacro(BoxFile);
  vtkGetStringMacro(BoxFile);
  vtkSetVector3Macro(Point1, double);
  vtkGetVector3Macro(Point1, double);
  vtkSetVector3Macro(Point2, double);
  vtkGetVector3Macro(Point2, double);
  vtkSetStringMacro(Workspace);
  vtkGetStringMacro(Workspace);
  vtkSetStringMacro(Perceptual);
  vtkGetStringMacro(Perceptual);

protected:
  vtkPVHapticBoxProbe();
  ~vtkPVHapticBoxProbe() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  char* BoxFile = nullptr;
  double Point1[3] = {0, 0, 1};
  double Point2[3] = {0, 0, 0};
  char* Workspace = nullptr;
  char* Perceptual = nullptr;

private:
  vtkPVHapticBoxProbe(const vtkPVHapticBoxProbe&) = delete;
  void operator=(const vtkPVHapticBoxProbe&) = delete;
};
#endif
