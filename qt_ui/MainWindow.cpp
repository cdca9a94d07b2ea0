#include "MainWindow.h"
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "ChartsView.h"
#include "DevicePanel.h"
#include "ErrorFieldPanel.h"
#include "ProbeView.h"
#include "ReadoutPanel.h"
#include "ScreenshotDialog.h"
#include "SessionFile.h"
#include "StabilityPanel.h"
#include "SurfacePanel.h"
#include "SessionPipeline.h"
#include "evaluation/comparison.h"
#include "evaluation/error_field.h"
#include "figure_text.h"
#include "vtkHapticBoxErrorFieldFilter.h"
#include <cmath>
#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QDir>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QKeySequence>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QScreen>
#include <QScrollArea>
#include <QLayout>
#include <QResizeEvent>
#include <QScrollBar>
#include <QSettings>
#include <QShowEvent>
#include <QStatusBar>
#include <QStyle>
#include <QTimer>
#include <QToolBar>
#include <algorithm>
#include <optional>

namespace {
constexpr int kMaxRecent = 8;
constexpr int kLayoutVersion = 2;  ///< saveState/restoreState: bump when the docks or toolbars change
// A dock's scroll area: as wide as its panel wants (a plain QScrollArea asks for almost no
// width, and the dock collapses), as tall as the dock allows, scrolling vertically beyond.
class DockScrollArea : public QScrollArea {
public:
  QSize sizeHint() const override {
    const QSize panel = widget() ? widget()->sizeHint() : QSize(240, 200);
    return {panel.width() + verticalScrollBar()->sizeHint().width() + 2, std::min(panel.height(), 600)};
  }
  QSize minimumSizeHint() const override {
    const QSize panel = widget() ? widget()->minimumSizeHint() : QSize(200, 60);
    return {panel.width() + verticalScrollBar()->sizeHint().width() + 2, 60};
  }

protected:
  // A resizable scroll area ignores its panel's height-for-width: wrapped lines (the readout's)
  // were squeezed into one. The panel is kept as tall as its lines need at the viewport's width.
  void resizeEvent(QResizeEvent* event) override {
    QScrollArea::resizeEvent(event);
    fitHeight();
  }
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (watched == widget() && event->type() == QEvent::LayoutRequest) fitHeight();
    return QScrollArea::eventFilter(watched, event);
  }

private:
  void fitHeight() {
    QWidget* panel = widget();
    if (!panel || !panel->layout() || !panel->layout()->hasHeightForWidth()) return;
    const int height = panel->layout()->totalHeightForWidth(viewport()->width());
    if (height > 0 && height != panel->minimumHeight()) panel->setMinimumHeight(height);
  }
};

