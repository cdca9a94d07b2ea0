// MainWindow's preferences that persist between runs (QSettings): the window's geometry and
// dock layout, the bake settings, Bake on Open, the orientation axes, the screenshot options.
#include "MainWindow.h"
#include "BakePanel.h"
#include "ProbeView.h"
#include <QAction>
#include <QSettings>
#include <algorithm>

namespace {
constexpr int kLayoutVersion = 2;  ///< saveState/restoreState: bump when the docks or toolbars change
}  // namespace

void MainWindow::savePreferences() {
  QSettings settings;
  settings.setValue(QStringLiteral("window/geometry"), saveGeometry());
  settings.setValue(QStringLiteral("window/state"), saveState(kLayoutVersion));
  bake_->applySettings();
  const BakeSettings& b = session_->bakeSettings();
  settings.beginGroup(QStringLiteral("bake"));
  settings.setValue(QStringLiteral("advanced"), b.advanced);
  settings.setValue(QStringLiteral("m"), b.m);
  settings.setValue(QStringLiteral("n"), b.n);
  settings.setValue(QStringLiteral("padding"), b.padding);
  settings.setValue(QStringLiteral("pieces"), int(b.pieces));
  settings.setValue(QStringLiteral("piecesFile"), b.piecesFile);
  settings.setValue(QStringLiteral("codec"), b.codec);
  settings.setValue(QStringLiteral("refine"), b.refine);
  settings.setValue(QStringLiteral("cache"), b.useCache);
  settings.endGroup();
  settings.setValue(QStringLiteral("view/bakeOnOpen"), bakeOnOpen_);
  settings.setValue(QStringLiteral("view/orientationAxes"), view_->orientationAxesVisible());
  settings.setValue(QStringLiteral("screenshot/magnification"), shotMagnification_);
  settings.setValue(QStringLiteral("screenshot/transparent"), shotTransparent_);
}

void MainWindow::restorePreferences() {
  QSettings settings;
  // The docks first, then the geometry: restoring the docks may resize the window.
  if (settings.contains(QStringLiteral("window/state")))
    restoreState(settings.value(QStringLiteral("window/state")).toByteArray(), kLayoutVersion);
  if (settings.contains(QStringLiteral("window/geometry")))
    restoreGeometry(settings.value(QStringLiteral("window/geometry")).toByteArray());
  BakeSettings b = session_->bakeSettings();
  settings.beginGroup(QStringLiteral("bake"));
  // Out-of-range values (an edited file, another version) fall back to the defaults.
  b.advanced = settings.value(QStringLiteral("advanced"), b.advanced).toBool();
  const int m = settings.value(QStringLiteral("m"), b.m).toInt(), n = settings.value(QStringLiteral("n"), b.n).toInt();
  if (m >= 2 && m <= 256) b.m = m;
  if (n >= 2 && n <= 64) b.n = n;
  const float padding = settings.value(QStringLiteral("padding"), b.padding).toFloat();
  if (padding >= 0.f && padding <= 0.5f) b.padding = padding;
  const int pieces = settings.value(QStringLiteral("pieces"), int(b.pieces)).toInt();
  if (pieces >= 0 && pieces <= 2) b.pieces = static_cast<BakeSettings::Pieces>(pieces);
  b.piecesFile = settings.value(QStringLiteral("piecesFile"), b.piecesFile).toString();
  const QString codec = settings.value(QStringLiteral("codec"), b.codec).toString();
  if (codec == QLatin1String("none") || codec == QLatin1String("block") || codec == QLatin1String("haar")) b.codec = codec;
  b.refine = settings.value(QStringLiteral("refine"), b.refine).toBool();
  b.useCache = settings.value(QStringLiteral("cache"), b.useCache).toBool();
  settings.endGroup();
  session_->setBakeSettings(b);
  bake_->showSettings();
  bakeOnOpenAction_->setChecked(settings.value(QStringLiteral("view/bakeOnOpen"), bakeOnOpen_).toBool());
  axesAction_->setChecked(settings.value(QStringLiteral("view/orientationAxes"), true).toBool());
  shotMagnification_ = std::clamp(settings.value(QStringLiteral("screenshot/magnification"), 1).toInt(), 1, 8);
  shotTransparent_ = settings.value(QStringLiteral("screenshot/transparent"), false).toBool();
}
