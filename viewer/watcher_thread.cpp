#include "viewer/watcher_thread.h"

namespace bt {

namespace {
// How often the thread drains inotify: a fraction of the debounce, and cheap (one read()).
constexpr std::chrono::milliseconds kPollInterval(20);
} // namespace

WatcherThread::WatcherThread(std::chrono::milliseconds debounce) : watcher_(debounce), thread_([this] { run(); }) {}

WatcherThread::~WatcherThread() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void WatcherThread::watch(const std::vector<std::filesystem::path>& files) {
  std::lock_guard lock(mutex_);
  watcher_.watch(files);
}

WatcherThread::Clock::time_point WatcherThread::noticedAt() const {
  std::lock_guard lock(mutex_);
  return noticedAt_;
}

void WatcherThread::run() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, kPollInterval, [this] { return stop_; })) {
    if (watcher_.poll().empty()) continue;
    noticedAt_ = Clock::now();
    changed_.store(true);
  }
}

} // namespace bt