bool isSessionFile(const QString& path) { return path.endsWith(QLatin1String(".hbsession"), Qt::CaseInsensitive); }
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), session_(new HapticSession(this)) {
  setWindowTitle(tr("HapticBox"));
  setAcceptDrops(true);
  view_ = new ProbeView(this);
  setCentralWidget(view_);
  bake_ = new BakePanel(session_);
  readout_ = new ReadoutPanel;
  errorPanel_ = new ErrorFieldPanel(session_);
  device_ = new DevicePanel(session_);
  charts_ = new ChartsView;
  stability_ = new StabilityPanel(session_);
  surface_ = new SurfacePanel(session_);
  createDocks();
  createActions();
  createToolBar();

  jobProgress_ = new QProgressBar;
  jobProgress_->setRange(0, 1000);
  jobProgress_->setMaximumWidth(180);
  jobProgress_->hide();
  jobCancel_ = new QPushButton(tr("Cancel"));
  jobCancel_->hide();
  statusBar()->addPermanentWidget(jobProgress_);
  statusBar()->addPermanentWidget(jobCancel_);
  connect(jobCancel_, &QPushButton::clicked, session_->job(), &BackgroundJob::cancel);
  // A job's status replaces the last one's ("Bake cancelled" must not linger into the next).
  connect(session_->job(), &BackgroundJob::started, this, [this](const QString& name) {
    jobCancel_->setEnabled(true);
    showMessage(tr("%1 of %2 running (Esc or Cancel stops it)").arg(name, fileLabel()));
  });
  // Cancel answers at once; the job stops at its next progress report.
  connect(session_->job(), &BackgroundJob::progressChanged, this, [this] {
    if (session_->job()->isRunning() && !jobCancel_->isEnabled())
      jobProgress_->setFormat(tr("cancelling %1").arg(session_->job()->name()));
  });
  connect(jobCancel_, &QPushButton::clicked, this, [this] {
    jobCancel_->setEnabled(false);
    showMessage(tr("Cancelling %1 of %2...").arg(session_->job()->name(), fileLabel()));
  });
  connect(session_->job(), &BackgroundJob::progressChanged, this, [this](double f) {
    jobProgress_->setValue(static_cast<int>(f * 1000.0));
    if (jobCancel_->isEnabled()) jobProgress_->setFormat(session_->job()->name() + QStringLiteral(" %p%"));
    jobProgress_->show();
    jobCancel_->show();
  });

  connect(session_, &HapticSession::meshChanged, this, &MainWindow::onMeshChanged);
  connect(session_, &HapticSession::boxesChanged, this, [this] {
    view_->setOutlines(session_->outlines());
    view_->setColorMode(ProbeView::ColorMode::Pieces);
    updateActions();
  });
  connect(session_, &HapticSession::jobFinished, this, &MainWindow::onJobFinished);
  connect(session_, &HapticSession::statusMessage, this, [this](const QString& m) { showMessage(m); });
  connect(session_, &HapticSession::sweepChanged, this,
          [this] { charts_->setRows(session_->sweepRows(), session_->compressionCurve()); });
  connect(bake_, &BakePanel::message, this, [this](const QString& m) { showMessage(m); });
  connect(errorPanel_, &ErrorFieldPanel::message, this, [this](const QString& m) { showMessage(m, true); });
  connect(errorPanel_, &ErrorFieldPanel::goToPoint, this, [this](const hb::Vec3& point, const hb::Vec3& normal) {
    // Head-on at the vertex, as the error field's probes were aimed (its cone's axis).
    if (normal.squaredNorm() > 0.f) session_->setProbeDirection(-normal.normalized());
    session_->setProbeTarget(point);
    showMessage(tr("Probe moved to the vertex at (%1, %2, %3)").arg(point.x()).arg(point.y()).arg(point.z()));
  });
  connect(errorPanel_, &ErrorFieldPanel::goToVertex, this, &MainWindow::goToWorstVertex);
  connect(errorPanel_, &ErrorFieldPanel::displayChanged, this, [this](bool field, ErrorMetric metric) {
    view_->setColorMode(field ? ProbeView::ColorMode::ErrorField : ProbeView::ColorMode::Pieces, metric);
  });
  connect(device_, &DevicePanel::message, this, [this](const QString& m) { showMessage(m); });
  connect(surface_, &SurfacePanel::extractRequested, this, [this](const hb::vtk::ModelOptions& options) {
    if (session_->hasMesh()) openFile(session_->meshPath(), true, options);
  });
  connect(surface_, &SurfacePanel::previewChanged, this,
          [this](vtkSmartPointer<vtkPolyData> preview, const QString& caption) { view_->setPreview(preview, caption); });
  connect(stability_, &StabilityPanel::message, this, [this](const QString& m) { showMessage(m, true); });
  connect(device_, &DevicePanel::tiltRequested, this, [this] {
    session_->tilt();
    session_->aimProbe(view_->viewDirection(), view_->viewRight());
    showMessage(tr("Probe tilted %1 degrees from the view direction").arg(session_->tiltDegrees()));
  });
  connect(view_, &ProbeView::surfaceDragged, this, &MainWindow::probeDragged);
  connect(view_, &ProbeView::depthStepped, this, &MainWindow::stepDepth);
  connect(charts_, &ChartsView::defaultBakeChosen, this, [this] {
    BakeSettings s = session_->bakeSettings();
    s.advanced = false;  // the default recipe, as `hapticbox bake MESH -o BOX`
    session_->setBakeSettings(s);
    bake_->showSettings();
    bake_->bakeButton()->click();
    showMessage(tr("Loading the default bake"));
  });
  connect(charts_, &ChartsView::configurationChosen, this, [this](int m, int n, const QString& codec) {
    BakeSettings s = session_->bakeSettings();
    s.advanced = true;  // a sweep point is an explicit sampling
    s.m = m;
    s.n = n;
    s.codec = codec;
    session_->setBakeSettings(s);
    bake_->showSettings();
    bake_->bakeButton()->click();
    showMessage(tr("Loading configuration m %1, n %2, codec %3").arg(m).arg(n).arg(codec));
  });

  QString note;
  session_->setDevice(DeviceKind::Virtual, {}, &note);
  timer_ = new QTimer(this);
  timer_->setInterval(16);
  connect(timer_, &QTimer::timeout, this, &MainWindow::refresh);
  timer_->start();
  // A first window takes most of the screen it opens on, never more (1366x768 laptops too).
  const QRect avail = availableGeometry();
  resize(QSize(1280, 860).boundedTo(QSize(avail.width() * 9 / 10, avail.height() * 9 / 10)));
  restorePreferences();
  fitToScreen();
  updateActions();
  showMessage(tr("Open a model (File > Open, or drop a file here)"));
}

