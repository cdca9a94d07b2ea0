#pragma once
// The 3D probe view: the model coloured by piece or by error field, PBB outlines, the probe
// segment and the exact and approximated force arrows with a legend. Shows what it is given;
// computes nothing (the session does).
#include "HapticSession.h"
#include "SessionFile.h"
#include <QVTKOpenGLNativeWidget.h>
#include <vtkSmartPointer.h>
#include <array>
#include <string>

class ProbeInteractorStyle;
class vtkActor;
class vtkGenericOpenGLRenderWindow;
class vtkIdTypeArray;
class vtkLineSource;
class vtkOrientationMarkerWidget;
class vtkPolyDataMapper;
class vtkRenderer;
class vtkScalarBarActor;
class vtkScalarsToColors;
class vtkUnsignedCharArray;
class vtkStaticCellLocator;
class vtkTextActor;


class ProbeView : public QVTKOpenGLNativeWidget {
  Q_OBJECT
public:
  enum class ColorMode { Pieces, ErrorField };

  explicit ProbeView(QWidget* parent = nullptr);
  ~ProbeView() override;

  /// The surface to show (cell "PieceId", optional error point arrays). Resets the camera.
  void setSurface(vtkPolyData* surface, float diagonal);
  void setOutlines(vtkPolyData* outlines);
  void setOutlinesVisible(bool on);
  bool outlinesVisible() const;
  /// Colours by piece, or by the error field's `metric` (when the surface has the array).
  void setColorMode(ColorMode mode, ErrorMetric metric = ErrorMetric::Perceptible);
  ColorMode colorMode() const { return colorMode_; }
  /// Updates the probe segment and both arrows; renders when something changed.
  void setReading(const ProbeReading& reading, double forceScale);
  void setProbeMode(bool on);

  /// Picks the model at display coordinates (VTK's, origin bottom-left).
  bool pickSurface(int x, int y, hb::Vec3& point) const;
  /// The camera's view direction and right vector (unit), for aiming the probe.
  hb::Vec3 viewDirection() const;
  hb::Vec3 viewRight() const;

  void resetCamera();
  /// Moves the camera (keeping its direction and distance) so that `point` is at the centre.
  void centreOn(const hb::Vec3& point);
  /// The camera's focal point (tests).
  hb::Vec3 focalPoint() const;
  /// Looks along an axis (0 x, 1 y, 2 z), toward +axis when `sign` > 0 (ParaView's "+X"
  /// button: the camera on the -X side), the model framed; up is +Z (+Y for the Z views).
  void viewAlong(int axis, int sign);
  /// The orientation axes in the lower-left corner (vtkOrientationMarkerWidget, vtkAxesActor).
  void setOrientationAxesVisible(bool on);
  bool orientationAxesVisible() const;
  /// Orbits the camera about the focal point, degrees.
  void orbitCamera(double azimuth, double elevation);
  CameraState cameraState() const;
  void setCameraState(const CameraState& s);

