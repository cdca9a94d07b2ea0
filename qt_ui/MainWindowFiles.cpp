// MainWindow's files: opening a model, a box file or a session (dialogs, drops, the recent
// list, the last folder), saving box files and sessions, and exporting screenshots and reports.
#include "MainWindow.h"
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "DevicePanel.h"
#include "ErrorFieldPanel.h"
#include "ProbeView.h"
#include "ScreenshotDialog.h"
#include "SessionFile.h"
#include "SessionPipeline.h"
#include <QAction>
#include <QApplication>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QMenu>
#include <QMessageBox>
#include <QPushButton>
#include <QSettings>
#include <optional>

namespace {
constexpr int kMaxRecent = 8;
}  // namespace

bool MainWindow::openFile(const QString& path, bool interactive, const hb::vtk::ModelOptions& options) {
  if (isSessionPath(path)) {
    return openSessionFile(path, interactive);
  }
  bakeOnOpenFailed_ = false;
  QApplication::setOverrideCursor(Qt::WaitCursor);
  QString error;
  const bool ok = session_->openMesh(path, &error, options);
  QApplication::restoreOverrideCursor();
  if (!ok) {
    // One sentence naming the file and the cause (the reader's message usually starts with the path).
    showMessage(error.startsWith(path) ? tr("Cannot open %1").arg(error) : tr("Cannot open %1: %2").arg(path, error), true);
    if (interactive) QMessageBox::warning(this, tr("Cannot open"), lastError_);
    return false;
  }
  addRecentFile(session_->meshPath());
  rememberFolder(session_->meshPath());
  if (!session_->hasBoxes() && bakeOnOpen_) {
    // A bake that cannot start (a piece file gone, settings refused) is an error of the open.
    QString why;
    const auto capture = connect(bake_, &BakePanel::message, this, [&why](const QString& m) { why = m; });
    bake_->bakeButton()->click();
    disconnect(capture);
    if (!session_->job()->isRunning() && !session_->hasBoxes()) {
      bakeOnOpenFailed_ = true;
      showMessage(tr("Bake of %1 failed: %2").arg(session_->meshPath(), why.isEmpty() ? tr("it did not start") : why), true);
      if (interactive) QMessageBox::warning(this, tr("Bake failed"), lastError_);
    }
  }
  return true;
}

void MainWindow::openDialog() {
  const QString p = QFileDialog::getOpenFileName(this, tr("Open model"), lastFolder(),
                                                 HapticSession::meshFileFilter() + tr(";;Sessions (*.hbsession)"));
  if (!p.isEmpty()) openFile(p, true);
}

void MainWindow::openDicomFolderDialog() {
  // A DICOM series is a folder of (often extension-less) files: choose the folder.
  const QString d = QFileDialog::getExistingDirectory(this, tr("Open DICOM folder"), lastFolder());
  if (!d.isEmpty()) openFile(d, true);
}

void MainWindow::openBoxDialog() {
  const QString p = QFileDialog::getOpenFileName(this, tr("Open box file"), lastFolder(), tr("Box files (*.hbox)"));
  if (p.isEmpty()) return;
  rememberFolder(p);
  QString error;
  if (!session_->openBoxFile(p, &error)) {
    showMessage(error, true);
    QMessageBox::warning(this, tr("Cannot open the box file"), error);
  }
}

void MainWindow::saveBoxDialog() {
  const QString p = QFileDialog::getSaveFileName(this, tr("Save box file"), lastFolder(), tr("Box files (*.hbox)"));
  if (p.isEmpty()) return;
  rememberFolder(p);
  QString error;
  if (!session_->saveBoxFile(p, &error)) showMessage(error, true);
  else showMessage(tr("Saved %1").arg(p));
}

bool MainWindow::openSessionFile(const QString& path, bool interactive) {
  SessionState s;
  try {
    s = loadSessionFile(path);
  } catch (const std::exception& e) {
    showMessage(QString::fromStdString(e.what()), true);
    if (interactive) QMessageBox::warning(this, tr("Cannot open the session"), QString::fromStdString(e.what()));
    return false;
  }
  session_->setBakeSettings(s.bake);
  bake_->showSettings();
  const bool bakeOnOpen = bakeOnOpen_;
  bakeOnOpen_ = s.baked;
  hb::vtk::ModelOptions options;
  if (s.hasSurface) options.volume = s.surface;  // the saved iso-value or label, smoothing, triangles
  const bool ok = openFile(s.meshPath, interactive, options);
  bakeOnOpen_ = bakeOnOpen;
  if (!ok) {
    showMessage(tr("Cannot open the session %1: %2").arg(path, lastError_), true);
    return false;
  }
  session_->setProbeDirection(hb::Vec3(s.probeDirection[0], s.probeDirection[1], s.probeDirection[2]));
  session_->setTiltDegrees(s.tiltDegrees);
  session_->setDepthFraction(s.depthFraction);
  if (s.hasProbe) session_->setProbeTarget(hb::Vec3(s.probePoint[0], s.probePoint[1], s.probePoint[2]));
  device_->showDepth();
  errorPanel_->setMetric(s.metric);
  if (s.hasCamera) view_->setCameraState(s.camera);
  outlinesAction_->setChecked(s.outlines);
  addRecentFile(path);
  showMessage(tr("Opened session %1").arg(path));
  return true;
}