MainWindow::~MainWindow() { timer_->stop(); }

void MainWindow::createDocks() {
  // Panels scroll inside their dock instead of being clipped (or forcing the window taller than
  // a laptop's screen): the dock's minimum height is then the scroll area's, not the panel's.
  const auto dock = [this](QWidget* w, const QString& title, const QString& name, Qt::DockWidgetArea area,
                           bool scroll = true) {
    auto* d = new QDockWidget(title, this);
    d->setObjectName(name);
    if (scroll) {
      auto* area = new DockScrollArea;
      area->setObjectName(name + QStringLiteral("Scroll"));
      area->setWidget(w);
      area->setWidgetResizable(true);
      area->setFrameShape(QFrame::NoFrame);
      area->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
      area->setMinimumHeight(60);
      d->setWidget(area);
    } else {
      d->setWidget(w);
    }
    addDockWidget(area, d);
    return d;
  };
  QDockWidget* readout = dock(readout_, tr("Readout"), QStringLiteral("ReadoutDock"), Qt::RightDockWidgetArea);
  QDockWidget* bake = dock(bake_, tr("Bake"), QStringLiteral("BakeDock"), Qt::RightDockWidgetArea);
  QDockWidget* field = dock(errorPanel_, tr("Error field"), QStringLiteral("ErrorFieldDock"), Qt::RightDockWidgetArea);
  QDockWidget* device = dock(device_, tr("Device"), QStringLiteral("DeviceDock"), Qt::RightDockWidgetArea);
  QDockWidget* charts = dock(charts_, tr("Charts"), QStringLiteral("ChartsDock"), Qt::BottomDockWidgetArea, false);
  QDockWidget* surface = dock(surface_, tr("Surface"), QStringLiteral("SurfaceDock"), Qt::RightDockWidgetArea);
  tabifyDockWidget(bake, surface);
  tabifyDockWidget(surface, field);
  tabifyDockWidget(field, device);
  // The stability table is wide (metric, box, exact, threshold, verdict): below the view,
  // beside the charts, shown by Tools > Stability Suite or the Window menu.
  QDockWidget* stability = dock(stability_, tr("Stability"), QStringLiteral("StabilityDock"), Qt::BottomDockWidgetArea, false);
  bake->raise();
  resizeDocks({readout, bake}, {260, 520}, Qt::Vertical);
  tabifyDockWidget(charts, stability);
  charts->hide();
  stability->hide();
  // Showing a dock must not push the window past its screen (the bottom docks once did).
  for (QDockWidget* d : {readout, bake, surface, field, device, charts, stability})
    connect(d, &QDockWidget::visibilityChanged, this, [this] { QTimer::singleShot(0, this, &MainWindow::fitToScreen); });
}

QRect MainWindow::availableGeometry() const {
  const QScreen* s = screen();
  if (!s) s = QGuiApplication::primaryScreen();
  return s ? s->availableGeometry() : QRect(0, 0, 1366, 768);
}

