/**
 * @class   vtkHapticBoxErrorFieldImage
 * @brief   Renders an error field (output of vtkHapticBoxErrorFieldFilter) to a PNG file.
 *
 * Debian's VTK 9.1 renders only through X, so rendering is attempted only when a display is
 * available: $DISPLAY is set and an X connection opens (DisplayAvailable). Headless callers
 * (the hapticbox command without X) get false and a note instead of a crash. Under
 * `xvfb-run -a` an image is produced.
 */
#ifndef vtkHapticBoxErrorFieldImage_h
#define vtkHapticBoxErrorFieldImage_h

#include "mesh/triangle_mesh.h"
#include <string>
#include <vector>

class vtkPolyData;

class vtkHapticBoxErrorFieldImage {
public:
  /// True when an X display can be opened; otherwise false with the reason in `why`.
  static bool DisplayAvailable(std::string* why = nullptr);

  /**
   * Renders `field` coloured by its point array `arrayName` (blue 0 to red `rangeMax`; NaN,
   * "no data", grey) with a scalar bar titled `title`, from two opposite views side by side,
   * to `pngPath` (`width` x `height` pixels). Returns false with the reason in `note` when
   * there is no display, the array is missing or the file cannot be written. Never throws.
   */
  static bool Render(vtkPolyData* field, const std::string& arrayName, double rangeMax, const std::string& title,
                     const std::string& pngPath, int width = 1200, int height = 600, std::string* note = nullptr);

  /**
   * As Render, for the perceptible ratio (array `arrayName`: the difference over what a hand
   * feels, 1 = just feelable) on its fixed scale anchored at 1 (hb::vtk::perceptible_table):
   * below 1 the model's plain colour, so differences no one can feel look like nothing.
   */
  static bool RenderPerceptible(vtkPolyData* field, const std::string& arrayName, const std::string& pngPath,
                                int width = 1200, int height = 600, std::string* note = nullptr);

  /**
   * A report's error-field picture (hb::ErrorFieldRenderer, report/report_request.h): the
   * per-vertex perceptible ratios over `mesh` (RenderPerceptible; the range argument is unused:
   * the scale is fixed), 1200 x 700, when a display is available (otherwise false and the
   * reason in `note`).
   */
  static bool RenderField(const hb::TriangleMesh& mesh, const std::vector<float>& perceptibleRatio, double unused,
                          const std::string& pngPath, std::string* note);

private:
  static bool RenderScale(vtkPolyData* field, const std::string& arrayName, bool perceptible, double rangeMax,
                          const std::string& title, const std::string& pngPath, int width, int height,
                          std::string* note);
};

#endif
