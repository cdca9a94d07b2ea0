#include "ErrorFieldPanel.h"
#include "BackgroundJob.h"
#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QRadioButton>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

ErrorFieldPanel::ErrorFieldPanel(HapticSession* session, QWidget* parent) : QWidget(parent), session_(session) {
  metric_ = new QComboBox;
  for (ErrorMetric m : {ErrorMetric::RelativeForce, ErrorMetric::Direction, ErrorMetric::ContactDisagreement})
    metric_->addItem(HapticSession::errorMetricTitle(m), int(m));
  probes_ = new QSpinBox;
  probes_->setRange(1, 64);
  probes_->setValue(1);
  probes_->setToolTip(tr("Probes aimed at each vertex from a 30 degree cone"));
  byPiece_ = new QRadioButton(tr("Colour by piece"));
  byField_ = new QRadioButton(tr("Colour by error field"));
  byPiece_->setChecked(true);
  compute_ = new QPushButton(tr("Compute error field"));
  cancel_ = new QPushButton(tr("Cancel"));
  progress_ = new QProgressBar;
  progress_->setRange(0, 1000);
  info_ = new QLabel;
  info_->setWordWrap(true);

  auto* form = new QFormLayout;
  form->addRow(tr("Metric"), metric_);
  form->addRow(tr("Probes per vertex"), probes_);
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(compute_);
  buttons->addWidget(cancel_);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(byPiece_);
  layout->addWidget(byField_);
  layout->addLayout(form);
  layout->addLayout(buttons);
  layout->addWidget(progress_);
  layout->addWidget(info_);
  layout->addStretch(1);

  const auto changed = [this] { emit displayChanged(showField(), metric()); };
  connect(metric_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, changed);
  connect(byField_, &QRadioButton::toggled, this, changed);
  connect(compute_, &QPushButton::clicked, this, [this] {
    QString error;
    if (!session_->startErrorField(probes_->value(), &error)) {
      emit message(error);
      return;
    }
    running_ = true;
    progress_->setValue(0);
    updateState();
  });
  connect(cancel_, &QPushButton::clicked, this, [this] { session_->job()->cancel(); });
  connect(session_->job(), &BackgroundJob::progressChanged, this, [this](double f) {
    if (running_) progress_->setValue(static_cast<int>(f * 1000.0));
  });
  connect(session_, &HapticSession::jobFinished, this, [this](const QString&, bool ok, const QString&) {
    if (running_ && !ok) progress_->setValue(0);
    running_ = false;
    updateState();
  });
  connect(session_, &HapticSession::errorFieldChanged, this, [this] {
    if (session_->hasErrorField()) byField_->setChecked(true);
    updateState();
    emit displayChanged(showField(), metric());
  });
  connect(session_, &HapticSession::boxesChanged, this, &ErrorFieldPanel::updateState);
  updateState();
}

ErrorMetric ErrorFieldPanel::metric() const { return static_cast<ErrorMetric>(metric_->currentData().toInt()); }
void ErrorFieldPanel::setMetric(ErrorMetric m) { metric_->setCurrentIndex(metric_->findData(int(m))); }
bool ErrorFieldPanel::showField() const { return byField_->isChecked() && session_->hasErrorField(); }
void ErrorFieldPanel::setShowField(bool on) { (on ? byField_ : byPiece_)->setChecked(true); }

void ErrorFieldPanel::updateState() {
  compute_->setEnabled(session_->hasBoxes() && !session_->job()->isRunning());
  cancel_->setEnabled(running_);
  byField_->setEnabled(session_->hasErrorField());
  if (!session_->hasErrorField()) {
    if (byField_->isChecked()) byPiece_->setChecked(true);
    info_->setText(session_->hasBoxes() ? tr("Not computed") : tr("Bake first"));
    return;
  }
  const hb::ErrorField& f = *session_->errorField();
  std::vector<float> v;
  for (float x : f.force_error)
    if (std::isfinite(x)) v.push_back(x);
  double median = 0.0;
  if (!v.empty()) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    median = v[v.size() / 2];
  }
  info_->setText(tr("%1 points, %2 probes in %3 s; median relative force error %4 % (%5 points with data)")
                     .arg(f.size())
                     .arg(f.probes)
                     .arg(f.seconds, 0, 'f', 2)
                     .arg(100.0 * median, 0, 'f', 2)
                     .arg(v.size()));
}
