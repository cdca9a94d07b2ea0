#include "ReadoutPanel.h"
#include "series_colours.h"
#include "perception/perceptible.h"
#include "HapticSession.h"
#include <QFontDatabase>
#include <QFormLayout>
#include <QLabel>
#include "figure_text.h"

namespace {
QLabel* value() {
  auto* l = new QLabel(QStringLiteral("-"));
  l->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  l->setTextInteractionFlags(Qt::TextSelectableByMouse);
  // Readouts change ten times a second: they wrap in the dock's width, never widen it.
  l->setWordWrap(true);
  l->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  return l;
}
}  // namespace

ReadoutPanel::ReadoutPanel(QWidget* parent)
    : QWidget(parent), depth_(value()), exact_(value()), approx_(value()), error_(value()), angle_(value()),
      query_(value()), device_(value()), felt_(value()) {
  auto* form = new QFormLayout(this);
  // The series colours of the arrows, the charts and the report (series_colours.h).
  const auto css = [](const hb::SeriesColour& c) { return QStringLiteral("color: rgb(%1, %2, %3);").arg(c.r).arg(c.g).arg(c.b); };
  exact_->setStyleSheet(css(hb::kExactSeries));
  approx_->setStyleSheet(css(hb::kBoxSeries));
  form->addRow(tr("Depth"), depth_);
  form->addRow(tr("|F| exact"), exact_);
  form->addRow(tr("|F| haptic box"), approx_);
  form->addRow(tr("You would feel it"), felt_);
  felt_->setToolTip(tr("Whether a hand could tell the box's force from exact's (hapticbox eval's perceptible "
                       "difference): beyond max(10 % |F|, 0.04 N), 25 deg between firm forces, or a contact on one "
                       "side only above 0.04 N; forces at the model's workspace scale"));
  form->addRow(tr("Relative error"), error_);
  form->addRow(tr("Angle"), angle_);
  form->addRow(tr("Query time"), query_);
  form->addRow(tr("Device thread"), device_);
}

void ReadoutPanel::setReading(const ProbeReading& r) {
  if (!r.placed) {
    depth_->setText(modelOpen_ ? tr("drag on the model to place the probe")
                               : tr("no model open: File > Open (or drop a file here)"));
    for (QLabel* l : {exact_, approx_, error_, angle_, query_, felt_}) l->setText(QStringLiteral("-"));
  } else {
    depth_->setText(r.exact.contact || r.approx.contact
                        ? tr("%1 exact, %2 box (model units)").arg(r.exact.depth, 0, 'g', 4).arg(r.approx.depth, 0, 'g', 4)
                        : tr("no contact"));
    exact_->setText(r.exact.contact ? tr("%1 N").arg(r.exact.force.norm(), 0, 'f', 4) : tr("no contact"));
    approx_->setText(!r.haveBoxes ? tr("no boxes (bake first)")
                     : r.approx.contact ? tr("%1 N").arg(r.approx.force.norm(), 0, 'f', 4)
                                        : tr("no contact"));
    const bool both = r.exact.contact && r.approx.contact;
    if (!r.haveBoxes || !(r.exact.contact || r.approx.contact)) {
      felt_->setText(QStringLiteral("-"));
    } else {
      const hb::PerceivedDifference p = hb::perceive(r.exact, r.approx, hb::PerceptualThresholds{}, r.maxForceN);
      const QString against = tr("%1 N against %2 N")
                                  .arg(QString::fromStdString(hb::sig(p.magnitude_difference_n)))
                                  .arg(QString::fromStdString(hb::sig(p.magnitude_threshold_n)));
      felt_->setText(p.perceptible() ? tr("yes (%1): %2").arg(QString::fromStdString(hb::perceived_by_name(p.by)), against)
                                     : tr("no: %1").arg(against));
    }
    error_->setText(both ? tr("%1 %").arg(100.0 * r.relativeError, 0, 'f', 2)
                         : (r.exact.contact != r.approx.contact && r.haveBoxes ? tr("contacts disagree") : tr("-")));
    angle_->setText(both ? tr("%1 deg").arg(r.angleDeg, 0, 'f', 2) : tr("-"));
    // One timing story: both answers timed the same way (ProbeReading: GUI thread, this segment,
    // median of back-to-back queries, warm), as `hapticbox bench` times its queries.
    query_->setText(tr("exact %1, box %2 (median of %3 warm queries each, this segment, GUI thread)")
                        .arg(QString::fromStdString(hb::duration_text(r.exactQueryNs * 1e-9)))
                        .arg(r.haveBoxes ? QString::fromStdString(hb::duration_text(r.approxQueryNs * 1e-9)) : tr("-"))
                        .arg(ProbeReading::kTimingRepeats));
    query_->setToolTip(tr("Both answers are timed the same way: on the window's thread, on the probe's segment, "
                          "the median of %1 back-to-back queries each with warm caches, as hapticbox bench times "
                          "(which takes the median over many random segments: the report's figures).")
                           .arg(ProbeReading::kTimingRepeats));
  }
  if (r.deviceRunning)
    device_->setText(tr("%1: %2 Hz, p99 period %3 us, box query %4 a tick")
                         .arg(r.deviceName)
                         .arg(r.rateHz, 0, 'f', 1)
                         .arg(r.p99PeriodUs, 0, 'f', 0)
                         .arg(QString::fromStdString(hb::duration_text(r.servoQueryNs * 1e-9))));
  else
    device_->setText(r.haveBoxes ? tr("%1: stopped").arg(r.deviceName) : tr("not running (bake first)"));
}

void ReadoutPanel::setModelOpen(bool open) { modelOpen_ = open; }

QString ReadoutPanel::rowText(const QString& key) const {
  if (key == QLatin1String("depth")) return depth_->text();
  if (key == QLatin1String("exact")) return exact_->text();
  if (key == QLatin1String("approx")) return approx_->text();
  if (key == QLatin1String("error")) return error_->text();
  if (key == QLatin1String("angle")) return angle_->text();
  if (key == QLatin1String("query")) return query_->text();
  if (key == QLatin1String("device")) return device_->text();
  if (key == QLatin1String("felt")) return felt_->text();
  return {};
}
