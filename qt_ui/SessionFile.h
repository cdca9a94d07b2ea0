#pragma once
// The session file (.hbsession, JSON): model, pieces and bake parameters, probe, display and
// camera, so that opening it restores the window.
#include "HapticSession.h"
#include <QString>
#include <array>

/// Camera state.
struct CameraState {
  std::array<double, 3> position{}, focalPoint{}, viewUp{};
  double viewAngle = 30.0;
  double parallelScale = 1.0;
};

struct SessionState {
  QString meshPath;
  BakeSettings bake;
  bool baked = false;                  ///< boxes existed: bake (or load the cache) on open.
  double depthFraction = 0.01;
  std::array<float, 3> probeDirection{0.f, 0.f, -1.f};
  double tiltDegrees = 0.0;
  bool hasProbe = false;               ///< the probe was placed: `probePoint` is where.
  std::array<float, 3> probePoint{};   ///< the surface point the probe was dragged to, model units.
  bool outlines = false;
  bool showErrorField = false;
  ErrorMetric metric = ErrorMetric::Perceptible;
  bool hasCamera = false;
  CameraState camera;
  /// How a volume became the model (the Surface panel: iso-value or label, smoothing, target
  /// triangles; the command line's --iso, --label, --smooth, --target-triangles), restored
  /// when the session opens. `hasSurface` false: the file had none (the loader's defaults).
  bool hasSurface = false;
  hb::vtk::VolumeSurfaceOptions surface;
};

/// True for a path the window opens as a session (the .hbsession extension, any case).
bool isSessionPath(const QString& path);

/// Writes `state` as JSON. Throws hb::IoError.
void saveSessionFile(const SessionState& state, const QString& path);
/// Reads a session file; relative paths are resolved against the file's folder.
/// Throws hb::IoError (unreadable) or hb::InvalidInput (not a session file, or a "mesh" that is
/// a session file itself: this one, another, or one in a cycle; a session names a model, so
/// opening one never opens another).
SessionState loadSessionFile(const QString& path);
