#pragma once
// The Stability tab: runs the trajectory stability suite (as `hapticbox stability`) on the open
// model's boxes in the background and shows its table: test, scene, metric, box, exact,
// threshold, verdict; with the penalty law or the proxy.
#include <QWidget>

class HapticSession;
class QCheckBox;
class QComboBox;
class QLabel;
class QPushButton;
class QSpinBox;
class QTableWidget;

class StabilityPanel : public QWidget {
  Q_OBJECT
public:
  explicit StabilityPanel(HapticSession* session, QWidget* parent = nullptr);

  QPushButton* runButton() const { return run_; }
  QSpinBox* sitesBox() const { return sites_; }
  QCheckBox* generatedBox() const { return generated_; }
  /// The contact law the suite runs (as `hapticbox stability --law`): penalty or proxy.
  QComboBox* lawBox() const { return law_; }
  QTableWidget* table() const { return table_; }
  QLabel* summaryLabel() const { return summary_; }

signals:
  void message(const QString& text);

private:
  void showReport();
  void updateState();

  HapticSession* session_;
  QSpinBox* sites_;
  QCheckBox* generated_;
  QComboBox* law_;
  QPushButton* run_;
  QLabel* summary_;
  QTableWidget* table_;
};
