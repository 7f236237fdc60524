// The file watcher on a thread of its own, so that a save is noticed within the debounce time
// however long a frame takes (a frame on llvmpipe took seconds, and a reload started 20-45 s
// after the save when the watcher was polled once per frame). The frame only reads the flag.
#pragma once

#include "viewer/file_watcher.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

namespace bt {

class WatcherThread {
public:
  using Clock = std::chrono::steady_clock;

  explicit WatcherThread(std::chrono::milliseconds debounce = std::chrono::milliseconds(250));
  ~WatcherThread(); // stops and joins the thread
  WatcherThread(const WatcherThread&) = delete;
  WatcherThread& operator=(const WatcherThread&) = delete;

  // Replaces the watched set; a change noticed before and not yet taken is kept.
  void watch(const std::vector<std::filesystem::path>& files);
  // True once (until taken) when a watched file has changed and been quiet for the debounce time.
  bool changed() const { return changed_.load(); }
  bool takeChange() { return changed_.exchange(false); }
  // When the last change was noticed (for tests and the overlay).
  Clock::time_point noticedAt() const;

private:
  void run();

  FileWatcher watcher_;
  mutable std::mutex mutex_; // guards watcher_, noticedAt_ and stop_
  std::condition_variable wake_;
  bool stop_ = false;
  Clock::time_point noticedAt_{};
  std::atomic<bool> changed_{false};
  std::thread thread_; // last: it starts once the rest is built
};

} // namespace bt
