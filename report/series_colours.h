#pragma once
// One colour per series wherever a series is drawn: the report's and the command line's charts
// (PLplot, report_charts.cpp), the window's Charts tab, its 3D probe arrows and its readout.
// The haptic box is blue, exact (Embree) red, VTK's cell locator orange, the raw boxes a bake
// tried purple (matplotlib's tab10).
namespace hb {

struct SeriesColour {
  int r, g, b;  ///< sRGB, 0-255.
  constexpr double rf() const { return r / 255.0; }
  constexpr double gf() const { return g / 255.0; }
  constexpr double bf() const { return b / 255.0; }
};

inline constexpr SeriesColour kBoxSeries{31, 119, 180};    ///< the haptic box: blue.
inline constexpr SeriesColour kExactSeries{214, 39, 40};   ///< exact Embree: red.
inline constexpr SeriesColour kVtkSeries{255, 127, 14};    ///< VTK's static cell locator: orange.
/// The raw haptic boxes a budgeted bake tried (hb::bake_chart_points): purple.
inline constexpr SeriesColour kRawTrialSeries{148, 103, 189};

} // namespace hb
