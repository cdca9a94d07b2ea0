#pragma once
// The error-field panel: compute (progress, cancel), choose the metric, colour by it, and the
// worst vertices for that metric (click one: the probe moves there).
#include "HapticSession.h"
#include <QWidget>

class QComboBox;
class QListWidget;
class QLabel;
class QProgressBar;
class QPushButton;
class QRadioButton;
class QSpinBox;

class ErrorFieldPanel : public QWidget {
  Q_OBJECT
public:
  explicit ErrorFieldPanel(HapticSession* session, QWidget* parent = nullptr);
  ErrorMetric metric() const;
  void setMetric(ErrorMetric m);
  bool showField() const;
  void setShowField(bool on);
  QPushButton* computeButton() const { return compute_; }
  /// The worst-vertices list (tests): one row per vertex, worst first, for the metric shown.
  QListWidget* worstList() const { return worst_; }

signals:
  /// The view should colour by piece (false) or by the field's metric (true).
  void displayChanged(bool showField, ErrorMetric metric);
  void message(const QString& text);
  /// A worst vertex was chosen: move the probe onto `point` (outward `normal`), model units.
  void goToPoint(const hb::Vec3& point, const hb::Vec3& normal);
  /// A worst vertex was chosen: put the probe where the field measured it (vertex index).
  void goToVertex(std::size_t vertex);

private:
  void updateState();
  void updateWorst();

  HapticSession* session_;
  QComboBox* metric_;
  QSpinBox* probes_;
  QRadioButton* byPiece_;
  QRadioButton* byField_;
  QPushButton* compute_;
  QPushButton* cancel_;
  QProgressBar* progress_;
  QLabel* info_;
  QListWidget* worst_;
  bool running_ = false;
};
