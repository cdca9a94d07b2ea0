// hapticbox-gui [MESH|SESSION] [--device virtual|falcon|replay:LOG] [--no-bake]
//               [--screenshot PNG [--charts]] [--measure-fps N] [--no-realtime] [--spin-us US] [--timing]
//               [--volume iso=V|label=L,smooth=N,triangles=N]
#include "BackgroundJob.h"
#include "DevicePanel.h"
#include "HapticSession.h"
#include "MainWindow.h"
#include "ProbeView.h"
#include "errors.h"
#include "parallel/huge_pages.h"
#include "volume_spec.h"
#include <QApplication>
#include <QCommandLineParser>
#include <QCoreApplication>
#include <QDockWidget>
#include <QEventLoop>
#include <QMessageBox>
#include <QSurfaceFormat>
#include <QTimer>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkObject.h>
#include <vtkRenderWindow.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace {

/// Processes events until `done` or `seconds` pass.
template <class F>
bool waitFor(F done, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > until) return false;
    QApplication::processEvents(QEventLoop::AllEvents, 20);
  }
  return true;
}

/// The command line's options (one list for the window and for --help without a display).
struct Options {
  QCommandLineOption device{QStringLiteral("device"), QStringLiteral("virtual | falcon | replay:LOG"), QStringLiteral("device"), QStringLiteral("virtual")};
  QCommandLineOption noBake{QStringLiteral("no-bake"), QStringLiteral("Do not bake on open when there is no cached bake")};
  QCommandLineOption shot{QStringLiteral("screenshot"), QStringLiteral("After opening (and baking), place the probe, save the view as PNG and quit"), QStringLiteral("png")};
  QCommandLineOption fps{QStringLiteral("measure-fps"), QStringLiteral("Render N frames of the probe view with the device thread on, print frames/s and quit"), QStringLiteral("frames")};
  QCommandLineOption field{QStringLiteral("error-field"), QStringLiteral("With --screenshot: compute the error field and show it")};
  QCommandLineOption sweep{QStringLiteral("sweep"), QStringLiteral("With --screenshot: run a small sweep and show the charts")};
  QCommandLineOption charts{QStringLiteral("charts"), QStringLiteral("With --screenshot: show the charts (the bake's own points without --sweep)")};
  QCommandLineOption noRealtime{QStringLiteral("no-realtime"), QStringLiteral("Run the device thread without SCHED_FIFO")};
  QCommandLineOption spin{QStringLiteral("spin-us"), QStringLiteral("Servo busy-wait before each deadline, us (default 0: sleep only)"), QStringLiteral("us"), QStringLiteral("0")};
  QCommandLineOption timing{QStringLiteral("timing"), QStringLiteral("Print where opening a model spends its time")};
  // The command line's --volume: the same spec, parser and help (hb::vtk::parse_volume_spec).
  QCommandLineOption volume{QStringLiteral("volume"), QString::fromStdString(hb::vtk::volume_spec_help()),
                            QString::fromLatin1(hb::vtk::kVolumeSpecSyntax)};
  explicit Options(QCommandLineParser& parser) {
    parser.setApplicationDescription(QStringLiteral("HapticBox desktop window"));
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addPositionalArgument(QStringLiteral("file"), QStringLiteral("Model (mesh, volume file or DICOM folder, CAD, scene) or session (.hbsession)"));
    parser.addOptions({device, noBake, shot, fps, field, sweep, charts, noRealtime, spin, timing, volume});
  }
};

/// The servo's run settings from the command line (--no-realtime, --spin-us, --timing); false
/// after saying on stderr what is wrong.
bool readRunSettings(const QCommandLineParser& parser, const Options& options) {
  HapticSession::RunSettings run;
  run.realtime = !parser.isSet(options.noRealtime);
  bool spinOk = false;
  run.spinUs = parser.value(options.spin).toDouble(&spinOk);
  if (!spinOk || !(run.spinUs >= 0.0 && run.spinUs <= 1000.0)) {
    std::fprintf(stderr, "hapticbox-gui: --spin-us %s: a number of microseconds in [0, 1000]\n",
                 qPrintable(parser.value(options.spin)));
    return false;
  }
  run.timing = parser.isSet(options.timing);
  HapticSession::setRunSettings(run);
  return true;
}

