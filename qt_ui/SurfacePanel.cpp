#include "SurfacePanel.h"
#include "figure_text.h"
#include "volume_preview.h"
#include <QFile>
#include <QTimer>
#include <QtConcurrent/QtConcurrentRun>
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QMouseEvent>
#include <QPainter>
#include <QPushButton>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

// --- histogram -------------------------------------------------------------------------

VolumeHistogramView::VolumeHistogramView(QWidget* parent) : QWidget(parent) {
  setMinimumHeight(90);
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Fixed);
  setCursor(Qt::CrossCursor);
  setToolTip(tr("Voxels per value (log scale). Dashed: the Otsu threshold (the automatic iso-value); "
                "solid: the iso-value. Click or drag to choose it."));
}

void VolumeHistogramView::setHistogram(const hb::vtk::VolumeHistogram& histogram, double otsu) {
  histogram_ = histogram;
  otsu_ = otsu;
  update();
}

void VolumeHistogramView::setIso(double iso) {
  iso_ = iso;
  update();
}

QRect VolumeHistogramView::plotRect() const { return rect().adjusted(4, 16, -4, -16); }

int VolumeHistogramView::xOf(double value) const {
  const QRect r = plotRect();
  if (!(histogram_.hi > histogram_.lo)) return r.left();
  return r.left() + int(std::lround((value - histogram_.lo) / (histogram_.hi - histogram_.lo) * r.width()));
}

double VolumeHistogramView::valueAt(int x) const {
  const QRect r = plotRect();
  const double f = std::clamp(double(x - r.left()) / std::max(1, r.width()), 0.0, 1.0);
  return histogram_.lo + f * (histogram_.hi - histogram_.lo);
}

void VolumeHistogramView::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), Qt::white);
  const QRect r = plotRect();
  if (histogram_.counts.empty()) {
    p.drawText(rect(), Qt::AlignCenter, tr("no volume"));
    return;
  }
  double top = 0;
  for (double c : histogram_.counts) top = std::max(top, std::log10(1.0 + c));
  const int n = int(histogram_.counts.size());
  p.setPen(Qt::NoPen);
  p.setBrush(QColor(150, 150, 150));
  for (int b = 0; b < n; ++b) {
    const double h = top > 0 ? std::log10(1.0 + histogram_.counts[std::size_t(b)]) / top : 0.0;
    const int x0 = r.left() + b * r.width() / n, x1 = r.left() + (b + 1) * r.width() / n;
    const int y = r.bottom() - int(h * r.height());
    p.drawRect(QRect(QPoint(x0, y), QPoint(std::max(x0, x1 - 1), r.bottom())));
  }
  p.setPen(Qt::black);
  const QString unit = QStringLiteral(" ");
  p.drawText(QRect(r.left(), r.bottom() + 1, r.width(), 15), Qt::AlignLeft | Qt::AlignTop, QString::number(histogram_.lo, 'g', 5));
  p.drawText(QRect(r.left(), r.bottom() + 1, r.width(), 15), Qt::AlignRight | Qt::AlignTop, QString::number(histogram_.hi, 'g', 5));
  const int xo = xOf(otsu_), xi = xOf(iso_);
  p.setPen(QPen(QColor(214, 39, 40), 1.5, Qt::DashLine));
  p.drawLine(xo, r.top(), xo, r.bottom());
  p.setPen(QPen(QColor(31, 119, 180), 2.0));
  p.drawLine(xi, r.top() - 2, xi, r.bottom());
  // Labels above the plot, each on the side away from the other.
  const QString otsuText = tr("Otsu %1").arg(otsu_, 0, 'f', 0), isoText = tr("iso %1").arg(iso_, 0, 'f', 0);
  const bool isoRight = xi >= xo;
  p.setPen(QColor(214, 39, 40));
  p.drawText(QRect(isoRight ? 0 : xo + 3, 0, isoRight ? xo - 3 : width() - xo - 3, 15),
             (isoRight ? Qt::AlignRight : Qt::AlignLeft) | Qt::AlignVCenter, otsuText);
  p.setPen(QColor(31, 119, 180));
  p.drawText(QRect(isoRight ? xi + 3 : 0, 0, isoRight ? width() - xi - 3 : xi - 3, 15),
             (isoRight ? Qt::AlignLeft : Qt::AlignRight) | Qt::AlignVCenter, isoText);
}

