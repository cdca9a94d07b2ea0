#pragma once
// One long operation (bake, error field, report) on a worker thread, with progress and cancel.
#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>

class QThread;
class QTimer;

/// Runs a function on its own QThread. The function receives a progress callback in the
/// shape of hb::ProgressCallback (fraction in [0, 1], returns false once cancel() was asked),
/// so it can hand it straight to a core operation, which then throws hb::Cancelled.
/// Progress is polled on the GUI thread at 20 Hz (never a signal per call). finished()
/// is emitted on the GUI thread with an empty message on success, the exception's message
/// otherwise; `cancelled` tells a cancel apart from a failure.
class BackgroundJob : public QObject {
  Q_OBJECT
public:
  using Work = std::function<void(const std::function<bool(double)>& progress)>;

  explicit BackgroundJob(QObject* parent = nullptr);
  ~BackgroundJob() override;  ///< cancels and waits.

  /// Starts `work`; returns false when a job is already running.
  bool start(const QString& name, Work work);
  bool isRunning() const;
  QString name() const { return name_; }
  /// Asks the running job to stop at its next progress call.
  void cancel();
  /// Blocks until the running job ends (tests, shutdown). Does not process events.
  void wait();

signals:
  /// The job `name` started (GUI thread): its status replaces whatever the last one said.
  void started(const QString& name);
  void progressChanged(double fraction);
  void finished(bool ok, bool cancelled, const QString& message);

private:
  void poll();

  QString name_;
  QThread* thread_ = nullptr;
  QTimer* poll_ = nullptr;
  std::atomic<bool> cancel_{false};
  std::atomic<double> progress_{0.0};
  // Written by the worker before the thread ends, read on the GUI thread after it.
  bool ok_ = false, cancelled_ = false;
  QString message_;
};
