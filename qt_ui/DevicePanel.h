#pragma once
// The device panel: virtual (mouse), replay a recorded trajectory, or a connected Falcon;
// the servo's contact law (penalty or proxy); probe depth and tilt.
#include "HapticSession.h"
#include <QWidget>

class QComboBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QSlider;

class DevicePanel : public QWidget {
  Q_OBJECT
public:
  explicit DevicePanel(HapticSession* session, QWidget* parent = nullptr);
  /// Applies the chosen device (shows the fallback note once when there is no hardware).
  void applyDevice();
  void showDepth();
  /// The servo's contact law (as `hapticbox servo --law`).
  QComboBox* lawBox() const { return law_; }

signals:
  void message(const QString& text);
  void tiltRequested();

private:
  HapticSession* session_;
  QComboBox* kind_;
  QComboBox* law_;
  QLineEdit* replay_;
  QPushButton* browse_;
  QPushButton* apply_;
  QSlider* depth_;
  QLabel* depthLabel_;
  QLabel* status_;
  bool hardwareNoteShown_ = false;
};