void VolumeHistogramView::mousePressEvent(QMouseEvent* event) {
  if (event->button() == Qt::LeftButton && !histogram_.counts.empty()) emit isoChosen(valueAt(event->pos().x()));
}

void VolumeHistogramView::mouseMoveEvent(QMouseEvent* event) {
  if ((event->buttons() & Qt::LeftButton) && !histogram_.counts.empty()) emit isoChosen(valueAt(event->pos().x()));
}

// --- panel -----------------------------------------------------------------------------

SurfacePanel::SurfacePanel(HapticSession* session, QWidget* parent)
    : QWidget(parent), session_(session), facts_(new QLabel), histogram_(new VolumeHistogramView), iso_(new QDoubleSpinBox),
      otsu_(new QPushButton(tr("Otsu"))), useLabel_(new QCheckBox(tr("Label"))), label_(new QSpinBox), smooth_(new QSpinBox),
      target_(new QSpinBox), extract_(new QPushButton(tr("Extract Surface"))), status_(new QLabel),
      previewOn_(new QCheckBox(tr("Live preview"))), previewTimer_(new QTimer(this)),
      previewWatcher_(new QFutureWatcher<PreviewResult>(this)) {
  for (QLabel* l : {facts_, status_}) {
    l->setWordWrap(true);
    l->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  }
  iso_->setDecimals(1);
  iso_->setRange(-1e9, 1e9);
  iso_->setToolTip(tr("Iso-value in the file's calibrated units (Hounsfield units for CT): the surface where the "
                      "values cross it (hapticbox --volume iso=V)"));
  otsu_->setToolTip(tr("Back to the Otsu threshold of the histogram (the automatic iso-value)"));
  label_->setRange(-1000000, 1000000);
  label_->setEnabled(false);
  useLabel_->setToolTip(tr("A label map: the boundary of the voxels holding this label (hapticbox --volume label=L)"));
  smooth_->setRange(0, 1000);
  smooth_->setToolTip(tr("Windowed-sinc smoothing iterations (0: none; 10-30 removes voxel steps and moves the "
                         "surface by well under a voxel; hapticbox --volume smooth=N)"));
  target_->setRange(0, 20000000);
  target_->setSingleStep(10000);
  target_->setSpecialValueText(tr("all"));
  target_->setToolTip(tr("Decimate to about this many triangles (all: keep every triangle; hapticbox --volume triangles=N)"));
  auto* isoRow = new QHBoxLayout;
  isoRow->addWidget(iso_, 1);
  isoRow->addWidget(otsu_);
  auto* labelRow = new QHBoxLayout;
  labelRow->addWidget(useLabel_);
  labelRow->addWidget(label_, 1);
  auto* form = new QFormLayout;
  form->setRowWrapPolicy(QFormLayout::WrapLongRows);
  form->addRow(tr("Iso-value"), isoRow);
  form->addRow(QString(), labelRow);
  form->addRow(tr("Smoothing"), smooth_);
  form->addRow(tr("Triangles"), target_);
  auto* layout = new QVBoxLayout(this);
  layout->addWidget(facts_);
  layout->addWidget(histogram_);
  layout->addLayout(form);
  previewOn_->setChecked(true);
  previewOn_->setToolTip(tr("Show the surface of the iso-value, label and smoothing in the 3D view as they change (from "
                            "a reduced copy of the volume, on a worker thread), before Extract Surface makes it the model"));
  layout->addWidget(previewOn_);
  layout->addWidget(extract_);
  layout->addWidget(status_);
  layout->addStretch(1);

  connect(histogram_, &VolumeHistogramView::isoChosen, this, [this](double v) {
    useLabel_->setChecked(false);
    iso_->setValue(v);
  });
  connect(iso_, qOverload<double>(&QDoubleSpinBox::valueChanged), histogram_, &VolumeHistogramView::setIso);
  connect(otsu_, &QPushButton::clicked, this, [this] {
    useLabel_->setChecked(false);
    iso_->setValue(session_->model()->otsu());
  });
  connect(useLabel_, &QCheckBox::toggled, this, [this](bool on) {
    label_->setEnabled(on);
    iso_->setEnabled(!on);
  });
  connect(extract_, &QPushButton::clicked, this, [this] { emit extractRequested(options()); });
  // The live preview: debounced, computed off the GUI thread, the latest options winning.
  previewTimer_->setSingleShot(true);
  previewTimer_->setInterval(kPreviewDebounceMs);
  connect(previewTimer_, &QTimer::timeout, this, &SurfacePanel::startPreview);
  connect(previewWatcher_, &QFutureWatcher<PreviewResult>::finished, this, &SurfacePanel::previewFinished);
  connect(iso_, qOverload<double>(&QDoubleSpinBox::valueChanged), this, &SurfacePanel::schedulePreview);
  connect(label_, qOverload<int>(&QSpinBox::valueChanged), this, &SurfacePanel::schedulePreview);
  connect(smooth_, qOverload<int>(&QSpinBox::valueChanged), this, &SurfacePanel::schedulePreview);
  connect(useLabel_, &QCheckBox::toggled, this, &SurfacePanel::schedulePreview);
  connect(previewOn_, &QCheckBox::toggled, this, [this](bool on) {
    if (on) schedulePreview();
    else clearPreview();
  });
  showModel();
}