/// --volume, checked before any window opens as `hapticbox` checks it: a bad spec is named on
/// stderr and is a usage error. False after saying what is wrong.
bool readVolumeOptions(const QCommandLineParser& parser, const Options& options, hb::vtk::ModelOptions& model) {
  if (!parser.isSet(options.volume)) return true;
  try {
    hb::vtk::parse_volume_spec(parser.value(options.volume).toStdString(), model.volume);
    return true;
  } catch (const hb::InvalidInput& e) {
    std::fprintf(stderr, "hapticbox-gui: %s\n", e.what());
    return false;
  }
}

/// The device --device names (virtual is the window's own default).
void chooseDevice(MainWindow& window, const QString& device) {
  if (device == QLatin1String("virtual")) return;
  QString note;
  if (device == QLatin1String("falcon")) window.session()->setDevice(DeviceKind::Falcon, {}, &note);
  else if (device.startsWith(QLatin1String("replay:"))) window.session()->setDevice(DeviceKind::Replay, device.mid(7), &note);
  if (!note.isEmpty()) std::fprintf(stderr, "hapticbox-gui: %s\n", qPrintable(note));
}

/// Reports a job the command line asked for (open, and the bake on open) that fails: its
/// message on stderr, in a dialog when interactive; the exit code is then non-zero.
struct CommandLineJobs {
  MainWindow& window;
  bool scripted = false;
  bool failedOnce = false;
  void failed(const QString& message) {
    failedOnce = true;
    std::fprintf(stderr, "hapticbox-gui: %s\n", qPrintable(message));
    if (!scripted) QMessageBox::warning(&window, QStringLiteral("HapticBox"), message);
  }
};

/// Opens the model or session the command line names, watching the bake on open. False when
/// the open (or the start of its bake) failed.
bool openFromCommandLine(CommandLineJobs& jobs, const QString& path, const hb::vtk::ModelOptions& model) {
  MainWindow& window = jobs.window;
  const auto t0 = std::chrono::steady_clock::now();
  const bool ok = window.openFile(path, false, model);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!ok) {
    jobs.failed(window.lastError().isEmpty() ? QStringLiteral("cannot open %1").arg(path) : window.lastError());
    return false;
  }
  std::fprintf(stderr, "hapticbox-gui: opened %s in %.3f s (%s)\n", qPrintable(path), s,
               window.session()->hasBoxes() ? "boxes from the cache" : "no cached boxes");
  if (window.bakeOnOpenFailed()) {
    jobs.failed(window.lastError());
    return false;
  }
  if (window.session()->job()->isRunning()) {
    // The bake on open: the command line's job too.
    auto* watch = new QObject(&window);
    QObject::connect(window.session(), &HapticSession::jobFinished, watch,
                     [&jobs, &window, watch](const QString& name, bool done, const QString& message) {
                       watch->deleteLater();
                       if (!done)
                         jobs.failed(QStringLiteral("%1 of %2 failed: %3")
                                         .arg(name, window.session()->meshPath(),
                                              message.isEmpty() ? QStringLiteral("unknown error") : message));
                     });
  }
  return true;
}

/// Puts the probe in contact near the centre of the view, tilted, and orbits the camera to see
/// it and the arrows from the side (the scripted screenshot's pose).
void placeProbeAtCentre(MainWindow& window) {
  ProbeView* view = window.probeView();
  hb::Vec3 p;
  const int* size = view->renderWindow()->GetSize();
  bool placed = false;
  for (int dy = 0; dy < size[1] / 2 && !placed; dy += 8)
    placed = view->pickSurface(size[0] / 2, size[1] / 2 + dy, p);
  if (!placed) return;
  window.session()->setTiltDegrees(20.0);
  window.session()->aimProbe(view->viewDirection(), view->viewRight());
  window.session()->setDepthFraction(0.02);
  window.session()->setProbeTarget(p);
  view->orbitCamera(50.0, 15.0);
}

/// --measure-fps: the frame rates of the probe view (full model and level-of-detail proxy) and
/// the device thread's rate, on stdout.
void printFrameRates(MainWindow& window, int frames) {
  ProbeView* view = window.probeView();
  const double rate = view->measureFrameRate(frames);
  const double lodRate = view->measureFrameRate(frames, true);
  const std::string caps = view->renderWindow()->ReportCapabilities();
  std::printf("%s", caps.substr(0, caps.find("OpenGL extensions")).c_str());
  waitFor([] { return false; }, 0.6);
  const ProbeReading r = window.session()->reading();
  std::printf("probe view: %.1f frames/s full model, %.1f frames/s while moving (proxy of %lld triangles), over %d "
              "frames (%zu triangles); device thread %s: %.1f Hz, p99 period %.0f us\n",
              rate, lodRate, static_cast<long long>(view->proxyTriangles()), frames,
              window.session()->hasMesh() ? window.session()->mesh().triangle_count() : 0,
              r.deviceRunning ? "on" : "off", r.rateHz, r.p99PeriodUs);
}

