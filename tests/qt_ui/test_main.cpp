// The window's tests need a QApplication (and a display: run under xvfb-run -a).
#include "HapticSession.h"
#include <QApplication>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (::testing::GTEST_FLAG(list_tests)) return RUN_ALL_TESTS();  // discovery: no display needed
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  HapticSession::RunSettings run;
  run.realtime = false;  // tests share the machine: no SCHED_FIFO
  HapticSession::setRunSettings(run);
  QApplication app(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("HapticBoxTests"));
  QApplication::setApplicationName(QStringLiteral("hb_ui_tests"));
  return RUN_ALL_TESTS();
}
