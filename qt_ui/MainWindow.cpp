// MainWindow: the docks around the probe view, the status bar's job progress, and the wiring
// of panels to the session. Its menus and toolbar are in MainWindowMenus.cpp, opening and
// saving files in MainWindowFiles.cpp, the persistent preferences in MainWindowPreferences.cpp.
#include "MainWindow.h"
#include "BackgroundJob.h"
#include "BakePanel.h"
#include "DockScrollArea.h"
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
    // Until a sweep (or a report) fills it, the speed chart shows the bake's own points (the
    // default bake, exact, the raw samplings it tried), read off its budget report; a scene
    // without one (a given sampling) leaves the chart as it is.
    if (!charts_->showsSweep() && session_->boxes()) {
      const std::vector<hb::BakeChartPoint> points = hb::bake_chart_points(*session_->boxes());
      if (!points.empty()) charts_->showBake(points, session_->compressionCurve());
      else if (session_->boxes()->parts().budget.present) charts_->showUntimedBake();  // an older file
    }
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

QString MainWindow::fileLabel() const {
  return session_->hasMesh() ? QFileInfo(session_->meshPath()).fileName() : tr("no model");
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
  const float diagonal = session_->hasBoxes() && session_->boxes()->parts().source.diagonal > 0.f ? session_->boxes()->parts().source.diagonal
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

// --- events ------------------------------------------------------------------------------

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (event->mimeData()->hasUrls()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  if (openDroppedUrls(event->mimeData()->urls())) event->acceptProposedAction();
}

void MainWindow::closeEvent(QCloseEvent* event) {
  savePreferences();
  session_->job()->cancel();
  session_->job()->wait();
  timer_->stop();
  QMainWindow::closeEvent(event);
}
