#pragma once
// The error-field panel: compute (progress, cancel), choose the metric, colour by it.
#include "HapticSession.h"
#include <QWidget>

class QComboBox;
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

signals:
  /// The view should colour by piece (false) or by the field's metric (true).
  void displayChanged(bool showField, ErrorMetric metric);
  void message(const QString& text);

private:
  void updateState();

  HapticSession* session_;
  QComboBox* metric_;
  QSpinBox* probes_;
  QRadioButton* byPiece_;
  QRadioButton* byField_;
  QPushButton* compute_;
  QPushButton* cancel_;
  QProgressBar* progress_;
  QLabel* info_;
  bool running_ = false;
};
