// Issue 18's "physical and faithful mean brightness of every shared Quake 1 level agree within a
// factor of 1.5 with default settings" (lighting/README.md, "Physical mode", gives the measure).
//
// The levels: every file under ../shared/maps whose name ends in .map (recursively, sorted),
// imported as `render` imports it (LibreQuake's with its loose texture folders, as the other
// tests open it), kept when it is a Quake 1 level: the Standard or Valve 220 dialect read as
// Quake's (lighting/game_rules.h gameOf; Half-Life's Valve 220 and Hexen II are other games).
// A file that does not import is not a level and is listed as such.
//
// The measure: the mean Rec. 709 luminance of the linear beauty over every pixel of the level's
// default camera, at exposure 0 (before any tone map), on the CPU tracer, with `render`'s
// defaults but the size and samples: faithful per pixel (`--luxels off`), physical with 3
// bounces and the default firefly clamp. Automatic exposure would hide any mismatch, so the
// radiance itself is compared. A level both modes leave black (no light at all in view) agrees.
//
// DISABLED: it still fails, on real causes, and the bar is not to be loosened. Of the 149 Quake 1
// levels this ../shared holds (under a minute here), 60 are black in both, 54 agree, 14 are
// brighter in physical mode and 21 darker, none black in physical mode only (bench/README.md,
// "Issue 18: faithful against physical brightness", after the display match, the 128-unit match
// of linear lights, the camera's sky and unlit liquids, physical minlight, light colours
// linearised, suns kept to their `_suntexture` and the sky lighting by its dome alone): 10 of the
// 16 levels people play agree (e1m1 0.97, dm3 1.19), lq_e4m3 1.76, e4m8 2.34, dev 2.23, lq_e3m1
// 0.38, lqdm13 0.40, lqdm5 0.60 do not. What is left is mostly the game's display: light
// multiplied in gamma space is a power of the lightmap, which one linear scale matches at one
// lightmap value only (bright, overbright levels are darker in physical mode, dim ones brighter;
// the inverse square against linear lights far from and near to them), and liquids blended in
// gamma space. Run it with
// --gtest_also_run_disabled_tests; DISABLED_DiagnosticPrintsEachLevelsFigures prints each level's
// figures with physical mode's direct light beside them.
#include "importers/import.h"
#include "lighting/game_rules.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/exposure.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace bt {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 32, kHeight = 18;
constexpr float kMaxRatio = 1.5f;
constexpr double kBlack = 1e-4; // mean luminance: a level this dark in both modes shows nothing lit

std::vector<fs::path> sharedMapFiles(const fs::path& shared) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(shared / "maps"))
    if (entry.is_regular_file() && entry.path().extension() == ".map") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

ImportOptions importOptions(const fs::path& shared, const fs::path& map) {
  ImportOptions options;
  const fs::path wads = shared / "maps/librequake/texture-wads";
  if (map.string().find("/librequake/") != std::string::npos)
    for (const auto& dir : fs::directory_iterator(wads))
      if (dir.is_directory()) options.textures.textureDirs.push_back(dir.path().string());
  return options;
}

bool isQuake1Level(const Scene& scene) {
  return (scene.format == "standard" || scene.format == "valve220") && gameOf(scene) == Game::Quake;
}

double meanLuminance(const RenderScene& rs, const CameraPose& pose, LightingMode mode, int spp,
                     int bounces = IntegratorSettings{}.bounces) {
  RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.spp = spp;
  s.seed = 1;
  s.integrator.mode = mode;
  s.integrator.bounces = bounces;
  s.integrator.clampIndirect = kClampIndirectDefault; // render's default; its --bounces default is the struct's
  const RenderImage image = renderCpu(rs, Camera(pose, kWidth, kHeight), s);
  double sum = 0.0;
  for (const glm::vec3& p : image.beauty) sum += luminance(p);
  return sum / double(image.beauty.size());
}

// Calls fn(name, scene, render scene, pose) for every shared Quake 1 level; returns their count.
// BT_BRIGHTNESS_LEVELS (environment), when set: only the levels whose name holds one of its
// comma-separated parts, to iterate on a few levels in seconds rather than the whole set.
template <class Fn> int forEachQuake1Level(const fs::path& shared, Fn fn) {
  const char* only = std::getenv("BT_BRIGHTNESS_LEVELS");
  const auto wanted = [only](const std::string& name) {
    if (!only || !*only) return true;
    for (std::string rest = only; !rest.empty();) {
      const size_t comma = rest.find(',');
      const std::string part = rest.substr(0, comma);
      if (!part.empty() && name.find(part) != std::string::npos) return true;
      rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    }
    return false;
  };
  int levels = 0;
  for (const fs::path& file : sharedMapFiles(shared)) {
    const std::string name = fs::relative(file, shared / "maps").string();
    if (!wanted(name)) continue;
    Scene scene;
    try {
      scene = importScene(file.string(), importOptions(shared, file));
    } catch (const std::exception& e) {
      std::printf("%-70s not a level: %s\n", name.c_str(), e.what());
      continue;
    }
    if (!isQuake1Level(scene)) continue;
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    fn(name, rs, defaultCameraPose(scene));
    ++levels;
  }
  return levels;
}

TEST(PhysicalBrightness, DISABLED_EverySharedQuake1LevelAgreesWithFaithfulWithinOneAndAHalf) {
  BT_REQUIRE_SHARED(shared);
  const int levels = forEachQuake1Level(shared, [](const std::string& name, const RenderScene& rs, const CameraPose& pose) {
    const double faithful = meanLuminance(rs, pose, LightingMode::Faithful, 1);
    const double physical = meanLuminance(rs, pose, LightingMode::Physical, 8);
    const double ratio = physical / std::max(faithful, 1e-12);
    std::printf("%-70s faithful %.5f physical %.5f ratio %.3f\n", name.c_str(), faithful, physical, ratio);
    if (faithful < kBlack && physical < kBlack) return;
    EXPECT_LE(ratio, kMaxRatio) << name << ": physical is brighter than faithful";
    EXPECT_GE(ratio, 1.0 / kMaxRatio) << name << ": physical is darker than faithful";
  });
  std::printf("%d Quake 1 levels\n", levels);
  EXPECT_GT(levels, 0);
}

// Not a test: the figures behind bench/README.md's table, with physical mode's direct light alone
// (no bounce) beside them, to tell the bounces' share from the lights' own. Run it with
// --gtest_also_run_disabled_tests --gtest_filter=*Diagnostic*.
TEST(PhysicalBrightness, DISABLED_DiagnosticPrintsEachLevelsFigures) {
  BT_REQUIRE_SHARED(shared);
  forEachQuake1Level(shared, [](const std::string& name, const RenderScene& rs, const CameraPose& pose) {
    const double faithful = meanLuminance(rs, pose, LightingMode::Faithful, 1);
    const double physical = meanLuminance(rs, pose, LightingMode::Physical, 8);
    const double direct = meanLuminance(rs, pose, LightingMode::Physical, 8, 0);
    std::printf("%-70s faithful %.5f physical %.5f direct %.5f ratio %.3f direct ratio %.3f\n", name.c_str(), faithful, physical, direct,
                physical / std::max(faithful, 1e-12), direct / std::max(faithful, 1e-12));
  });
}

} // namespace
} // namespace bt
