#include "BakePanel.h"
#include "BackgroundJob.h"
#include "HapticSession.h"
#include "figure_text.h"
#include "scene/density_range.h"
#include "box/haptic_box.h"
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>

BakePanel::BakePanel(HapticSession* session, QWidget* parent) : QWidget(parent), session_(session) {
  recipe_ = new QComboBox;
  recipe_->addItem(tr("Default (error budget, as hapticbox bake)"), false);
  recipe_->addItem(tr("Advanced (the sampling below)"), true);
  recipe_->setItemData(0, tr("hb::default_recipe(): automatic pieces, n, cell and refinement chosen per piece to meet "
                             "the default error budget against exact Embree, block codec"), Qt::ToolTipRole);
  m_ = new QSpinBox;
  m_->setRange(2, 256);
  m_->setToolTip(tr("Position points per PBB face edge (m)"));
  n_ = new QSpinBox;
  n_->setRange(2, 64);
  n_->setToolTip(tr("Directional points per sub-block face edge (n)"));
  padding_ = new QDoubleSpinBox;
  padding_->setRange(0.0, 0.5);
  padding_->setDecimals(3);
  padding_->setSingleStep(0.005);
  padding_->setToolTip(tr("PBB padding, fraction of the box diagonal"));

  pieces_ = new QComboBox;
  pieces_->addItem(tr("None (one box)"), int(BakeSettings::Pieces::None));
  pieces_->addItem(tr("From a piece file"), int(BakeSettings::Pieces::File));
  pieces_->addItem(tr("Automatic"), int(BakeSettings::Pieces::Automatic));
  pieces_->setItemData(2, tr("Quasi-convex pieces by hb::decompose_auto (one box each)"), Qt::ToolTipRole);
  piecesFile_ = new QLineEdit;
  piecesFile_->setPlaceholderText(tr("one piece id per triangle"));
  browse_ = new QPushButton(tr("..."));
  browse_->setMaximumWidth(32);
  auto* fileRow = new QHBoxLayout;
  fileRow->setContentsMargins(0, 0, 0, 0);
  fileRow->addWidget(piecesFile_);
  fileRow->addWidget(browse_);

  codec_ = new QComboBox;
  codec_->addItem(tr("none (8-byte samples)"), QStringLiteral("none"));
  codec_->addItem(tr("block (ours, ~8:1 at 0.05% of the diagonal)"), QStringLiteral("block"));
  codec_->addItem(tr("haar (the paper's wavelet)"), QStringLiteral("haar"));
  refine_ = new QCheckBox(tr("Refine exactly on the mesh's triangles"));
  refine_->setToolTip(tr("Store the triangle each sample hit: a query then intersects the line with the few "
                         "triangles its samples name (and their neighbours) and answers exactly where it "
                         "finds the surface. 2-4 bytes more per sample; slower queries."));
  cache_ = new QCheckBox(tr("Use the box cache"));
  cacheInfo_ = new QLabel;
  cacheInfo_->setWordWrap(true);
  clearCache_ = new QPushButton(tr("Clear"));
  clearCache_->setToolTip(tr("Remove every cached box file (the boxes in use stay loaded)"));
  auto* cacheRow = new QHBoxLayout;
  cacheRow->setContentsMargins(0, 0, 0, 0);
  cacheRow->addWidget(cacheInfo_, 1);
  cacheRow->addWidget(clearCache_);
  size_ = new QLabel;
  // Texts that grow (sizes, cache, bake summary) wrap inside the dock instead of widening it
  // (and shrinking the 3D view): their width hint is ignored, their height follows the text.
  for (QLabel* l : {size_, cacheInfo_}) {
    l->setWordWrap(true);
    l->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  }
  const auto showSize = [this] {
    if (!recipe_->currentData().toBool()) {
      size_->setText(tr("chosen per piece by the error budget"));
      size_->setStyleSheet(QString());
      return;
    }
    hb::BoxParams p;
    p.m = m_->value();
    p.n = n_->value();
    const double mb = static_cast<double>(p.sample_count() * sizeof(hb::Sample)) / 1048576.0;
    const std::uint64_t ids = refine_->isChecked() ? p.sample_count() * 2u : 0u;  // 16-bit unless a piece spans > 65,535 triangles
    // Figures as the command line prints them (3 significant digits, decimal units).
    QString text = tr("%1 of tables per box, %2 rays per box")
                       .arg(QString::fromStdString(hb::bytes_text(p.sample_count() * sizeof(hb::Sample))))
                       .arg(QString::fromStdString(hb::count_text(static_cast<double>(p.sample_count()))));
    if (ids > 0) text += tr(", + %1 of triangle ids").arg(QString::fromStdString(hb::bytes_text(ids)));
    size_->setText(text);
    size_->setStyleSheet(mb > 1024.0 ? QStringLiteral("color: #c00000;") : QString());
  };
  connect(m_, QOverload<int>::of(&QSpinBox::valueChanged), this, showSize);
  connect(n_, QOverload<int>::of(&QSpinBox::valueChanged), this, showSize);
  connect(refine_, &QCheckBox::toggled, this, showSize);
  connect(recipe_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, showSize);

  bake_ = new QPushButton(tr("Bake"));
  bake_->setDefault(true);
  cancel_ = new QPushButton(tr("Cancel"));
  progress_ = new QProgressBar;
  progress_->setRange(0, 1000);
  progress_->setTextVisible(true);
  progress_->setFormat(QStringLiteral("%p%"));
  info_ = new QLabel;
  info_->setWordWrap(true);
  info_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  info_->setTextInteractionFlags(Qt::TextSelectableByMouse);

  auto* form = new QFormLayout;
  form->addRow(tr("Recipe"), recipe_);
  form->addRow(tr("Positions m"), m_);
  form->addRow(tr("Directions n"), n_);
  form->addRow(tr("Padding"), padding_);
  form->addRow(tr("Pieces"), pieces_);
  form->addRow(tr("Piece file"), fileRow);
  form->addRow(tr("Codec"), codec_);
  form->addRow(refine_);
  form->addRow(tr("Size"), size_);
  form->addRow(cache_);
  form->addRow(tr("Cache"), cacheRow);
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(bake_);
  buttons->addWidget(cancel_);
  auto* layout = new QVBoxLayout(this);
  layout->addLayout(form);
  layout->addLayout(buttons);
  layout->addWidget(progress_);
  layout->addWidget(info_);
  layout->addStretch(1);

  showSettings();
  showSize();
  connect(bake_, &QPushButton::clicked, this, &BakePanel::bake);
  connect(cancel_, &QPushButton::clicked, this, [this] { session_->job()->cancel(); });
  connect(browse_, &QPushButton::clicked, this, &BakePanel::browsePieces);
  connect(pieces_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, &BakePanel::updateState);
  connect(recipe_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, &BakePanel::updateState);
  connect(session_->job(), &BackgroundJob::progressChanged, this, [this](double f) {
    if (bakeRunning_) progress_->setValue(static_cast<int>(f * 1000.0));
  });
  connect(session_, &HapticSession::jobFinished, this, [this](const QString&, bool ok, const QString&) {
    if (bakeRunning_ && !ok) progress_->setValue(0);
    bakeRunning_ = false;
    updateState();
  });
  connect(session_, &HapticSession::boxesChanged, this, &BakePanel::updateState);
  connect(session_, &HapticSession::cacheChanged, this, &BakePanel::showCacheUsage);
  connect(clearCache_, &QPushButton::clicked, this, [this] {
    QString error;
    if (!session_->clearCache(&error)) emit message(error);
  });
  showCacheUsage();
  connect(session_, &HapticSession::meshChanged, this, &BakePanel::updateState);
  updateState();
}

