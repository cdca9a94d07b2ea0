// MainWindow's menus (File, View, Probe, Device, Tools, Window, Help) with their shortcuts,
// and the toolbar of the common actions.
#include "MainWindow.h"
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "DevicePanel.h"
#include "ErrorFieldPanel.h"
#include "ProbeView.h"
#include <QAction>
#include <QDockWidget>
#include <QFileDialog>
#include <QKeySequence>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QStyle>
#include <QToolBar>

void MainWindow::createActions() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  QAction* open = file->addAction(tr("&Open..."), this, &MainWindow::openDialog, QKeySequence::Open);
  // Ctrl+O and the other menu shortcuts answer wherever the focus is, the 3D view included.
  open->setShortcutContext(Qt::ApplicationShortcut);
  open->setObjectName(QStringLiteral("openAction"));
  file->addAction(tr("Open &DICOM Folder..."), this, &MainWindow::openDicomFolderDialog, QKeySequence(tr("Ctrl+Shift+O")))
      ->setObjectName(QStringLiteral("openDicomFolderAction"));
  recentMenu_ = file->addMenu(tr("Open &Recent"));
  file->addAction(tr("Open &Box File..."), this, &MainWindow::openBoxDialog);
  saveBoxAction_ = file->addAction(tr("Save Box File &As..."), this, &MainWindow::saveBoxDialog);
  file->addSeparator();
  file->addAction(tr("Open &Session..."), this, [this] {
    const QString p = QFileDialog::getOpenFileName(this, tr("Open session"), lastFolder(), tr("Sessions (*.hbsession)"));
    if (!p.isEmpty()) openFile(p, true);
  });
  file->addAction(tr("Save Session &As..."), this, [this] {
    const QString p = QFileDialog::getSaveFileName(this, tr("Save session"), lastFolder(), tr("Sessions (*.hbsession)"));
    if (!p.isEmpty()) saveSession(p.endsWith(QLatin1String(".hbsession")) ? p : p + QStringLiteral(".hbsession"));
  });
  file->addSeparator();
  file->addAction(tr("Export Screens&hot..."), this, &MainWindow::screenshotDialog, QKeySequence(tr("Ctrl+P")));
  reportAction_ = file->addAction(tr("Export Error &Report..."), this, [this] {
    const QString d = QFileDialog::getExistingDirectory(this, tr("Report folder"), reportStartFolder());
    if (!d.isEmpty()) exportReport(d);
  });
  file->addSeparator();
  file->addAction(tr("&Quit"), this, &QWidget::close, QKeySequence::Quit);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  outlinesAction_ = view->addAction(tr("PBB &Outlines"));
  outlinesAction_->setCheckable(true);
  outlinesAction_->setShortcut(QKeySequence(tr("O")));
  connect(outlinesAction_, &QAction::toggled, view_, &ProbeView::setOutlinesVisible);
  view->addAction(tr("&Reset Camera"), view_, &ProbeView::resetCamera, QKeySequence(tr("R")));
  QMenu* along = view->addMenu(tr("View &Direction"));
  const struct { const char* text; int axis, sign; } directions[] = {
      {"+X", 0, 1}, {"-X", 0, -1}, {"+Y", 1, 1}, {"-Y", 1, -1}, {"+Z", 2, 1}, {"-Z", 2, -1}};
  for (const auto& d : directions) {
    QAction* a = along->addAction(tr("Look Along %1").arg(QLatin1String(d.text)), this,
                                  [this, axis = d.axis, sign = d.sign] { view_->viewAlong(axis, sign); });
    a->setIconText(QLatin1String(d.text));
    a->setObjectName(QStringLiteral("view%1").arg(QLatin1String(d.text)).replace('+', 'P').replace('-', 'M'));
    a->setToolTip(tr("Look along %1 (the camera on the %2 side)").arg(QLatin1String(d.text),
                                                                      QLatin1String(d.sign > 0 ? "-" : "+") + QLatin1Char("XYZ"[d.axis])));
  }
  axesAction_ = view->addAction(tr("Orientation &Axes"));
  axesAction_->setCheckable(true);
  axesAction_->setChecked(view_->orientationAxesVisible());
  connect(axesAction_, &QAction::toggled, view_, &ProbeView::setOrientationAxesVisible);
  bakeOnOpenAction_ = view->addAction(tr("&Bake on Open"));
  bakeOnOpenAction_->setCheckable(true);
  bakeOnOpenAction_->setChecked(bakeOnOpen_);
  connect(bakeOnOpenAction_, &QAction::toggled, this, [this](bool on) { bakeOnOpen_ = on; });

  QMenu* probe = menuBar()->addMenu(tr("&Probe"));
  probeToolAction_ = probe->addAction(tr("Probe &Tool (drag on the model)"));
  probeToolAction_->setCheckable(true);
  probeToolAction_->setChecked(true);
  probeToolAction_->setShortcut(QKeySequence(tr("P")));
  connect(probeToolAction_, &QAction::toggled, view_, &ProbeView::setProbeMode);
  probe->addAction(tr("Push &Deeper"), this, [this] { stepDepth(+1); }, QKeySequence(tr("]")));
  probe->addAction(tr("&Pull Back"), this, [this] { stepDepth(-1); }, QKeySequence(tr("[")));
  probe->addAction(tr("T&ilt"), device_, &DevicePanel::tiltRequested, QKeySequence(tr("T")));

  QMenu* deviceMenu = menuBar()->addMenu(tr("&Device"));
  QAction* estop = deviceMenu->addAction(tr("&Emergency Stop (no force until released)"));
  estop->setCheckable(true);
  estop->setShortcut(QKeySequence(tr("Space")));
  estop->setShortcutContext(Qt::ApplicationShortcut);
  connect(estop, &QAction::toggled, session_, &HapticSession::setEmergencyStop);

  QMenu* tools = menuBar()->addMenu(tr("&Tools"));
  tools->addAction(tr("&Bake"), bake_->bakeButton(), &QPushButton::click, QKeySequence(tr("Ctrl+B")));
  errorFieldAction_ = tools->addAction(tr("Compute &Error Field"), errorPanel_->computeButton(), &QPushButton::click,
                                       QKeySequence(tr("Ctrl+E")));
  tools->addAction(tr("Run &Sweep (speed against accuracy)"), this, [this] {
    QString error;
    if (!session_->startSweep({8, 16, 32}, {4, 8}, 5000, &error)) showMessage(error, true);
    else if (auto* d = findChild<QDockWidget*>(QStringLiteral("ChartsDock"))) showBottomDock(d);
  });
  tools->addAction(tr("S&tability Suite..."), this, [this] {
    if (auto* d = findChild<QDockWidget*>(QStringLiteral("StabilityDock"))) showBottomDock(d);
  });
  tools->addAction(tr("Cancel Running Job"), session_->job(), &BackgroundJob::cancel, QKeySequence(tr("Esc")));

  QMenu* windows = menuBar()->addMenu(tr("&Window"));
  for (QDockWidget* d : findChildren<QDockWidget*>()) windows->addAction(d->toggleViewAction());

  QMenu* help = menuBar()->addMenu(tr("&Help"));
  help->addAction(tr("&Controls"), this, [this] {
    QMessageBox::information(this, tr("Controls"),
                             tr("Left drag on the model: move the probe tip over the surface.\n"
                                "Left drag on the background: rotate. Right drag: zoom. Middle drag: pan.\n"
                                "Ctrl+wheel or [ and ]: push the tip deeper / pull it back.\n"
                                "T: tilt the probe (15 degree steps). O: PBB outlines. R: reset camera.\n"
                                "Space: emergency stop of the device force (Space again: release).\n"
                                "Red arrow: exact force (Embree). Blue arrow: haptic box force (the colours of the charts and the report)."));
  });
  help->addAction(tr("&About"), this, [this] {
    QMessageBox::about(this, tr("About HapticBox"),
                       tr("HapticBox %1: haptic rendering by directional sampling.").arg(QStringLiteral(HB_VERSION)));
  });
  updateRecentMenu();
}

