#pragma once
// The surface panel of a volume (CT, MR): which surface of it becomes the haptic model. The
// iso-value in the file's calibrated units (HU for CT) over the volume's histogram with the
// Otsu threshold marked, or a label of a label map; smoothing and the target triangle count;
// Extract re-reads the model with these options (as `hapticbox ... --iso --label --smooth
// --target-triangles`), which the window then bakes.
#include "HapticSession.h"
#include <QWidget>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSpinBox;

/// The histogram of calibrated values (log counts), the Otsu threshold (dashed) and the
/// iso-value (solid); a click or drag chooses the iso-value.
class VolumeHistogramView : public QWidget {
  Q_OBJECT
public:
  explicit VolumeHistogramView(QWidget* parent = nullptr);
  void setHistogram(const hb::vtk::VolumeHistogram& histogram, double otsu);
  void setIso(double iso);
  QSize sizeHint() const override { return {260, 110}; }
  /// The value at horizontal pixel x (tests).
  double valueAt(int x) const;

signals:
  void isoChosen(double iso);

protected:
  void paintEvent(QPaintEvent* event) override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;

private:
  QRect plotRect() const;
  int xOf(double value) const;
  hb::vtk::VolumeHistogram histogram_;
  double otsu_ = 0.0, iso_ = 0.0;
};

class SurfacePanel : public QWidget {
  Q_OBJECT
public:
  explicit SurfacePanel(HapticSession* session, QWidget* parent = nullptr);
  /// Shows the open model: a volume's facts, histogram and the options it was read with.
  void showModel();
  /// The options of the controls.
  hb::vtk::ModelOptions options() const;

  QDoubleSpinBox* isoBox() const { return iso_; }
  QCheckBox* labelCheck() const { return useLabel_; }
  QSpinBox* labelBox() const { return label_; }
  QSpinBox* smoothBox() const { return smooth_; }
  QSpinBox* targetBox() const { return target_; }
  QPushButton* extractButton() const { return extract_; }
  VolumeHistogramView* histogramView() const { return histogram_; }

signals:
  /// Re-read the open volume with these options.
  void extractRequested(const hb::vtk::ModelOptions& options);

private:
  HapticSession* session_;
  QLabel* facts_;
  VolumeHistogramView* histogram_;
  QDoubleSpinBox* iso_;
  QPushButton* otsu_;
  QCheckBox* useLabel_;
  QSpinBox* label_;
  QSpinBox* smooth_;
  QSpinBox* target_;
  QPushButton* extract_;
  QLabel* status_;
};