void BakePanel::showSettings() {
  const BakeSettings& s = session_->bakeSettings();
  recipe_->setCurrentIndex(recipe_->findData(s.advanced));
  m_->setValue(s.m);
  n_->setValue(s.n);
  padding_->setValue(s.padding);
  pieces_->setCurrentIndex(pieces_->findData(int(s.pieces)));
  piecesFile_->setText(s.piecesFile);
  const int c = codec_->findData(s.codec);
  codec_->setCurrentIndex(c < 0 ? 0 : c);
  refine_->setChecked(s.refine);
  cache_->setChecked(s.useCache);
}

void BakePanel::applySettings() {
  BakeSettings s = session_->bakeSettings();
  s.advanced = recipe_->currentData().toBool();
  s.m = m_->value();
  s.n = n_->value();
  s.padding = static_cast<float>(padding_->value());
  s.pieces = static_cast<BakeSettings::Pieces>(pieces_->currentData().toInt());
  s.piecesFile = piecesFile_->text();
  s.codec = codec_->currentData().toString();
  s.refine = refine_->isChecked();
  s.useCache = cache_->isChecked();
  session_->setBakeSettings(s);
}

void BakePanel::bake() {
  applySettings();
  if (session_->bakeSettings().pieces == BakeSettings::Pieces::File && session_->bakeSettings().piecesFile.trimmed().isEmpty()) {
    emit message(tr("Pieces is set to 'From a piece file' but no piece file is chosen: choose one (...) or set Pieces to None"));
    return;
  }
  // Reopening with the same settings is instant: use the cache when it holds this bake.
  if (session_->bakeSettings().useCache && session_->loadCachedBoxes()) {
    progress_->setValue(1000);
    emit message(tr("Loaded the cached bake from %1").arg(session_->cacheDir()));
    return;
  }
  QString error;
  if (!session_->startBake(&error)) {
    emit message(error);
    return;
  }
  bakeRunning_ = true;
  progress_->setValue(0);
  updateState();
}

