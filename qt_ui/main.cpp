// hapticbox-gui [MESH|SESSION] [--device virtual|falcon|replay:LOG] [--no-bake]
//               [--screenshot PNG] [--measure-fps N] [--no-realtime] [--spin-us US] [--timing]
//               [--iso V | --label L] [--smooth N] [--target-triangles N]
#include "BackgroundJob.h"
#include "DevicePanel.h"
#include "HapticSession.h"
#include "MainWindow.h"
#include "ProbeView.h"
#include "parallel/huge_pages.h"
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
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>

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
  QCommandLineOption noRealtime{QStringLiteral("no-realtime"), QStringLiteral("Run the device thread without SCHED_FIFO")};
  QCommandLineOption spin{QStringLiteral("spin-us"), QStringLiteral("Servo busy-wait before each deadline, us (default 0: sleep only)"), QStringLiteral("us"), QStringLiteral("0")};
  QCommandLineOption timing{QStringLiteral("timing"), QStringLiteral("Print where opening a model spends its time")};
  QCommandLineOption iso{QStringLiteral("iso"), QStringLiteral("Volumes: iso-value in calibrated units (HU for CT); default the Otsu threshold"), QStringLiteral("value")};
  QCommandLineOption label{QStringLiteral("label"), QStringLiteral("Volumes (label maps): the surface of the voxels with this label"), QStringLiteral("label")};
  QCommandLineOption smooth{QStringLiteral("smooth"), QStringLiteral("Volumes: windowed-sinc smoothing iterations (0: none)"), QStringLiteral("iterations")};
  QCommandLineOption target{QStringLiteral("target-triangles"), QStringLiteral("Volumes: decimate to about this many triangles (0: keep all)"), QStringLiteral("count")};
  std::tuple<QCommandLineOption&, QCommandLineOption&, QCommandLineOption&, QCommandLineOption&, QCommandLineOption&,
             QCommandLineOption&, QCommandLineOption&, QCommandLineOption&, QCommandLineOption&, QCommandLineOption&,
             QCommandLineOption&, QCommandLineOption&, QCommandLineOption&>
      list{device, noBake, shot, fps, field, sweep, noRealtime, spin, timing, iso, label, smooth, target};
  explicit Options(QCommandLineParser& parser) {
    parser.setApplicationDescription(QStringLiteral("HapticBox desktop window"));
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addPositionalArgument(QStringLiteral("file"), QStringLiteral("Model (mesh, volume file or DICOM folder, CAD, scene) or session (.hbsession)"));
    parser.addOptions({device, noBake, shot, fps, field, sweep, noRealtime, spin, timing, iso, label, smooth, target});
  }
};

}  // namespace

