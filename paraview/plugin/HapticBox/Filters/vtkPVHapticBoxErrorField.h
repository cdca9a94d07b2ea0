/**
 * @class   vtkPVHapticBoxErrorField
 * @brief   ParaView's "HapticBox Error Field": vtkHapticBoxErrorFieldFilter on the input surface
 *          with the boxes of a .hbox file (or the default bake of the surface), at the
 *          workspace of the surface's diagonal: the arrays `hapticbox field BOX MESH` writes.
 *
 * Properties as text, as the command line takes them: Workspace ("mm=80,stiffness=1500",
 * empty for the default), Perceptual ("nominal", "strict" or "w=10,f0=0.04,theta=25,fmin=0.2").
 * Besides the field's arrays, "PerceptibleColour" (RGBA) is PerceptibleRatio through the
 * product's perceptible colour scale (hb::vtk::perceptible_table: below 1 the plain surface,
 * 1-4 amber to crimson): colour by it with Map Scalars off to see the window's picture.
 */
#ifndef vtkPVHapticBoxErrorField_h
#define vtkPVHapticBoxErrorField_h
#include "HapticBoxFiltersModule.h"
#include <vtkPolyDataAlgorithm.h>

class HAPTICBOXFILTERS_EXPORT vtkPVHapticBoxErrorField : public vtkPolyDataAlgorithm {
public:
  static vtkPVHapticBoxErrorField* New();
  vtkTypeMacro(vtkPVHapticBoxErrorField, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The .hbox file of the boxes (empty: the default bake of the input surface).
  vtkSetStringMacro(BoxFile);
  vtkGetStringMacro(BoxFile);
  /// Probes aimed at each point (1).
  vtkSetClampMacro(ProbesPerPoint, int, 1, 100000);
  vtkGetMacro(ProbesPerPoint, int);
  /// Seed of the probes (1).
  vtkSetClampMacro(Seed, int, 0, VTK_INT_MAX);
  vtkGetMacro(Seed, int);
  /// 0: one value per vertex (default); 1: NumberOfSamples points spread evenly by area.
  vtkSetClampMacro(SampleMode, int, 0, 1);
  vtkGetMacro(SampleMode, int);
  vtkSetClampMacro(NumberOfSamples, int, 1, VTK_INT_MAX);
  vtkGetMacro(NumberOfSamples, int);
  /// The workspace spec (`--workspace`; empty: the default, 80 mm at 1500 N/m).
  vtkSetStringMacro(Workspace);
  vtkGetStringMacro(Workspace);
  /// The perceptual thresholds (`--perceptual`; default "nominal").
  vtkSetStringMacro(Perceptual);
  vtkGetStringMacro(Perceptual);

protected:
  vtkPVHapticBoxErrorField();
  ~vtkPVHapticBoxErrorField() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* BoxFile = nullptr;
  int ProbesPerPoint = 1;
  int Seed = 1;
  int SampleMode = 0;
  int NumberOfSamples = 10000;
  char* Workspace = nullptr;
  char* Perceptual = nullptr;

private:
  vtkPVHapticBoxErrorField(const vtkPVHapticBoxErrorField&) = delete;
  void operator=(const vtkPVHapticBoxErrorField&) = delete;
};
#endif