void BakePanel::showCacheUsage() {
  const hb::BoxCacheUsage u = session_->cacheUsage();
  cacheInfo_->setText(tr("%1 box file(s), %2 MB").arg(u.files).arg(static_cast<double>(u.bytes) / 1e6, 0, 'f', 1));
  cacheInfo_->setToolTip(session_->cacheDir());
  clearCache_->setEnabled(u.files > 0);
}

void BakePanel::browsePieces() {
  const QString path = QFileDialog::getOpenFileName(this, tr("Piece file"), QFileInfo(session_->meshPath()).absolutePath(),
                                                    tr("Piece files (*.txt *.pieces);;All files (*)"));
  if (!path.isEmpty()) piecesFile_->setText(path);
}

void BakePanel::updateState() {
  const bool busy = session_->job()->isRunning();
  bake_->setEnabled(session_->hasMesh() && !busy);
  cancel_->setEnabled(bakeRunning_);
  const bool advanced = recipe_->currentData().toBool();
  for (QWidget* w : std::initializer_list<QWidget*>{m_, n_, padding_, pieces_, codec_, refine_}) w->setEnabled(advanced);
  const bool file = advanced && pieces_->currentData().toInt() == int(BakeSettings::Pieces::File);
  piecesFile_->setEnabled(file);
  browse_->setEnabled(file);
  if (!session_->hasBoxes()) {
    info_->setText(session_->hasMesh() ? tr("No boxes yet: bake to start the device thread") : QString());
    return;
  }
  if (!busy) progress_->setValue(1000);
  const hb::BoxScene& s = *session_->boxes();
  const std::size_t refineBytes = s.bytes().refinement;
  // A scene answered by exact Embree keeps its boxes as frames (no tables): say so, not "0 B".
  const QString tables = has_tables(s.parts()) ? tr("%1 of tables").arg(QString::fromStdString(hb::bytes_text(s.bytes().tables)))
                                        : tr("box frames (no tables: exact Embree answers)");
  // A scene's boxes have their own densities: the range, not the first box's.
  const hb::DensityRange d = hb::density_range(s);
  const auto span = [](int lo, int hi) { return QString::fromStdString(hb::range_text(lo, hi)); };
  // The device's probe asks with its state: say when exact Embree over the full mesh answers it.
  const QString strokes = strokes_by_full_mesh(s)
                              ? tr(" + %1 of full mesh: the device's strokes by exact Embree (faster there)")
                                    .arg(QString::fromStdString(hb::bytes_text(s.bytes().embree)))
                              : QString();
  info_->setText(tr("%1 box(es), m %2, n %3, %4%5, %6")
                     .arg(s.parts().boxes.size())
                     .arg(span(d.m_min, d.m_max))
                     .arg(span(d.n_min, d.n_max))
                     .arg(refineBytes > 0 ? tables + tr(" + %1 for exact refinement")
                                                         .arg(QString::fromStdString(hb::bytes_text(refineBytes)))
                                          : tables)
                     .arg(strokes)
                     .arg(session_->boxesFromCache() ? tr("from the cache")
                                                     : tr("baked in %1 in all").arg(QString::fromStdString(hb::duration_text(session_->bakeSeconds())))));
}