int main(int argc, char** argv) {
  hb::use_huge_page_heap(argc, argv);  // may re-execute this program once (parallel/huge_pages.h)
  const bool display = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY") || std::getenv("QT_QPA_PLATFORM");
  if (!display) {
    // --help and --version need no display: a core application answers them.
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
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("HapticBox"));
  QApplication::setApplicationName(QStringLiteral("hapticbox-gui"));
  QApplication::setApplicationVersion(QStringLiteral(HB_VERSION));

  QCommandLineParser parser;
  Options options(parser);
  const auto& [device, noBake, shot, fps, field, sweep, noRealtime, spin, timing, iso, label, smooth, target] = options.list;
  parser.process(app);
  HapticSession::RunSettings run;
  run.realtime = !parser.isSet(noRealtime);
  bool spinOk = false;
  run.spinUs = parser.value(spin).toDouble(&spinOk);
  if (!spinOk || !(run.spinUs >= 0.0 && run.spinUs <= 1000.0)) {
    std::fprintf(stderr, "hapticbox-gui: --spin-us %s: a number of microseconds in [0, 1000]\n", qPrintable(parser.value(spin)));
    return 2;
  }
  run.timing = parser.isSet(timing);
  HapticSession::setRunSettings(run);

  // The volume options, checked before any window opens: each bad value named, as the
  // command line's --iso, --label, --smooth and --target-triangles are.
  hb::vtk::ModelOptions model;
  {
    const auto bad = [](const char* option, const QString& value, const char* want) {
      std::fprintf(stderr, "hapticbox-gui: %s %s: %s\n", option, qPrintable(value), want);
      return 2;
    };
    bool ok = true;
    if (parser.isSet(iso)) {
      const double v = parser.value(iso).toDouble(&ok);
      if (!ok || !std::isfinite(v)) return bad("--iso", parser.value(iso), "a finite number (calibrated units, HU for CT)");
      model.volume.iso = v;
    }
    if (parser.isSet(label)) {
      model.volume.label = parser.value(label).toLong(&ok);
      if (!ok) return bad("--label", parser.value(label), "a whole number (a label of the label map)");
    }
    if (model.volume.iso && model.volume.label) return bad("--label", parser.value(label), "not with --iso (one or the other)");
    if (parser.isSet(smooth)) {
      model.volume.smooth_iterations = parser.value(smooth).toInt(&ok);
      if (!ok || model.volume.smooth_iterations < 0)
        return bad("--smooth", parser.value(smooth), "a whole number of iterations, >= 0");
    }
    if (parser.isSet(target)) {
      model.volume.target_triangles = parser.value(target).toULongLong(&ok);
      if (!ok) return bad("--target-triangles", parser.value(target), "a whole number of triangles, >= 0");
    }
  }

  // The window reports every error itself (status bar, dialog, and here on stderr): no VTK
  // error text or pipeline dump on the console.
  vtkObject::GlobalWarningDisplayOff();
  const bool scripted = parser.isSet(shot) || parser.isSet(fps);
  MainWindow window;
  window.setBakeOnOpen(!parser.isSet(noBake));
  window.show();
  // A job the command line asked for (open, and the bake on open) that fails: its message on
  // stderr, in a dialog when interactive, and a non-zero exit (at once for a scripted run,
  // when the window closes otherwise).
  bool commandLineFailed = false;
  const auto failed = [&](const QString& message) {
    commandLineFailed = true;
    std::fprintf(stderr, "hapticbox-gui: %s\n", qPrintable(message));
    if (!scripted) QMessageBox::warning(&window, QStringLiteral("HapticBox"), message);
  };
  const QString dev = parser.value(device);
  if (dev != QLatin1String("virtual")) {
    QString note;
    if (dev == QLatin1String("falcon")) window.session()->setDevice(DeviceKind::Falcon, {}, &note);
    else if (dev.startsWith(QLatin1String("replay:"))) window.session()->setDevice(DeviceKind::Replay, dev.mid(7), &note);
    if (!note.isEmpty()) std::fprintf(stderr, "hapticbox-gui: %s\n", qPrintable(note));
  }
  const QStringList args = parser.positionalArguments();
  if (!args.isEmpty()) {
    const auto t0 = std::chrono::steady_clock::now();
    const bool ok = window.openFile(args.front(), false, model);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (ok) {
      std::fprintf(stderr, "hapticbox-gui: opened %s in %.3f s (%s)\n", qPrintable(args.front()), s,
                   window.session()->hasBoxes() ? "boxes from the cache" : "no cached boxes");
      if (window.bakeOnOpenFailed()) {
        failed(window.lastError());
        if (scripted) return 1;
      } else if (window.session()->job()->isRunning()) {
        // The bake on open: the command line's job too.
        auto* watch = new QObject(&window);
        QObject::connect(window.session(), &HapticSession::jobFinished, watch,
                         [&failed, &window, watch](const QString& name, bool done, const QString& message) {
                           watch->deleteLater();
                           if (!done)
                             failed(QStringLiteral("%1 of %2 failed: %3")
                                        .arg(name, window.session()->meshPath(), message.isEmpty() ? QStringLiteral("unknown error") : message));
                         });
      }
    } else {
      failed(window.lastError().isEmpty() ? QStringLiteral("cannot open %1").arg(args.front()) : window.lastError());
      if (scripted) return 1;
    }
  }

  if (parser.isSet(shot) || parser.isSet(fps)) {
    // Scripted runs: wait for the bake, put the probe in contact at the centre of the view.
    waitFor([&] { return !window.session()->job()->isRunning(); }, 600);
    waitFor([] { return false; }, 0.3);
    if (commandLineFailed) return 1;
    ProbeView* view = window.probeView();
    hb::Vec3 p;
    const int* size = view->renderWindow()->GetSize();
    bool placed = false;
    for (int dy = 0; dy < size[1] / 2 && !placed; dy += 8)
      placed = view->pickSurface(size[0] / 2, size[1] / 2 + dy, p);
    if (placed) {
      window.session()->setTiltDegrees(20.0);
      window.session()->aimProbe(view->viewDirection(), view->viewRight());
      window.session()->setDepthFraction(0.02);
      window.session()->setProbeTarget(p);
      view->orbitCamera(50.0, 15.0);  // see the probe and the arrows from the side
    }
    waitFor([] { return false; }, 1.0);
    window.refresh();
    if (parser.isSet(field)) {
      window.session()->startErrorField(1);
      waitFor([&] { return !window.session()->job()->isRunning(); }, 600);
    }
    if (parser.isSet(sweep)) {
      window.session()->startSweep({8, 16}, {4, 8}, 2000);
      waitFor([&] { return !window.session()->job()->isRunning(); }, 600);
      if (auto* d = window.findChild<QDockWidget*>(QStringLiteral("ChartsDock"))) {
        d->show();
        window.resizeDocks({d}, {window.height() * 2 / 5}, Qt::Vertical);
      }
    }
    waitFor([] { return false; }, 0.5);
    if (parser.isSet(fps)) {
      const int frames = std::max(1, parser.value(fps).toInt());
      const double rate = view->measureFrameRate(frames);
      const double lodRate = view->measureFrameRate(frames, true);
      const std::string caps = view->renderWindow()->ReportCapabilities();
      std::printf("%s", caps.substr(0, caps.find("OpenGL extensions")).c_str());
      waitFor([] { return false; }, 0.6);
      const ProbeReading r = window.session()->reading();
      std::printf("probe view: %.1f frames/s full model, %.1f frames/s while moving (proxy of %lld triangles), over %d "
                  "frames (%zu triangles); device thread %s: %.1f Hz, p99 period %.0f us\n",
                  rate, lodRate, static_cast<long long>(view->proxyTriangles()), frames, window.session()->hasMesh() ? window.session()->mesh().triangle_count() : 0,
                  r.deviceRunning ? "on" : "off", r.rateHz, r.p99PeriodUs);
    }
    if (parser.isSet(shot)) {
      if (!window.exportScreenshot(parser.value(shot))) return 1;
      QString whole = parser.value(shot);
      whole.insert(whole.size() - 4, QStringLiteral("-window"));
      window.grab().save(whole);  // the whole window, panels included
      std::printf("screenshot: %s\n", qPrintable(parser.value(shot)));
    }
    return 0;
  }
  const int rc = app.exec();
  return commandLineFailed ? 1 : rc;
}
