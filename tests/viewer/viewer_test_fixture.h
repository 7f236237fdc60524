// The viewer tests' room, fixture and image helpers (tests/viewer/viewer_window_test.cpp,
// viewer_feedback_test.cpp: one binary, run under xvfb-run).
#pragma once

#include "viewer/viewer.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace bt::viewer_test {

namespace fs = std::filesystem;

// A closed 256-unit room (six brushes) of texture "wall" with one light in the middle, Valve 220;
// the player starts at x = playerX.
inline std::string roomMap(int lightValue, int playerX = -96) {
  auto brush = [](int x0, int y0, int z0, int x1, int y1, int z1) {
    auto face = [](int ax, int ay, int az, int bx, int by, int bz, int cx, int cy, int cz, const char* axes) {
      char line[256];
      std::snprintf(line, sizeof line, "( %d %d %d ) ( %d %d %d ) ( %d %d %d ) wall %s 0 1 1\n", ax, ay, az, bx, by, bz, cx, cy, cz, axes);
      return std::string(line);
    };
    std::string b = "{\n";
    b += face(x0, y0, z0, x0, y0 + 1, z0, x0, y0, z0 + 1, "[ 0 1 0 0 ] [ 0 0 -1 0 ]"); // -X
    b += face(x1, y1, z1, x1, y1, z1 + 1, x1, y1 + 1, z1, "[ 0 1 0 0 ] [ 0 0 -1 0 ]"); // +X
    b += face(x0, y0, z0, x0, y0, z0 + 1, x0 + 1, y0, z0, "[ 1 0 0 0 ] [ 0 0 -1 0 ]"); // -Y
    b += face(x1, y1, z1, x1 + 1, y1, z1, x1, y1, z1 + 1, "[ 1 0 0 0 ] [ 0 0 -1 0 ]"); // +Y
    b += face(x0, y0, z0, x0 + 1, y0, z0, x0, y0 + 1, z0, "[ 1 0 0 0 ] [ 0 -1 0 0 ]"); // -Z
    b += face(x1, y1, z1, x1, y1 + 1, z1, x1 + 1, y1, z1, "[ 1 0 0 0 ] [ 0 -1 0 0 ]"); // +Z
    return b + "}\n";
  };
  std::string map = "// Game: Quake\n// Format: Valve\n{\n\"classname\" \"worldspawn\"\n\"mapversion\" \"220\"\n";
  map += brush(-144, -144, -144, -128, 144, 144) + brush(128, -144, -144, 144, 144, 144);
  map += brush(-128, -144, -144, 128, -128, 144) + brush(-128, 128, -144, 128, 144, 144);
  map += brush(-128, -128, -144, 128, 128, -128) + brush(-128, -128, 128, 128, 128, 144);
  map += "}\n{\n\"classname\" \"light\"\n\"origin\" \"0 0 64\"\n\"light\" \"" + std::to_string(lightValue) + "\"\n}\n";
  map += "{\n\"classname\" \"info_player_start\"\n\"origin\" \"" + std::to_string(playerX) + " 0 -64\"\n\"angle\" \"0\"\n}\n";
  return map;
}

class ViewerWindowTest : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("bt_view_" + std::to_string(std::random_device{}()));
    fs::create_directories(dir_);
    map_ = dir_ / "room.map";
    std::ofstream(map_) << roomMap(300);
    // The loose texture beside the map (<map dir>/textures), as LibreQuake and ports keep them.
    writeTexture(dir_ / "textures/wall.png", 128);
    writeTexture(dir_ / "textures/wall_norm.png", 128); // a companion map: read, so watched
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }

  // An editor's save: a temporary file renamed over the map.
  void save(const std::string& text) {
    std::ofstream(dir_ / "room.map.tmp") << text;
    fs::rename(dir_ / "room.map.tmp", map_);
  }

  // A 16x16 grey PNG, saved the way an image editor does (a temporary file renamed over it).
  static void writeTexture(const fs::path& png, uint8_t grey) {
    fs::create_directories(png.parent_path());
    const fs::path temp = png.parent_path() / ("saving-" + png.filename().string());
    const std::vector<uint8_t> pixels(16 * 16 * 3, grey);
    auto out = OIIO::ImageOutput::create(temp.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(temp.string(), OIIO::ImageSpec(16, 16, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
    ASSERT_TRUE(out->close());
    fs::rename(temp, png);
  }

  ViewerOptions options() const {
    ViewerOptions o;
    o.map = map_.string();
    o.width = 96;
    o.height = 64;
    o.screenshotDir = dir_;
    // The GL tracer, which the automatic choice passes over on Xvfb's llvmpipe: these tests are
    // the GL window's (viewer_cpu_test.cpp has the CPU window's).
    o.backend = ViewerBackend::Gl;
    return o;
  }

  // Runs frames until `done` or a time limit: reloads wait for the watcher's debounce.
  template <typename Pred> static bool frameUntil(Viewer& viewer, Pred done, double seconds = 120.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      if (!viewer.frame()) return false;
      if (done()) return true;
    }
    return false;
  }

  fs::path dir_, map_;
};

// The largest difference of a colour channel between the PNG and the window's display image
// (RGBA8), or 256 when they differ in size.
inline int largestDifference(const fs::path& png, const Viewer::DisplayImage& shown) {
  auto in = OIIO::ImageInput::open(png.string());
  if (!in) return 256;
  const auto& spec = in->spec();
  if (spec.width != shown.width || spec.height != shown.height || spec.nchannels != 3) return 256;
  std::vector<uint8_t> pixels(size_t(spec.width) * spec.height * 3);
  in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data());
  int worst = 0;
  for (size_t i = 0; i < pixels.size() / 3; ++i)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(pixels[3 * i + c]) - int(shown.rgba[4 * i + c])));
  return worst;
}

inline double meanPixel(const fs::path& png) {
  auto in = OIIO::ImageInput::open(png.string());
  if (!in) return -1.0;
  const auto& spec = in->spec();
  std::vector<uint8_t> pixels(size_t(spec.width) * spec.height * spec.nchannels);
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data());
  double sum = 0.0;
  for (uint8_t p : pixels) sum += p;
  return sum / pixels.size();
}

} // namespace bt::viewer_test
