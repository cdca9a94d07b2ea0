#include "StabilityPanel.h"
#include "BackgroundJob.h"
#include "HapticSession.h"
#include "stability/stability_suite.h"
#include "figure_text.h"
#include <QCheckBox>
#include <QComboBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QSpinBox>
#include <QTableWidget>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

namespace {

QString figure(double v) { return std::isnan(v) ? QStringLiteral("-") : QString::fromStdString(hb::sig(v, 4)); }

QString threshold(const hb::StabilityMetric& m) {
  switch (m.rule) {
    case hb::StabilityRule::at_most: return QStringLiteral("<= ") + figure(m.threshold);
    case hb::StabilityRule::at_least: return QStringLiteral(">= ") + figure(m.threshold);
    case hb::StabilityRule::within: return QStringLiteral("= ") + figure(m.threshold) + QStringLiteral(" +- ") + figure(m.tolerance);
    case hb::StabilityRule::difference_at_most: return QStringLiteral("box - exact <= ") + figure(m.threshold);
    case hb::StabilityRule::info: return QStringLiteral("-");
  }
  return QStringLiteral("?");
}

}  // namespace

StabilityPanel::StabilityPanel(HapticSession* session, QWidget* parent)
    : QWidget(parent), session_(session), sites_(new QSpinBox), generated_(new QCheckBox(tr("Also generated walls, plates and grooves"))), law_(new QComboBox), run_(new QPushButton(tr("Run Stability Suite"))),
      summary_(new QLabel), table_(new QTableWidget(0, 7)) {
  sites_->setRange(1, 1000);
  sites_->setValue(12);
  sites_->setToolTip(tr("Trajectories per test on the model (surface points by area), as hapticbox stability --sites"));
  law_->addItem(tr("Penalty (depth law on each answer)"), int(hb::ContactLaw::penalty));
  law_->addItem(tr("Proxy (god-object)"), int(hb::ContactLaw::proxy));
  law_->setToolTip(tr("How answers become forces along the trajectories, box and exact alike "
                      "(hapticbox stability --law): the proxy stays calm in crisp creases"));
  run_->setToolTip(tr("The calibration gate, then T1-T8 on the model and on generated walls, plates and grooves: "
                      "the box and exact Embree on the same trajectories (docs/stability.md)"));
  summary_->setWordWrap(true);
  summary_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  summary_->setText(tr("Bake the boxes, then run the suite (as hapticbox stability BOX MESH)"));
  table_->setHorizontalHeaderLabels(
      {tr("Test"), tr("Scene"), tr("Metric"), tr("Box"), tr("Exact"), tr("Threshold"), tr("Verdict")});
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->setSelectionBehavior(QAbstractItemView::SelectRows);
  table_->verticalHeader()->hide();
  table_->horizontalHeader()->setStretchLastSection(true);
  table_->setWordWrap(false);
  table_->setTextElideMode(Qt::ElideRight);
  table_->verticalHeader()->setDefaultSectionSize(table_->fontMetrics().height() + 6);
  // A dock below the view: at least five rows show (a header and two rows told nothing), no
  // more, so it does not force the window taller than a laptop's screen.
  table_->setMinimumHeight(table_->horizontalHeader()->sizeHint().height() + 5 * table_->verticalHeader()->defaultSectionSize() +
                           2 * table_->frameWidth());
  auto* form = new QFormLayout;
  form->addRow(tr("Sites per test"), sites_);
  form->addRow(tr("Contact law"), law_);
  generated_->setChecked(true);
  form->addRow(generated_);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(form);
  layout->addWidget(run_);
  layout->addWidget(summary_);
  layout->addWidget(table_, 1);
  connect(run_, &QPushButton::clicked, this, [this] {
    QString error;
    const auto law = static_cast<hb::ContactLaw>(law_->currentData().toInt());
    if (!session_->startStability(static_cast<std::size_t>(sites_->value()), generated_->isChecked(), &error, law))
      emit message(error);
    updateState();
  });
  connect(session_, &HapticSession::stabilityChanged, this, &StabilityPanel::showReport);
  connect(session_, &HapticSession::boxesChanged, this, &StabilityPanel::updateState);
  connect(session_, &HapticSession::jobFinished, this, &StabilityPanel::updateState);
  connect(session_->job(), &BackgroundJob::started, this, &StabilityPanel::updateState);
  updateState();
}

void StabilityPanel::updateState() { run_->setEnabled(session_->hasBoxes() && !session_->job()->isRunning()); }

void StabilityPanel::showReport() {
  const hb::StabilityReport* r = session_->stabilityReport();
  if (!r) return;
  std::vector<const hb::StabilityMetric*> rows;
  for (const auto& m : r->calibration) rows.push_back(&m);
  for (const auto& m : r->metrics) rows.push_back(&m);
  table_->setRowCount(static_cast<int>(rows.size()));
  for (int i = 0; i < static_cast<int>(rows.size()); ++i) {
    const hb::StabilityMetric& m = *rows[static_cast<std::size_t>(i)];
    const QString metric = QString::fromStdString(m.metric) + (m.unit.empty() ? QString() : QStringLiteral(" [%1]").arg(QString::fromStdString(m.unit)));
    const QStringList cells = {QString::fromStdString(m.test), QString::fromStdString(m.scene), metric, figure(m.box),
                               figure(m.exact), threshold(m), QString::fromStdString(m.verdict)};
    for (int c = 0; c < cells.size(); ++c) {
      auto* item = new QTableWidgetItem(cells[c]);
      if (c == 2) item->setToolTip(cells[c]);
      if (c == 6 && m.rule != hb::StabilityRule::info)
        item->setForeground(m.pass ? QColor(0x1a, 0x7f, 0x37) : m.exact_pass ? QColor(0xc0, 0x00, 0x00) : QColor(0xa0, 0x60, 0x00));
      table_->setItem(i, c, item);
    }
  }
  // The metric names are sentences: a narrow, elided column (the whole text in its tooltip)
  // keeps box, exact, threshold and verdict in view in the dock.
  table_->resizeColumnsToContents();
  table_->setColumnWidth(1, std::min(table_->columnWidth(1), 110));
  table_->setColumnWidth(2, std::min(table_->columnWidth(2), 420));
  summary_->setText(tr("%1: calibration %2; %3 passed, %4 failed (box), %5 failed by the law (exact fails too); "
                       "%6 device, %7 law, filter %8; %9")
                        .arg(QFileInfo(session_->meshPath()).fileName())
                        .arg(r->calibration_pass ? tr("pass") : tr("FAIL"))
                        .arg(r->passed)
                        .arg(r->failed - std::min(r->failed, r->failed_law))
                        .arg(r->failed_law)
                        .arg(QString::fromStdString(r->device))
                        .arg(QString::fromStdString(r->contact_law))
                        .arg(QString::fromStdString(r->filter))
                        .arg(QString::fromStdString(hb::duration_text(r->seconds))));
}