bool MainWindow::saveSession(const QString& path) {
  SessionState s;
  s.meshPath = session_->meshPath();
  s.bake = session_->bakeSettings();
  s.baked = session_->hasBoxes();
  s.depthFraction = session_->depthFraction();
  const hb::Vec3 d = session_->probeDirection();
  s.probeDirection = {d.x(), d.y(), d.z()};
  s.tiltDegrees = session_->tiltDegrees();
  s.outlines = outlinesAction_->isChecked();
  s.showErrorField = errorPanel_->showField();
  s.metric = errorPanel_->metric();
  s.hasCamera = session_->hasMesh();
  s.camera = view_->cameraState();
  if (session_->hasMesh() && session_->model()->isVolume()) {
    // The surface the model was extracted with (what the Surface panel last applied).
    s.hasSurface = true;
    s.surface = session_->model()->modelOptions().volume;
  }
  if (const std::optional<hb::Vec3> p = session_->surfacePoint()) {
    s.hasProbe = true;
    s.probePoint = {p->x(), p->y(), p->z()};
  }
  try {
    saveSessionFile(s, path);
    rememberFolder(path);
    showMessage(tr("Saved session %1").arg(path));
    return true;
  } catch (const std::exception& e) {
    showMessage(QString::fromStdString(e.what()), true);
    return false;
  }
}

bool MainWindow::openDroppedUrls(const QList<QUrl>& urls) {
  for (const QUrl& url : urls)
    if (url.isLocalFile()) return openFile(url.toLocalFile(), true);
  showMessage(tr("Drop a model or session file from this computer"), true);
  return false;
}

void MainWindow::addRecentFile(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value(QStringLiteral("recentFiles")).toStringList();
  recent.removeAll(path);
  recent.prepend(path);
  while (recent.size() > kMaxRecent) recent.removeLast();
  settings.setValue(QStringLiteral("recentFiles"), recent);
  updateRecentMenu();
}

void MainWindow::updateRecentMenu() {
  recentMenu_->clear();
  const QStringList recent = QSettings().value(QStringLiteral("recentFiles")).toStringList();
  for (const QString& p : recent)
    recentMenu_->addAction(QFileInfo(p).fileName(), this, [this, p] { openFile(p, true); })->setToolTip(p);
  recentMenu_->setEnabled(!recent.isEmpty());
}

QString MainWindow::lastFolder() const {
  const QString folder = QSettings().value(QStringLiteral("files/lastFolder")).toString();
  return !folder.isEmpty() && QFileInfo(folder).isDir() ? folder : QDir::currentPath();
}

QString MainWindow::reportStartFolder() const {
  // Where the last report went (its parent: a report is a folder of its own), never the
  // dataset folder a model was opened from; the first time, the home folder.
  const QString folder = QSettings().value(QStringLiteral("files/lastReportParent")).toString();
  return !folder.isEmpty() && QFileInfo(folder).isDir() ? folder : QDir::homePath();
}

void MainWindow::rememberFolder(const QString& fileOrFolder) {
  const QFileInfo info(fileOrFolder);
  const QString folder = info.isDir() ? info.absoluteFilePath() : info.absolutePath();
  if (!folder.isEmpty()) QSettings().setValue(QStringLiteral("files/lastFolder"), folder);
}

bool MainWindow::exportScreenshot(const QString& path, int magnification, bool transparent) {
  try {
    view_->saveScreenshot(path, magnification, transparent);
    rememberFolder(path);
    const QSize size = view_->viewPixels() * magnification;
    showMessage(tr("Saved %1 (%2 x %3 pixels%4)")
                    .arg(path)
                    .arg(size.width())
                    .arg(size.height())
                    .arg(transparent ? tr(", transparent background") : QString()));
    return true;
  } catch (const std::exception& e) {
    showMessage(QString::fromStdString(e.what()), true);
    return false;
  }
}

bool MainWindow::exportReport(const QString& dir, std::size_t samples) {
  if (!QDir().mkpath(dir)) {
    showMessage(tr("Cannot create %1").arg(dir), true);
    return false;
  }
  QString image;
  if (session_->hasErrorField()) {
    // The rendered field with its scalar bar, in the metric the report's caption names (the
    // perceptible difference, on its scale anchored at what a hand feels), whichever metric the
    // window shows; the window's display returns after.
    const ProbeView::ColorMode mode = view_->colorMode();
    view_->setColorMode(ProbeView::ColorMode::ErrorField, ErrorMetric::Perceptible);
    image = QDir(dir).absoluteFilePath(QStringLiteral("error_field.png"));
    if (!exportScreenshot(image)) image.clear();
    view_->setColorMode(mode, errorPanel_->metric());
  }
  QString error;
  if (!session_->startReport(dir, image, samples, &error)) {
    showMessage(error, true);
    return false;
  }
  pendingReportDir_ = dir;
  QSettings().setValue(QStringLiteral("files/lastReportParent"), QFileInfo(QDir(dir).absolutePath()).absolutePath());
  return true;
}

void MainWindow::screenshotDialog() {
  ScreenshotDialog options(view_->viewPixels(), this);
  options.setMagnification(shotMagnification_);
  options.setTransparent(shotTransparent_);
  if (options.exec() != QDialog::Accepted) return;
  shotMagnification_ = options.magnification();
  shotTransparent_ = options.transparent();
  const QString base = session_->hasMesh() ? QFileInfo(session_->meshPath()).completeBaseName() : QStringLiteral("hapticbox");
  const QString p = QFileDialog::getSaveFileName(this, tr("Screenshot"), QDir(lastFolder()).filePath(base + QStringLiteral(".png")),
                                                 tr("PNG (*.png)"));
  if (p.isEmpty()) return;
  exportScreenshot(p.endsWith(QLatin1String(".png"), Qt::CaseInsensitive) ? p : p + QStringLiteral(".png"),
                   shotMagnification_, shotTransparent_);
}