bool SurfacePanel::previewPending() const { return previewTimer_->isActive() || previewWatcher_->isRunning(); }

QString SurfacePanel::statusText() const { return status_->text(); }

void SurfacePanel::schedulePreview() {
  if (showing_ || !previewOn_->isChecked() || !session_->hasMesh() || !session_->model()->volume()) return;
  previewTimer_->start();  // restarted by every change: computed once the controls rest
}

void SurfacePanel::startPreview() {
  if (previewWatcher_->isRunning()) {
    previewAgain_ = true;  // one more with the latest options when this one ends
    return;
  }
  std::shared_ptr<const hb::vtk::Volume> volume = session_->model()->volume();
  if (!volume) return;
  const hb::vtk::VolumeSurfaceOptions o = options().volume;
  const std::string path = QFile::encodeName(session_->meshPath()).toStdString();
  const unsigned generation = generation_;
  status_->setText(surfaceText_ + QStringLiteral("\n") + tr("Preview: computing..."));
  previewWatcher_->setFuture(QtConcurrent::run([volume, o, path, generation] {
    PreviewResult r;
    r.generation = generation;
    try {
      const hb::vtk::VolumePreview p = hb::vtk::volume_preview_surface(*volume, o, path);
      r.surface = p.surface;
      r.shrink = p.shrink;
      r.seconds = p.seconds;
    } catch (const std::exception& e) {
      r.error = QString::fromStdString(e.what());
    }
    return r;
  }));
}

void SurfacePanel::previewFinished() {
  const PreviewResult r = previewWatcher_->result();
  if (previewAgain_) {
    previewAgain_ = false;
    startPreview();
    return;
  }
  if (r.generation != generation_ || !previewOn_->isChecked()) return;  // another model opened meanwhile
  if (!r.error.isEmpty() || !r.surface) {
    previewTriangles_ = 0;
    status_->setText(surfaceText_ + QStringLiteral("\n") + tr("Preview: %1").arg(r.error));
    emit previewChanged(nullptr, QString());
    return;
  }
  previewTriangles_ = std::size_t(r.surface->GetNumberOfPolys());
  const hb::vtk::ModelOptions o = options();
  const QString at = o.volume.label ? tr("label %1").arg(*o.volume.label) : tr("iso %1").arg(*o.volume.iso, 0, 'f', 1);
  const QString resolution = r.shrink > 1 ? tr("volume at 1/%1 resolution").arg(r.shrink) : tr("full resolution");
  const QString caption = tr("Preview at %1, smoothing %2: %3 triangles (%4, %5). Extract Surface makes it the model.")
                              .arg(at)
                              .arg(o.volume.smooth_iterations)
                              .arg(QString::fromStdString(hb::sig(double(previewTriangles_), 6)))
                              .arg(resolution)
                              .arg(QString::fromStdString(hb::duration_text(r.seconds)));
  status_->setText(surfaceText_ + QStringLiteral("\n") + caption);
  emit previewChanged(r.surface, tr("Preview at %1: %2 triangles (Extract Surface to use it)")
                                     .arg(at, QString::fromStdString(hb::sig(double(previewTriangles_), 6))));
}