void MainWindow::fitToScreen() {
  const QRect avail = availableGeometry();
  if (avail.isEmpty()) return;
  // The frame (title bar, borders) is known once the window is shown; before, allow a typical one.
  QMargins frame(frameGeometry().left() - geometry().left(), frameGeometry().top() - geometry().top(),
                 frameGeometry().right() - geometry().right(), frameGeometry().bottom() - geometry().bottom());
  if (!isVisible() || frameGeometry() == geometry()) frame = QMargins(2, 32, 2, 2);
  const QSize room = avail.size().shrunkBy(frame);
  QSize size = geometry().size().boundedTo(room);
  // Below the window's minimum size nothing helps: the docks then shrink to their scroll areas.
  size = size.expandedTo(minimumSizeHint().boundedTo(room));
  if (size != geometry().size()) resize(size);
  QRect outer = QRect(geometry().topLeft(), size).marginsAdded(frame);
  if (!avail.contains(outer)) {
    outer.moveLeft(std::clamp(outer.left(), avail.left(), std::max(avail.left(), avail.right() - outer.width() + 1)));
    outer.moveTop(std::clamp(outer.top(), avail.top(), std::max(avail.top(), avail.bottom() - outer.height() + 1)));
    move(outer.topLeft());
  }
}

void MainWindow::showBottomDock(QDockWidget* dock) {
  const bool wasVisible = dock->isVisible();
  dock->show();
  dock->raise();
  // Two fifths of the window's height: the view keeps the larger part on a laptop's screen.
  if (!wasVisible) resizeDocks({dock}, {height() * 2 / 5}, Qt::Vertical);
}

void MainWindow::showEvent(QShowEvent* event) {
  QMainWindow::showEvent(event);
  // Once the frame is known: fit it (the first show, and after a restored geometry).
  QTimer::singleShot(0, this, &MainWindow::fitToScreen);
}

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

QString MainWindow::fileLabel() const {
  return session_->hasMesh() ? QFileInfo(session_->meshPath()).fileName() : tr("no model");
}

// --- preferences -------------------------------------------------------------------------

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

void MainWindow::showMessage(const QString& text, bool error) {
  if (error) lastError_ = text;
  statusBar()->showMessage(text, error ? 0 : 8000);
}

void MainWindow::updateActions() {
  saveBoxAction_->setEnabled(session_->hasBoxes());
  reportAction_->setEnabled(session_->hasBoxes());
  errorFieldAction_->setEnabled(session_->hasBoxes());
}

// --- files -------------------------------------------------------------------------------

