#pragma once
// The main window: menus, docks and the status bar around the probe view. It wires widgets to
// the session (the logic) and holds neither data nor algorithms.
#include "HapticSession.h"
#include <QMainWindow>
#include <QList>
#include <QStringList>
#include <QUrl>

class BakePanel;
class ChartsView;
class DevicePanel;
class ErrorFieldPanel;
class ProbeView;
class QAction;
class QDockWidget;
class QLabel;
class QMenu;
class QProgressBar;
class QPushButton;
class QTimer;
class QToolBar;
class ReadoutPanel;
class StabilityPanel;
class SurfacePanel;

class MainWindow : public QMainWindow {
  Q_OBJECT
public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Opens a mesh or a session file; errors go to the status bar (and a dialog when
  /// `interactive`). Returns false on failure.
  bool openFile(const QString& path, bool interactive = false, const hb::vtk::ModelOptions& options = {});
  /// The last error the window reported (status bar, dialog): a whole sentence naming the file
  /// and the cause; empty when none yet. The command line prints it on a failed job.
  QString lastError() const { return lastError_; }
  /// The last openFile opened the model but its bake on open could not start (lastError says why).
  bool bakeOnOpenFailed() const { return bakeOnOpenFailed_; }
  /// What a drop does: opens the first local file. Returns false when there is none or it fails.
  bool openDroppedUrls(const QList<QUrl>& urls);
  /// Bakes automatically after opening a model without a cached bake (default on).
  void setBakeOnOpen(bool on) { bakeOnOpen_ = on; }

  /// Writes the view as PNG at `magnification` x its size, optionally with a transparent
  /// background (File > Export Screenshot asks for both).
  bool exportScreenshot(const QString& path, int magnification = 1, bool transparent = false);
  /// Starts the report job (the files of `hapticbox report` plus the error-field image).
  bool exportReport(const QString& dir, std::size_t samples = 20000);
  bool saveSession(const QString& path);

  HapticSession* session() const { return session_; }
  ProbeView* probeView() const { return view_; }
  ReadoutPanel* readoutPanel() const { return readout_; }
  BakePanel* bakePanel() const { return bake_; }
  ErrorFieldPanel* errorFieldPanel() const { return errorPanel_; }
  DevicePanel* devicePanel() const { return device_; }
  ChartsView* chartsView() const { return charts_; }
  StabilityPanel* stabilityPanel() const { return stability_; }
  SurfacePanel* surfacePanel() const { return surface_; }
  /// Preferences that persist between runs (QSettings): bake settings, Bake on Open, the
  /// orientation axes, the window's geometry and dock/toolbar layout, the screenshot options.
  /// Read when the window is made, written when it closes (and when a bake starts).
  void savePreferences();
  void restorePreferences();
  /// The folder file dialogs open in: the last one a file was opened from or saved to.
  QString lastFolder() const;
  void rememberFolder(const QString& fileOrFolder);
  /// The folder File > Export Error Report's dialog opens in: the parent of the last report's
  /// folder, else the home folder (not the folder of the model's data).
  QString reportStartFolder() const;
  QToolBar* toolBar() const { return toolBar_; }
  /// Shrinks and moves the window so that its frame lies within the available geometry of its
  /// screen (called on show, after restoring a layout and when a dock appears).
  void fitToScreen();
  /// The available geometry (screen minus panels) of the window's screen.
  QRect availableGeometry() const;
  /// One display tick (the timer calls it at ~60 Hz): latest reading to the view and readout.
  void refresh();

protected:
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  void closeEvent(QCloseEvent* event) override;
  void showEvent(QShowEvent* event) override;

private:
  void createActions();
  void createDocks();
  void createToolBar();
  void screenshotDialog();
  QString fileLabel() const;
  void showMessage(const QString& text, bool error = false);
  void addRecentFile(const QString& path);
  void updateRecentMenu();
  void updateActions();
  void onMeshChanged();
  void onJobFinished(const QString& name, bool ok, const QString& message);
  void openDialog();
  void openDicomFolderDialog();
  void openBoxDialog();
  void saveBoxDialog();
  bool openSessionFile(const QString& path, bool interactive);
  QString lastError_;
  bool bakeOnOpenFailed_ = false;
  void probeDragged(const hb::Vec3& point, bool press);
  void stepDepth(int step);
  void goToWorstVertex(std::size_t vertex);
  /// Shows a dock below the view (charts, stability) at two fifths of the window's height.
  void showBottomDock(QDockWidget* dock);

  HapticSession* session_;
  ProbeView* view_;
  BakePanel* bake_;
  ReadoutPanel* readout_;
  ErrorFieldPanel* errorPanel_;
  DevicePanel* device_;
  ChartsView* charts_;
  StabilityPanel* stability_;
  SurfacePanel* surface_;
  QTimer* timer_;
  QProgressBar* jobProgress_;
  QPushButton* jobCancel_;
  QMenu* recentMenu_ = nullptr;
  QAction* outlinesAction_ = nullptr;
  QAction* probeToolAction_ = nullptr;
  QAction* saveBoxAction_ = nullptr;
  QAction* reportAction_ = nullptr;
  QAction* errorFieldAction_ = nullptr;
  QAction* axesAction_ = nullptr;
  QAction* bakeOnOpenAction_ = nullptr;
  QToolBar* toolBar_ = nullptr;
  int shotMagnification_ = 1;
  bool shotTransparent_ = false;
  bool bakeOnOpen_ = true;
  int refreshCount_ = 0;
  QString pendingReportDir_;
};
