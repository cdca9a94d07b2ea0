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

/// The viridis colour at t in [0, 1] (clamped), RGB in [0, 1].
void viridis(double t, double rgb[3]);

} // namespace hb::vtk