void SurfacePanel::clearPreview() {
  previewTimer_->stop();
  previewAgain_ = false;
  previewTriangles_ = 0;
  status_->setText(surfaceText_);
  emit previewChanged(nullptr, QString());
}

hb::vtk::ModelOptions SurfacePanel::options() const {
  hb::vtk::ModelOptions o = session_->hasMesh() ? session_->model()->modelOptions() : hb::vtk::ModelOptions{};
  o.volume.iso.reset();
  o.volume.label.reset();
  if (useLabel_->isChecked()) o.volume.label = label_->value();
  else o.volume.iso = iso_->value();
  o.volume.smooth_iterations = smooth_->value();
  o.volume.target_triangles = std::size_t(target_->value());
  return o;
}

void SurfacePanel::showModel() {
  // Filling the controls is no change of the user's: no preview for it; an older one goes.
  struct Showing {
    bool& flag;
    explicit Showing(bool& f) : flag(f) { flag = true; }
    ~Showing() { flag = false; }
  } showing(showing_);
  ++generation_;
  surfaceText_.clear();
  clearPreview();
  const bool volume = session_->hasMesh() && session_->model()->isVolume();
  for (QWidget* w : std::initializer_list<QWidget*>{histogram_, iso_, otsu_, useLabel_, smooth_, target_, extract_, previewOn_})
    w->setEnabled(volume);
  label_->setEnabled(volume && useLabel_->isChecked());
  if (!volume) {
    facts_->setText(session_->hasMesh() ? tr("%1 is a surface, not a volume: nothing to choose here.")
                                               .arg(QFileInfo(session_->meshPath()).fileName())
                                        : tr("Open a volume (CT or MR: NIfTI, MetaImage, NRRD, File > Open DICOM Folder) "
                                             "to choose which of its surfaces becomes the model."));
    histogram_->setHistogram({}, 0.0);
    status_->clear();
    return;
  }
  const SessionModel* m = session_->model();
  const nlohmann::json& f = m->modelFacts();
  QString dims;
  if (f.contains("dimensions") && f["dimensions"].size() == 3)
    dims = tr("%1 x %2 x %3 voxels").arg(f["dimensions"][0].get<long>()).arg(f["dimensions"][1].get<long>()).arg(f["dimensions"][2].get<long>());
  QString spacing;
  if (f.contains("spacing_mm") && f["spacing_mm"].size() == 3)
    spacing = tr(" of %1 x %2 x %3 mm").arg(f["spacing_mm"][0].get<double>(), 0, 'g', 3).arg(f["spacing_mm"][1].get<double>(), 0, 'g', 3).arg(f["spacing_mm"][2].get<double>(), 0, 'g', 3);
  const hb::vtk::VolumeHistogram& h = m->histogram();
  facts_->setText(tr("%1, %2: %3%4; values %5 to %6 (calibrated: HU for CT)")
                      .arg(QFileInfo(session_->meshPath()).fileName(), QString::fromStdString(f.value("format", std::string("volume"))),
                           dims, spacing)
                      .arg(h.lo, 0, 'g', 5)
                      .arg(h.hi, 0, 'g', 5));
  histogram_->setHistogram(h, m->otsu());
  iso_->setRange(h.lo, h.hi);
  const hb::vtk::ModelOptions& o = m->modelOptions();
  useLabel_->setChecked(o.volume.label.has_value());
  if (o.volume.label) label_->setValue(int(*o.volume.label));
  label_->setEnabled(useLabel_->isChecked());
  iso_->setEnabled(!useLabel_->isChecked());
  iso_->setValue(f.contains("iso") ? f["iso"].get<double>() : m->otsu());
  histogram_->setIso(iso_->value());
  smooth_->setValue(o.volume.smooth_iterations);
  target_->setValue(int(std::min<std::size_t>(o.volume.target_triangles, 20000000)));
  surfaceText_ = tr("Surface: %1 triangles at %2 (Otsu %3)")
                       .arg(session_->mesh().triangle_count())
                       .arg(o.volume.label ? tr("label %1").arg(*o.volume.label)
                                           : tr("iso %1%2").arg(iso_->value(), 0, 'f', 1).arg(o.volume.iso ? QString() : tr(", automatic")))
                       .arg(m->otsu(), 0, 'f', 1);
  status_->setText(surfaceText_);
}