  /// Renders at the next pass of the event loop (GUI thread; coalesced).
  void renderNow();
  /// Writes the view as PNG, `magnification` (1-8) times the view's size in pixels, with a
  /// transparent background (RGBA) when asked; throws hb::IoError.
  void saveScreenshot(const QString& path, int magnification = 1, bool transparent = false);
  /// The view's size in pixels (what magnification 1 writes).
  QSize viewPixels() const;
  /// What is on screen (tests).
  bool exactArrowShown() const;
  bool approxArrowShown() const;
  bool scalarBarShown() const;
  /// The model's colouring as drawn (tests read the colours back through VTK, not pixels):
  /// the lookup table, whether scalars colour it, the per-vertex colours the mapper makes
  /// (RGBA, one tuple a point; null when not coloured by a point array), the bar's title.
  vtkScalarsToColors* surfaceColorTable() const;
  bool surfaceColoredByScalars() const;
  vtkUnsignedCharArray* mappedSurfaceColors();
  std::string scalarBarTitle() const;
  /// The colour an arrow is drawn in (the series colours of the charts and the report).
  std::array<double, 3> arrowColor(bool exact) const;
  /// The caption beside an arrow seen nearly end on ("toward you" / "away from you"), empty
  /// when the arrow reads by its shape (tests).
  QString exactArrowCaption() const;
  QString approxArrowCaption() const;
  /// Frames per second over `frames` renders while orbiting (benchmark); `interactive`
  /// renders the level-of-detail proxy, as during a drag.
  double measureFrameRate(int frames, bool interactive = false);
  /// Triangles of the level-of-detail proxy (0: the model is small enough to need none).
  vtkIdType proxyTriangles() const;
  /// While interacting (camera or probe moving) a decimated proxy of a large model is drawn,
  /// as ParaView does; the full model is drawn again once the view is still for 250 ms.
  void setInteracting(bool on);
  /// A preview surface of a volume's options (the Surface panel's live preview), drawn in its
  /// own colour in place of the model with `caption` above it; null: the model again. Keeps the
  /// camera (the preview lies where the model does).
  void setPreview(vtkPolyData* preview, const QString& caption = {});
  /// Triangles of the preview shown (0: none), and the preview itself (null: none).
  vtkIdType previewTriangles() const;
  vtkPolyData* preview() const { return preview_; }

signals:
  /// A left drag on the model: the point under the mouse; `press` on the first one.
  void surfaceDragged(const hb::Vec3& point, bool press);
  /// Ctrl + wheel: +1 deeper, -1 shallower.
  void depthStepped(int step);

private:
  // The constructor's parts: the model, its proxy, preview and outlines; the probe, arrows,
  // captions and legend; the interaction; the scalar bar and orientation axes.
  void addModelActors();
  void addProbeActors();
  void connectInteraction();
  void addOverlays();
  void updateColoring();
  void updateArrowCaptions();
  void buildProxy();
  void updateProxyColors();

  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window_;
  vtkSmartPointer<vtkRenderer> renderer_;
  vtkSmartPointer<ProbeInteractorStyle> style_;
  vtkSmartPointer<vtkPolyDataMapper> surfaceMapper_;
  vtkSmartPointer<vtkActor> surfaceActor_;
  vtkSmartPointer<vtkPolyData> proxy_;
  vtkSmartPointer<vtkIdTypeArray> proxySource_;  ///< nearest model vertex of each proxy point
  vtkSmartPointer<vtkPolyDataMapper> proxyMapper_;
  vtkSmartPointer<vtkActor> proxyActor_;
  vtkSmartPointer<vtkPolyData> preview_;
  vtkSmartPointer<vtkPolyDataMapper> previewMapper_;
  vtkSmartPointer<vtkActor> previewActor_;
  vtkSmartPointer<vtkTextActor> previewCaption_;
  class QTimer* stillTimer_ = nullptr;
  bool interacting_ = false;
  bool renderPending_ = false;
  vtkSmartPointer<vtkPolyDataMapper> outlineMapper_;
  vtkSmartPointer<vtkActor> outlineActor_;
  vtkSmartPointer<vtkLineSource> probeLine_;
  vtkSmartPointer<vtkActor> probeActor_;
  vtkSmartPointer<vtkActor> tipActor_;
  vtkSmartPointer<vtkActor> exactArrow_;
  vtkSmartPointer<vtkActor> approxArrow_;
  vtkSmartPointer<vtkTextActor> exactCaption_;
  vtkSmartPointer<vtkTextActor> approxCaption_;
  hb::Vec3 exactTip_{0.f, 0.f, 0.f}, approxTip_{0.f, 0.f, 0.f};
  hb::Vec3 exactDir_{0.f, 0.f, 0.f}, approxDir_{0.f, 0.f, 0.f};
  float exactLength_ = 0.f;  ///< shown length of the arrows (the captions stand clear of the rim)
  vtkSmartPointer<vtkOrientationMarkerWidget> axesWidget_;
  vtkSmartPointer<vtkTextActor> legendExact_;
  vtkSmartPointer<vtkTextActor> legendApprox_;
  vtkSmartPointer<vtkScalarBarActor> scalarBar_;
  vtkSmartPointer<vtkStaticCellLocator> locator_;
  vtkPolyData* surface_ = nullptr;
  float diagonal_ = 1.f;
  ColorMode colorMode_ = ColorMode::Pieces;
  ErrorMetric metric_ = ErrorMetric::Perceptible;
  std::array<float, 12> lastShown_{};
};
