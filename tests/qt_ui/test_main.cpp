// The window's tests need a QApplication (and a display: run under xvfb-run -a).
#include <QApplication>
#include <QSurfaceFormat>
#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (::testing::GTEST_FLAG(list_tests)) return RUN_ALL_TESTS();  // discovery: no display needed
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  qputenv("HB_GUI_NO_REALTIME", "1");  // tests share the machine: no SCHED_FIFO
  QApplication app(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("HapticBoxTests"));
  QApplication::setApplicationName(QStringLiteral("hb_ui_tests"));
  return RUN_ALL_TESTS();
}
