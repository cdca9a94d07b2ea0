#include "ErrorFieldPanel.h"
#include "BackgroundJob.h"
#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include "figure_text.h"
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <QProgressBar>
#include <QPushButton>
#include <QRadioButton>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

namespace {

const std::vector<float>& metricValues(const hb::ErrorField& f, ErrorMetric m) {
  switch (m) {
  case ErrorMetric::Perceptible: return f.perceptible_ratio;
  case ErrorMetric::RelativeForce: return f.force_error;
  case ErrorMetric::Direction: return f.direction_error;
  case ErrorMetric::ContactDisagreement: break;
  }
  return f.contact_disagreement;
}

}  // namespace

ErrorFieldPanel::ErrorFieldPanel(HapticSession* session, QWidget* parent) : QWidget(parent), session_(session) {
  metric_ = new QComboBox;
  for (ErrorMetric m : kErrorMetrics)
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
  worst_ = new QListWidget;
  worst_->setToolTip(tr("The vertices where the metric shown is worst; click one to move the probe there"));
  worst_->setMaximumHeight(170);

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
  layout->addWidget(new QLabel(tr("Worst vertices (click to probe there):")));
  layout->addWidget(worst_);
  layout->addStretch(1);
  connect(worst_, &QListWidget::itemActivated, this, [this](QListWidgetItem* item) {
    const QVariantList v = item->data(Qt::UserRole).toList();
    if (v.size() == 7) emit goToVertex(std::size_t(v[6].toULongLong()));
    else if (v.size() == 6)
      emit goToPoint(hb::Vec3(v[0].toFloat(), v[1].toFloat(), v[2].toFloat()),
                     hb::Vec3(v[3].toFloat(), v[4].toFloat(), v[5].toFloat()));
  });
  connect(worst_, &QListWidget::itemClicked, worst_, &QListWidget::itemActivated);

  const auto changed = [this] {
    updateState();
    emit displayChanged(showField(), metric());
  };
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
    worst_->clear();
    if (byField_->isChecked()) byPiece_->setChecked(true);
    info_->setText(session_->hasBoxes() ? tr("Not computed") : tr("Bake first"));
    return;
  }
  // The summary names the metric shown (and its unit), and the vertices without data.
  const hb::ErrorField& f = *session_->errorField();
  const ErrorMetric m = metric();
  const std::vector<float>& values = metricValues(f, m);
  const hb::ErrorValuesSummary sum = hb::summarize_error_values(values, 0);
  const std::size_t noData = sum.no_data;
  const double median = sum.median;
  QString figure;
  if (m == ErrorMetric::Perceptible) {
    std::size_t felt = 0;
    float largest = 0.f;
    for (float v : values)
      if (v > 1.f) ++felt, largest = std::max(largest, v);
    figure = felt == 0 ? tr("a hand would feel the difference at none of the %1 vertices (coloured: above 1 x "
                            "what a hand feels)").arg(values.size())
                       : tr("a hand would feel the difference at %1 of %2 vertices (%3), up to %4 x the threshold")
                             .arg(felt)
                             .arg(values.size())
                             .arg(QString::fromStdString(hb::percent(double(felt) / double(std::max<std::size_t>(1, values.size())))))
                             .arg(QString::fromStdString(hb::sig(largest)));
  } else if (m == ErrorMetric::RelativeForce)
    figure = tr("median relative force error %1").arg(QString::fromStdString(hb::percent(median)));
  else if (m == ErrorMetric::Direction)
    figure = tr("median direction error %1 deg").arg(QString::fromStdString(hb::sig(median)));
  else
    figure = tr("contacts disagree at %1 of %2 vertices (%3)")
                 .arg(sum.above_zero)
                 .arg(sum.with_data)
                 .arg(QString::fromStdString(
                     hb::percent(sum.with_data == 0 ? 0.0 : double(sum.above_zero) / double(sum.with_data))));
  info_->setText(tr("%1 points, %2 probes in %3; %4; %5 point(s) with no data (grey: no probe touched the "
                    "surface in both answers)")
                     .arg(f.size())
                     .arg(f.probes)
                     .arg(QString::fromStdString(hb::duration_text(f.seconds)))
                     .arg(figure)
                     .arg(noData));
  updateWorst();
}

void ErrorFieldPanel::updateWorst() {
  worst_->clear();
  const hb::ErrorField& f = *session_->errorField();
  vtkPolyData* surface = session_->surface();
  if (!surface || surface->GetNumberOfPoints() != vtkIdType(f.size())) return;
  const ErrorMetric m = metric();
  const std::vector<float>& values = metricValues(f, m);
  const std::vector<std::size_t> order = hb::summarize_error_values(values, 10).worst;
  const std::size_t k = order.size();
  vtkDataArray* normals = surface->GetPointData()->GetNormals();
  for (std::size_t j = 0; j < k; ++j) {
    const std::size_t i = order[j];
    double p[3], n[3] = {0.0, 0.0, 1.0};
    surface->GetPoint(vtkIdType(i), p);
    if (normals) normals->GetTuple(vtkIdType(i), n);
    const QString value = m == ErrorMetric::Perceptible ? QString::fromStdString(hb::sig(values[i])) + tr(" x threshold")
                          : m == ErrorMetric::RelativeForce ? QString::fromStdString(hb::percent(values[i]))
                          : m == ErrorMetric::Direction   ? QString::fromStdString(hb::sig(values[i])) + " deg"
                                                          : QString::fromStdString(hb::percent(values[i])) + tr(" disagree");
    auto* item = new QListWidgetItem(tr("%1  at vertex %2 (%3, %4, %5)")
                                         .arg(value)
                                         .arg(i)
                                         .arg(QString::fromStdString(hb::sig(p[0])))
                                         .arg(QString::fromStdString(hb::sig(p[1])))
                                         .arg(QString::fromStdString(hb::sig(p[2]))));
    item->setData(Qt::UserRole, QVariantList{p[0], p[1], p[2], n[0], n[1], n[2], qulonglong(i)});
    worst_->addItem(item);
  }
  if (k == 0) worst_->addItem(tr("(no vertex with an error for this metric)"));
}
