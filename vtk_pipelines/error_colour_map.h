#pragma once
// The colour maps of the error field, shared by the window and the report's rendered image:
// viridis (perceptually uniform, readable in grey and by colour-blind viewers) for continuous
// errors, a two-colour categorical map for the yes/no contact disagreement, grey for no data.
#include <vtkSmartPointer.h>
#include <string>

class vtkLookupTable;
class vtkScalarBarActor;

namespace hb::vtk {

/// Viridis over [0, range_max] (range_max <= 0: [0, 1]); values above show the top colour (the
/// bar's top label then means "this or more"); NaN grey, annotated "no data".
vtkSmartPointer<vtkLookupTable> viridis_table(double range_max);

/// Two categories, 0 "contacts agree" (dark blue) and 1 "contacts disagree" (yellow), as an
/// indexed lookup table (the scalar bar draws swatches, not a continuous bar).
vtkSmartPointer<vtkLookupTable> agreement_table();

/// Sets up `bar` for `table`: title, label format, the "no data" swatch (and "above" swatch for
/// continuous tables), fonts large enough to read; light text on a dark background.
void style_scalar_bar(vtkScalarBarActor* bar, vtkLookupTable* table, const std::string& title, bool categorical,
                      bool dark_background = false);

/// The perceptible-difference ratio (hb::perceive's difference over its threshold: 1 = what a
/// hand just feels) over [0, kPerceptibleTop]: everything below 1 is `plain` (the model's own
/// colour: no one can feel it), 1 to kPerceptibleTop a ramp from amber through orange and red
/// to dark crimson, above it the top colour ("and above"); NaN grey. Fixed, so pictures of
/// different models and bakes compare.
constexpr double kPerceptibleTop = 4.0;
vtkSmartPointer<vtkLookupTable> perceptible_table(const double plain[3]);
/// The colour of a model with nothing to show (the window's plain surface, the report's picture).
void plain_surface_colour(double rgb[3]);
/// The perceptible scale's bar title, in the user's terms.
std::string perceptible_title();
/// Sets up `bar` for the perceptible table (style_scalar_bar, whole-number labels 0..top).
void style_perceptible_bar(vtkScalarBarActor* bar, vtkLookupTable* table, bool dark_background = false);

/// The viridis colour at t in [0, 1] (clamped), RGB in [0, 1].
void viridis(double t, double rgb[3]);

} // namespace hb::vtk
