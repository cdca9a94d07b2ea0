// A worker QThread per job: the work runs there, its result is delivered on the GUI thread
// through QThread::finished (a queued connection), progress by polling an atomic.
#include "BackgroundJob.h"
#include "errors.h"
#include <QThread>
#include <QTimer>
#include <exception>

BackgroundJob::BackgroundJob(QObject* parent) : QObject(parent), poll_(new QTimer(this)) {
  poll_->setInterval(50);
  connect(poll_, &QTimer::timeout, this, &BackgroundJob::poll);
}

BackgroundJob::~BackgroundJob() {
  cancel();
  wait();
}

bool BackgroundJob::isRunning() const { return thread_ != nullptr; }

bool BackgroundJob::start(const QString& name, Work work) {
  if (thread_) return false;
  name_ = name;
  cancel_.store(false);
  progress_.store(0.0);
  ok_ = cancelled_ = false;
  message_.clear();
  thread_ = QThread::create([this, work = std::move(work)] {
    const auto progress = [this](double f) {
      progress_.store(f, std::memory_order_relaxed);
      return !cancel_.load(std::memory_order_relaxed);
    };
    try {
      work(progress);
      ok_ = true;
    } catch (const hb::Cancelled&) {
      cancelled_ = true;
      message_ = tr("%1 cancelled").arg(name_);
    } catch (const std::exception& e) {
      message_ = QString::fromStdString(e.what());
    } catch (...) {
      message_ = tr("%1 failed: unknown error").arg(name_);
    }
  });
  connect(thread_, &QThread::finished, this, [this] {
    poll_->stop();
    thread_->deleteLater();
    thread_ = nullptr;
    emit progressChanged(ok_ ? 1.0 : progress_.load());
    emit finished(ok_, cancelled_, message_);
  });
  poll_->start();
  thread_->start();
  emit started(name_);
  return true;
}

void BackgroundJob::cancel() { cancel_.store(true); }

void BackgroundJob::wait() {
  if (thread_) thread_->wait();
}

void BackgroundJob::poll() { emit progressChanged(progress_.load(std::memory_order_relaxed)); }
