/**
 * @class   ProbeInteractorStyle
 * @brief   Trackball camera, except that a left drag that starts on the model moves the probe.
 *
 * The style only reports display coordinates; ProbeView picks and the session moves the
 * device. Ctrl + wheel steps the probe depth. With probe mode off it is a plain trackball.
 */
#ifndef ProbeInteractorStyle_h
#define ProbeInteractorStyle_h

#include <vtkInteractorStyleTrackballCamera.h>
#include <functional>

class ProbeInteractorStyle : public vtkInteractorStyleTrackballCamera {
public:
  static ProbeInteractorStyle* New();
  vtkTypeMacro(ProbeInteractorStyle, vtkInteractorStyleTrackballCamera);

  /// Called with display coordinates; returns true when the point is on the model (the drag
  /// then moves the probe rather than the camera).
  std::function<bool(int x, int y, bool press)> ProbeCallback;
  /// Called with +1 / -1 on Ctrl + wheel.
  std::function<void(int step)> DepthCallback;

  vtkSetMacro(ProbeMode, bool);
  vtkGetMacro(ProbeMode, bool);

  void OnLeftButtonDown() override;
  void OnLeftButtonUp() override;
  void OnMouseMove() override;
  void OnMouseWheelForward() override;
  void OnMouseWheelBackward() override;

protected:
  ProbeInteractorStyle() = default;
  ~ProbeInteractorStyle() override = default;

  bool ProbeMode = true;
  bool Dragging = false;

private:
  ProbeInteractorStyle(const ProbeInteractorStyle&) = delete;
  void operator=(const ProbeInteractorStyle&) = delete;
};

#endif
