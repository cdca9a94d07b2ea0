// The window's tests need a QApplication (and a display: run under xvfb-run -a).
// Preferences (QSettings) go to a temporary folder, never the user's, and start empty in
// every test.
#include "HapticSession.h"
#include <QApplication>
#include <QSettings>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QTemporaryDir>
#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>

namespace {
class FreshSettings : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo&) override { QSettings().clear(); }
};
}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (::testing::GTEST_FLAG(list_tests)) return RUN_ALL_TESTS();  // discovery: no display needed
  QStandardPaths::setTestModeEnabled(true);
  QTemporaryDir settingsDir;
  QSettings::setPath(QSettings::NativeFormat, QSettings::UserScope, settingsDir.path());
  QSettings::setPath(QSettings::IniFormat, QSettings::UserScope, settingsDir.path());
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  HapticSession::RunSettings run;
  run.realtime = false;  // tests share the machine: no SCHED_FIFO
  HapticSession::setRunSettings(run);
  QApplication app(argc, argv);
  QApplication::setOrganizationName(QStringLiteral("HapticBoxTests"));
  QApplication::setApplicationName(QStringLiteral("hb_ui_tests"));
  ::testing::UnitTest::GetInstance()->listeners().Append(new FreshSettings);
  return RUN_ALL_TESTS();
}
