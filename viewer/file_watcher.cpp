#include "viewer/file_watcher.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <array>
#include <cerrno>

namespace bt {

namespace fs = std::filesystem;

namespace {
// Everything an editor's save can look like: in-place writes, create + write, rename over.
constexpr uint32_t kSaveEvents = IN_CLOSE_WRITE | IN_MODIFY | IN_MOVED_TO | IN_CREATE | IN_ATTRIB;

fs::path normalised(const fs::path& p) {
  std::error_code ec;
  fs::path abs = fs::absolute(p, ec);
  return (ec ? p : abs).lexically_normal();
}
} // namespace

FileWatcher::FileWatcher(std::chrono::milliseconds debounce) : fd_(inotify_init1(IN_NONBLOCK | IN_CLOEXEC)), debounce_(debounce) {}

FileWatcher::~FileWatcher() {
  if (fd_ >= 0) close(fd_);
}

void FileWatcher::watch(const std::vector<fs::path>& files) {
  if (fd_ < 0) return;
  for (const auto& [wd, dir] : directories_) inotify_rm_watch(fd_, wd);
  directories_.clear();
  files_.clear();
  pending_.clear();

  std::set<fs::path> dirs;
  for (const fs::path& f : files) {
    fs::path file = normalised(f);
    files_.insert(file);
    dirs.insert(file.parent_path());
  }
  for (const fs::path& dir : dirs) {
    int wd = inotify_add_watch(fd_, dir.c_str(), kSaveEvents);
    if (wd >= 0) directories_[wd] = dir;
  }
}

void FileWatcher::drainEvents(Clock::time_point now) {
  // inotify events are variable-length; the buffer must be aligned for inotify_event.
  alignas(inotify_event) std::array<char, 16 * 1024> buffer;
  for (;;) {
    ssize_t n = read(fd_, buffer.data(), buffer.size());
    if (n <= 0) return; // EAGAIN: nothing more pending
    for (ssize_t offset = 0; offset < n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(buffer.data() + offset);
      offset += static_cast<ssize_t>(sizeof(inotify_event) + event->len);
      auto dir = directories_.find(event->wd);
      if (dir == directories_.end() || event->len == 0) continue;
      fs::path file = dir->second / event->name;
      if (files_.count(file)) pending_[file] = now;
    }
  }
}

std::vector<fs::path> FileWatcher::poll(Clock::time_point now) {
  std::vector<fs::path> changed;
  if (fd_ < 0) return changed;
  drainEvents(now);
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (now - it->second >= debounce_) {
      changed.push_back(it->first);
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  return changed;
}

} // namespace bt
