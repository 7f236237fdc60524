// Watches a set of files for changes the way editors save them.
//
// TrenchBroom, J.A.C.K. and most text editors save by writing a temporary file and renaming it
// over the original, which replaces the inode: a watch on the file itself would go silent after
// the first save. So we watch each file's *directory* (inotify) and filter events by name.
// A save can also arrive as several writes; a change is reported only once the file has stopped
// changing for the debounce interval.
#pragma once

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace bt {

class FileWatcher {
public:
  using Clock = std::chrono::steady_clock;

  explicit FileWatcher(std::chrono::milliseconds debounce = std::chrono::milliseconds(250));
  ~FileWatcher();
  FileWatcher(const FileWatcher&) = delete;
  FileWatcher& operator=(const FileWatcher&) = delete;

  // Replaces the watched set (the map, and every WAD and texture file it resolved).
  void watch(const std::vector<std::filesystem::path>& files);

  // Drains pending events without blocking. Returns the files that changed and have been quiet
  // for the debounce interval since their last event; each change is reported once.
  std::vector<std::filesystem::path> poll(Clock::time_point now = Clock::now());

  bool valid() const { return fd_ >= 0; }

private:
  void drainEvents(Clock::time_point now);

  int fd_ = -1;
  std::chrono::milliseconds debounce_;
  std::map<int, std::filesystem::path> directories_;           // inotify watch descriptor -> directory
  std::set<std::filesystem::path> files_;                      // absolute, normalised paths
  std::map<std::filesystem::path, Clock::time_point> pending_; // last event time per changed file
};

} // namespace bt
