#pragma once
// The readout: depth, both force magnitudes, their relative error and angle, query times,
// the device thread's rate and p99 period.
#include <QWidget>

struct ProbeReading;
class QLabel;

class ReadoutPanel : public QWidget {
  Q_OBJECT
public:
  explicit ReadoutPanel(QWidget* parent = nullptr);
  void setReading(const ProbeReading& r);
  /// Whether a model is open (the hint without a probe then says how to open one).
  void setModelOpen(bool open);
  /// The text of a row (tests): "depth", "exact", "approx", "error", "angle", "query", "device", "felt".
  QString rowText(const QString& key) const;

private:
  QLabel* depth_;
  QLabel* exact_;
  QLabel* approx_;
  QLabel* error_;
  QLabel* angle_;
  QLabel* query_;
  QLabel* device_;
  QLabel* felt_;  ///< whether a hand would feel the box-vs-exact difference (hb::perceive)
  bool modelOpen_ = false;
};
