#pragma once
// The surface panel of a volume (CT, MR): which surface of it becomes the haptic model. The
// iso-value in the file's calibrated units (HU for CT) over the volume's histogram with the
// Otsu threshold marked, or a label of a label map; smoothing and the target triangle count;
// Extract re-reads the model with these options (as `hapticbox ... --iso --label --smooth
// --target-triangles`), which the window then bakes. Before that, a live preview: 300 ms after
// the iso-value, label or smoothing last changed, the surface of a reduced copy of the volume
// (volume_preview.h) is computed on a worker thread and shown in the 3D view.
#include "HapticSession.h"
#include <QFutureWatcher>
#include <QWidget>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QSpinBox;
class QTimer;

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

  QCheckBox* previewCheck() const { return previewOn_; }
  /// Triangles of the last preview shown (0: none), whether one is being computed or waits
  /// for its debounce, and the longest the GUI thread waited for a preview (it never computes
  /// one itself: only hands the result to the view), ms.
  std::size_t previewTriangles() const { return previewTriangles_; }
  bool previewPending() const;
  QString statusText() const;

  /// How long the controls must rest before a preview is computed, ms.
  static constexpr int kPreviewDebounceMs = 300;

signals:
  /// Re-read the open volume with these options.
  void extractRequested(const hb::vtk::ModelOptions& options);
  /// A preview surface to show (null: hide the preview; the model shows again), and its caption.
  void previewChanged(vtkSmartPointer<vtkPolyData> surface, const QString& caption);

private:
  struct PreviewResult {
    vtkSmartPointer<vtkPolyData> surface;
    int shrink = 1;
    double seconds = 0.0;
    QString error;
    unsigned generation = 0;
  };
  void schedulePreview();
  void startPreview();
  void previewFinished();
  void clearPreview();

  QCheckBox* previewOn_;
  QTimer* previewTimer_;
  QFutureWatcher<PreviewResult>* previewWatcher_;
  bool previewAgain_ = false;   ///< the options changed while a preview ran: run another after it.
  bool showing_ = false;        ///< showModel is filling the controls (no preview for that).
  unsigned generation_ = 0;     ///< bumped when another model opens: older previews are dropped.
  std::size_t previewTriangles_ = 0;
  QString surfaceText_;
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