void MainWindow::createToolBar() {
  // The common actions one click away (ParaView's and Slicer's toolbars): files, bake and
  // cancel, screenshot, and the camera's standard views.
  toolBar_ = addToolBar(tr("Main"));
  toolBar_->setObjectName(QStringLiteral("MainToolBar"));
  toolBar_->setToolButtonStyle(Qt::ToolButtonTextBesideIcon);
  QStyle* st = style();
  QAction* open = toolBar_->addAction(st->standardIcon(QStyle::SP_DialogOpenButton), tr("Open"), this, &MainWindow::openDialog);
  open->setToolTip(tr("Open a model or a session (Ctrl+O)"));
  QAction* save = toolBar_->addAction(st->standardIcon(QStyle::SP_DialogSaveButton), tr("Save Session"), this, [this] {
    const QString p = QFileDialog::getSaveFileName(this, tr("Save session"), lastFolder(), tr("Sessions (*.hbsession)"));
    if (!p.isEmpty()) saveSession(p.endsWith(QLatin1String(".hbsession")) ? p : p + QStringLiteral(".hbsession"));
  });
  save->setObjectName(QStringLiteral("toolSaveSession"));
  toolBar_->addSeparator();
  QAction* bake = toolBar_->addAction(st->standardIcon(QStyle::SP_MediaPlay), tr("Bake"), bake_->bakeButton(), &QPushButton::click);
  bake->setToolTip(tr("Bake the boxes with the Bake panel's settings (Ctrl+B)"));
  QAction* cancel = toolBar_->addAction(st->standardIcon(QStyle::SP_BrowserStop), tr("Cancel"), this, [this] {
    if (session_->job()->isRunning()) jobCancel_->click();
  });
  cancel->setToolTip(tr("Cancel the running job (Esc)"));
  toolBar_->addAction(tr("Screenshot"), this, &MainWindow::screenshotDialog)->setToolTip(tr("Export the view as PNG (Ctrl+P)"));
  toolBar_->addSeparator();
  QAction* reset = toolBar_->addAction(tr("Reset"), view_, &ProbeView::resetCamera);
  reset->setToolTip(tr("Reset the camera to frame the model (R)"));
  for (QAction* a : findChildren<QAction*>())
    if (a->objectName().startsWith(QLatin1String("view"))) toolBar_->addAction(a);
  toolBar_->addAction(axesAction_);
  toolBar_->addAction(outlinesAction_);
  // Enabled with the job: Bake needs a model, Cancel a running job.
  connect(session_->job(), &BackgroundJob::started, cancel, [cancel] { cancel->setEnabled(true); });
  connect(session_, &HapticSession::jobFinished, cancel, [cancel] { cancel->setEnabled(false); });
  cancel->setEnabled(false);
  cancel->setObjectName(QStringLiteral("toolCancel"));
  bake->setObjectName(QStringLiteral("toolBake"));
}