/// Scripted runs (--screenshot, --measure-fps): waits for the bake, places the probe, runs the
/// error field or the sweep when asked, then measures and writes. Returns the exit code.
int runScripted(MainWindow& window, const QCommandLineParser& parser, const Options& options, const CommandLineJobs& jobs) {
  waitFor([&] { return !window.session()->job()->isRunning(); }, 600);
  waitFor([] { return false; }, 0.3);
  if (jobs.failedOnce) return 1;
  placeProbeAtCentre(window);
  waitFor([] { return false; }, 1.0);
  window.refresh();
  if (parser.isSet(options.field)) {
    window.session()->startErrorField(1);
    waitFor([&] { return !window.session()->job()->isRunning(); }, 600);
  }
  if (parser.isSet(options.sweep)) {
    window.session()->startSweep({8, 16}, {4, 8}, 2000);
    waitFor([&] { return !window.session()->job()->isRunning(); }, 600);
  }
  if (parser.isSet(options.sweep) || parser.isSet(options.charts)) {
    if (auto* d = window.findChild<QDockWidget*>(QStringLiteral("ChartsDock"))) {
      d->show();
      window.resizeDocks({d}, {window.height() * 2 / 5}, Qt::Vertical);
    }
  }
  waitFor([] { return false; }, 0.5);
  if (parser.isSet(options.fps)) printFrameRates(window, std::max(1, parser.value(options.fps).toInt()));
  if (parser.isSet(options.shot)) {
    if (!window.exportScreenshot(parser.value(options.shot))) return 1;
    QString whole = parser.value(options.shot);
    whole.insert(whole.size() - 4, QStringLiteral("-window"));
    window.grab().save(whole);  // the whole window, panels included
    std::printf("screenshot: %s\n", qPrintable(parser.value(options.shot)));
  }
  return 0;
}

/// --help and --version without a display: a core application answers them; anything else
/// says why the window cannot open.
int runWithoutDisplay(int argc, char** argv) {
  QCoreApplication core(argc, argv);
  QCoreApplication::setApplicationName(QStringLiteral("hapticbox-gui"));
  QCoreApplication::setApplicationVersion(QStringLiteral(HB_VERSION));
  QCommandLineParser parser;
  Options options(parser);
  parser.process(core);  // prints help or version and exits; a bad option exits 1 with its error
  std::fprintf(stderr, "hapticbox-gui: no display (DISPLAY is not set); use the hapticbox command, or "
                       "./run.sh for the headless main job\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  hb::use_huge_page_heap(argc, argv);  // may re-execute this program once (parallel/huge_pages.h)
  const bool display = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY") || std::getenv("QT_QPA_PLATFORM");
  if (!display) return runWithoutDisplay(argc, argv);
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("HapticBox"));
  QApplication::setApplicationName(QStringLiteral("hapticbox-gui"));
  QApplication::setApplicationVersion(QStringLiteral(HB_VERSION));

  QCommandLineParser parser;
  Options options(parser);
  parser.process(app);
  if (!readRunSettings(parser, options)) return 2;
  hb::vtk::ModelOptions model;
  if (!readVolumeOptions(parser, options, model)) return 2;

  // The window reports every error itself (status bar, dialog, and here on stderr): no VTK
  // error text or pipeline dump on the console.
  vtkObject::GlobalWarningDisplayOff();
  const bool scripted = parser.isSet(options.shot) || parser.isSet(options.fps);
  MainWindow window;
  window.setBakeOnOpen(!parser.isSet(options.noBake));
  window.show();
  CommandLineJobs jobs{window, scripted};
  chooseDevice(window, parser.value(options.device));
  const QStringList args = parser.positionalArguments();
  if (!args.isEmpty() && !openFromCommandLine(jobs, args.front(), model) && scripted) return 1;
  if (scripted) return runScripted(window, parser, options, jobs);
  const int rc = app.exec();
  return jobs.failedOnce ? 1 : rc;
}
