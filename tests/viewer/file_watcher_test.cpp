#include "viewer/file_watcher.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

namespace bt {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

class FileWatcherTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("bt_watch_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    map_ = dir_ / "level.map";
    write(map_, "{}\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  static void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

  // How TrenchBroom saves: a temporary file renamed over the original.
  void saveByRename(const std::string& text) {
    fs::path tmp = dir_ / "level.map.tmp";
    write(tmp, text);
    fs::rename(tmp, map_);
  }

  fs::path dir_, map_;
};

TEST_F(FileWatcherTest, ReportsARenameOverSaveAfterTheDebounce) {
  FileWatcher watcher(100ms);
  ASSERT_TRUE(watcher.valid());
  watcher.watch({map_});
  auto t0 = FileWatcher::Clock::now();
  saveByRename("{ \"classname\" \"worldspawn\" }\n");
  EXPECT_TRUE(watcher.poll(t0 + 10ms).empty()) << "reported before the file went quiet";
  auto changed = watcher.poll(t0 + 200ms);
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0], map_.lexically_normal());
  EXPECT_TRUE(watcher.poll(t0 + 400ms).empty()) << "the same change reported twice";
}

TEST_F(FileWatcherTest, KeepsWatchingAfterTheInodeIsReplaced) {
  FileWatcher watcher(0ms);
  watcher.watch({map_});
  saveByRename("1");
  EXPECT_EQ(watcher.poll().size(), 1u);
  saveByRename("2");
  EXPECT_EQ(watcher.poll().size(), 1u);
}

TEST_F(FileWatcherTest, WaitsUntilTheFileStopsChanging) {
  FileWatcher watcher(100ms);
  watcher.watch({map_});
  auto t0 = FileWatcher::Clock::now();
  write(map_, "part 1");
  EXPECT_TRUE(watcher.poll(t0 + 90ms).empty()); // the first write is seen at 90 ms
  write(map_, "part 1 part 2");
  // 105 ms after the first write was seen: reported here if the second did not restart the
  // quiet period. The second is seen now, so the period runs to 295 ms.
  EXPECT_TRUE(watcher.poll(t0 + 195ms).empty()) << "the second write did not restart the quiet period";
  EXPECT_TRUE(watcher.poll(t0 + 280ms).empty());
  EXPECT_EQ(watcher.poll(t0 + 300ms).size(), 1u);
}

TEST_F(FileWatcherTest, IgnoresOtherFilesInTheDirectoryButWatchesTextures) {
  fs::path wad = dir_ / "textures.wad";
  write(wad, "WAD2");
  FileWatcher watcher(0ms);
  watcher.watch({map_, wad});
  write(dir_ / "autosave.map", "{}");
  EXPECT_TRUE(watcher.poll().empty());
  write(wad, "WAD2 changed");
  auto changed = watcher.poll();
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0], wad.lexically_normal());
}

} // namespace
} // namespace bt