bool MainWindow::openFile(const QString& path, bool interactive, const hb::vtk::ModelOptions& options) {
  if (isSessionFile(path)) {
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

void MainWindow::onMeshChanged() {
  view_->setSurface(session_->surface(), session_->diagonal());
  view_->setOutlines(session_->outlines());
  setWindowTitle(tr("HapticBox - %1").arg(QFileInfo(session_->meshPath()).fileName()));
  const hb::TriangleMesh& m = session_->mesh();
  QString text = tr("Opened %1: %2 vertices, %3 triangles").arg(session_->meshPath()).arg(m.vertex_count()).arg(m.triangle_count());
  if (!session_->meshWarnings().isEmpty()) text += QStringLiteral(" (") + session_->meshWarnings().join(QStringLiteral("; ")) + QStringLiteral(")");
  showMessage(text);
  device_->showDepth();
  // Nothing of the last model stays: its charts, its stability table; a volume shows its surface panel.
  charts_->setRows({}, {});
  surface_->showModel();
  if (session_->model()->isVolume())
    if (auto* d = findChild<QDockWidget*>(QStringLiteral("SurfaceDock"))) d->raise();
  updateActions();
}

void MainWindow::onJobFinished(const QString& name, bool ok, const QString& message) {
  jobProgress_->hide();
  jobCancel_->hide();
  jobCancel_->setEnabled(true);
  // Whole sentences that name the job and the model: a bare ": cannot open" helps nobody.
  QString text;
  if (ok) text = name == tr("Report") ? tr("Report written to %1").arg(pendingReportDir_) : tr("%1 of %2 done").arg(name, fileLabel());
  else if (message == tr("%1 cancelled").arg(name)) text = tr("%1 of %2 cancelled").arg(name, fileLabel());
  else text = tr("%1 of %2 failed: %3").arg(name, fileLabel(), message.isEmpty() ? tr("unknown error") : message);
  if (name == tr("Bake") && ok) savePreferences();  // the settings that baked are the ones to start with next time
  showMessage(text, !ok);
  updateActions();
}

// --- probe -------------------------------------------------------------------------------

void MainWindow::probeDragged(const hb::Vec3& point, bool press) {
  if (press) session_->aimProbe(view_->viewDirection(), view_->viewRight());
  session_->setProbeTarget(point);
}

void MainWindow::goToWorstVertex(std::size_t vertex) {
  if (!session_->hasMesh() || !session_->hasErrorField() || vertex >= session_->mesh().vertex_count()) return;
  // The probe the error field ran at this vertex (the same segment: hb::error_field_probes with
  // the error-field filter's options), the one with the largest error when there were several.
  vtkHapticBoxErrorFieldFilter* f = session_->model()->pipeline()->errorField();
  hb::ErrorFieldOptions o;
  o.probes_per_point = std::max(1, f->GetProbesPerPoint());
  o.cone_degrees = float(f->GetConeAngle());
  o.length_fraction = float(f->GetLengthFraction());
  o.max_depth_fraction = float(f->GetMaxDepthFraction());
  o.seed = f->GetSeed();
  const float diagonal = session_->hasBoxes() && session_->boxes()->source().diagonal > 0.f ? session_->boxes()->source().diagonal
                                                                                           : session_->diagonal();
  const hb::SurfacePoint point = hb::surface_points_at_vertices(session_->mesh())[vertex];
  const std::vector<hb::Segment> probes = hb::error_field_probes(point, vertex, diagonal, o);
  const hb::ExactQuery* exact = session_->model()->readyExact();
  std::size_t best = 0;
  double worst = -1.0;
  for (std::size_t k = 0; exact && session_->hasBoxes() && k < probes.size(); ++k) {
    const hb::Contact e = exact->query(probes[k], session_->model()->law());
    const hb::Contact a = session_->boxes()->query(probes[k], session_->model()->law());
    const double err = e.contact != a.contact ? 1e9 : e.contact ? hb::relative_force_error(e, a) : 0.0;
    if (err > worst) worst = err, best = k;
  }
  const hb::Segment& s = probes[best];
  const hb::Vec3 dir = (s.end - s.start).normalized();
  // The tip where the field's probe ended: aimed at its point, as deep as it went.
  const float depth = std::max(0.f, (s.end - point.position).dot(dir));
  session_->setProbeDirection(dir);
  session_->setDepthFraction(double(depth) / double(session_->diagonal()));
  session_->setProbeTarget(s.end - dir * depth);
  device_->showDepth();
  view_->centreOn(point.position);
  showMessage(tr("Probe at vertex %1, on the error field's probe there (%2 from the inward normal)")
                  .arg(vertex)
                  .arg(QString::fromStdString(hb::sig(std::acos(std::clamp(double(dir.dot(-point.normal.normalized())), -1.0, 1.0)) * 180.0 / M_PI)) + tr(" deg")));
}

void MainWindow::stepDepth(int step) {
  session_->setDepthFraction(session_->depthFraction() + 0.0025 * step);
  device_->showDepth();
}

void MainWindow::refresh() {
  const ProbeReading r = session_->reading();
  view_->setReading(r, session_->forceDisplayScale());
  if (++refreshCount_ % 6 == 0) {  // text at ~10 Hz
    readout_->setModelOpen(session_->hasMesh());
    readout_->setReading(r);
  }
}

// --- export ------------------------------------------------------------------------------

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

// --- events ------------------------------------------------------------------------------

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (event->mimeData()->hasUrls()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  if (openDroppedUrls(event->mimeData()->urls())) event->acceptProposedAction();
}

bool MainWindow::openDroppedUrls(const QList<QUrl>& urls) {
  for (const QUrl& url : urls)
    if (url.isLocalFile()) return openFile(url.toLocalFile(), true);
  showMessage(tr("Drop a model or session file from this computer"), true);
  return false;
}

void MainWindow::closeEvent(QCloseEvent* event) {
  savePreferences();
  session_->job()->cancel();
  session_->job()->wait();
  timer_->stop();
  QMainWindow::closeEvent(event);
}
