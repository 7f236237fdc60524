#include "viewer/watcher_thread.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

namespace bt {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class WatcherThreadTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("bt_watch_thread_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    map_ = dir_ / "level.map";
    std::ofstream(map_) << "{}\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  void saveByRename(const fs::path& file, const std::string& text) {
    std::ofstream(dir_ / "saving.tmp") << text;
    fs::rename(dir_ / "saving.tmp", file);
  }

  fs::path dir_, map_;
};

// The owner does nothing meanwhile, as a viewer in the middle of a frame that takes seconds:
// the thread notices the save by itself, once the file has been quiet for the debounce time.
TEST_F(WatcherThreadTest, NoticesASaveWithinTheDebounceWithoutBeingPolled) {
  WatcherThread watcher(100ms);
  watcher.watch({map_});
  const auto saved = WatcherThread::Clock::now();
  saveByRename(map_, "{ \"classname\" \"worldspawn\" }\n");
  std::this_thread::sleep_for(600ms);
  ASSERT_TRUE(watcher.changed()) << "the save was not noticed while the owner was busy";
  const auto delay = watcher.noticedAt() - saved;
  EXPECT_GE(delay, 100ms) << "noticed before the file went quiet";
  EXPECT_LE(delay, 300ms) << "noticed long after the debounce";
  EXPECT_TRUE(watcher.takeChange());
  EXPECT_FALSE(watcher.takeChange()) << "one save reported twice";
}

TEST_F(WatcherThreadTest, IgnoresFilesItDoesNotWatchAndFilesThatAppear) {
  WatcherThread watcher(20ms);
  const fs::path texture = dir_ / "wall.png";
  watcher.watch({map_, texture}); // a file the import looked for and did not find
  saveByRename(dir_ / "other.map", "x");
  std::this_thread::sleep_for(200ms);
  EXPECT_FALSE(watcher.changed()) << "a file nobody watches changed the level";
  saveByRename(texture, "png");
  std::this_thread::sleep_for(200ms);
  EXPECT_TRUE(watcher.changed()) << "a watched file that appeared was not noticed";
}

} // namespace
} // namespace bt
