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
// Enabled with a held list (kHeld below): the levels that still fail, each with why, as far as
// analysed; the bar is not loosened for them, and a held level that comes to agree fails the test
// until it is taken off the list. Of the 149 Quake 1 levels this ../shared holds (about 25 s
// here), 60 are black in both, 59 agree and 30 are held (bench/README.md, "Issue 18: faithful
// against physical brightness", bright18d: each Quake light matched over the surfaces its light
// lands on; bright18g: the minlight as the game's display shows it). Run
// --gtest_also_run_disabled_tests --gtest_filter=*Diagnostic* for each level's figures with
// physical mode's direct light beside them; BT_BRIGHTNESS_LEVELS=a,b runs a few levels.
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
#include <map>
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
  // PCG's samples, those the figures and the held list were taken with: at 8 spp the Sobol
  // sequence's noise moves some dark levels 7-16 % (hl_light_black 0.583 against 0.693, the two
  // samplers within 1 % of each other at 256 spp: noise, not a bias).
  s.integrator.lowDiscrepancy = false;
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

// Why each held level is left outside 1.5x (its ratio, physical / faithful, when it was held; "lin."
// the same with faithful mode's display made linear, srgbToLinear(texture) x lightmap / 128 x k,
// a local patch of bench/README.md's bright18e section: within 1.5x there, the display is the cause).
const char* const kStackedWater = "two layers of translucent water (_wateralpha 0.5: the box's far side seen through its near "
                                  "one) over an unlit void: the game composites them in gamma space, srgbToLinear(0.75 s(t)) "
                                  "= 0.53 t, a linear blend 0.21 t + 0.79 x 0.21 t = 0.38 t";
const char* const kDisplayPower = "the game's display is about L^2.2 of the lightmap, physical light linear, matched at one "
                                  "lightmap value (k): a mostly overbright view is darker, a dim one brighter";
const char* const kHotSpot = "strong lights near what they light: the compiler's luxels stop at 255, the inverse square does not";
const char* const kSurface = "_surface templates: an area emitter in physical mode, the compiler's point lights in faithful mode";
const char* const kUnmodelled = "a key neither mode models (_lightignore; _switchableshadow), so faithful is no reference here";
const char* const kNearWall = "a light a few units from a face: the landing match counts its wall at 16 units and at grazing "
                              "incidence; agreed under the fixed 128-unit match (0.79-0.94), not analysed further";
const char* const kOpaqueWater = "water the game draws opaque (r_wateralpha 1) in view, physical mode at kPhysicalWaterOpacity "
                                 "0.5 (issue 16); the camera at the game's opacity brought it in, but took pools.map's water "
                                 "out of its documented colour range (bench/README.md, bright18d)";
const char* const kLongReach = "linear lights of long reach (wait 0.3, or light 550-600): matched over all they land on, "
                               "the inverse square puts more of it on the near walls in view than the compiler's straight "
                               "falloff, less on the far ones";
const char* const kNoCosine = "_anglesense 0 spotlights (delay 3): the compiler lights the grazing floor without the cosine "
                              "of incidence, Lambert with it (the globes alone 0.08; at _anglesense 1 0.71)";
const std::map<std::string, const char*> kHeld = {
    {"ericw-tools/testmaps/deprecated/bouncecolorscaletest.map", kHotSpot},                 // 3.34: light 10000 delay 2
    {"ericw-tools/testmaps/deprecated/calcpointstest.map", kDisplayPower},                  // 2.44, lin. 0.86 (held as hot spots before)
    {"ericw-tools/testmaps/deprecated/dirttest2.map", kLongReach},                          // 2.14, lin. 2.78; _dirt is 4 % of it
    {"ericw-tools/testmaps/deprecated/falloff.map", kDisplayPower},                         // 0.57, lin. 0.78 (held as kNearWall before)
    {"ericw-tools/testmaps/deprecated/glasstest.map", kNoCosine},                           // 0.52, lin. 0.60; 0.24 with minlight as shown
    {"ericw-tools/testmaps/deprecated/light_near_wall.map", kNearWall},                     // 0.63, lin. 0.56
    {"ericw-tools/testmaps/deprecated/offgrid_after.map", kDisplayPower},                   // 1.82, lin. 1.23 (held as kNearWall before)
    {"ericw-tools/testmaps/deprecated/offgrid_before.map", kDisplayPower},                  // 1.82, lin. 1.24 (held as kNearWall before)
    {"ericw-tools/testmaps/deprecated/shadowself_shadow.map", kDisplayPower},               // 0.62, lin. 1.41: delay 2 light 500
    {"ericw-tools/testmaps/deprecated/stairsteptest.map", kDisplayPower},                   // 0.60, lin. 1.15: three delay 2 lights
    {"ericw-tools/testmaps/deprecated/testrotators_bmodel.map", kDisplayPower},             // 2.12, lin. 0.87: faithful about 1e-4
    {"ericw-tools/testmaps/deprecated/testslime.map", kDisplayPower},                       // 0.55, lin. 1.20: one delay 2 light
    {"ericw-tools/testmaps/deprecated/testsurfacelight.map", kSurface},                     // 0.17
    {"ericw-tools/testmaps/q1_extract_textures.map", kOpaqueWater},                         // 0.51
    {"ericw-tools/testmaps/q1_func_illusionary_visblocker.map", kOpaqueWater},              // 0.47
    {"ericw-tools/testmaps/q1_func_illusionary_visblocker_interactions.map", kOpaqueWater}, // 0.47
    {"ericw-tools/testmaps/q1_light_bounce_litwater.map", kOpaqueWater},                    // 0.56
    {"ericw-tools/testmaps/q1_liquid_software.map", kOpaqueWater},                          // 0.53
    {"ericw-tools/testmaps/q1_tjunc_matrix.map", kOpaqueWater},                             // 0.51
    {"ericw-tools/testmaps/light_general.map", kLongReach},                                 // 0.37, lin. 0.67 (0.21 before)
    {"ericw-tools/testmaps/phongtest2.map", kDisplayPower},                                 // 0.54, lin. 1.01: _sunlight 300
    {"ericw-tools/testmaps/q1_light_switchableshadow_selfshadows.map", kUnmodelled},        // 0.61, lin. 0.95
    {"ericw-tools/testmaps/q1_light_switchableshadow_target.map", kUnmodelled},             // 0.61, lin. 0.84
    {"ericw-tools/testmaps/q1_lightignore.map", kUnmodelled},                               // 1.99, lin. 1.08
    {"ericw-tools/testmaps/q1_loose_textures_ignored/q1_loose_textures_ignored.map", kStackedWater}, // 0.58 (1.71 before)
    {"ericw-tools/testmaps/q1_surflight_minlight.map", kSurface},                                    // 1.67
    {"librequake/lq1/maps/src/dm/lqdm13.map", kDisplayPower},                                        // 0.42, lin. 0.74
    {"librequake/lq1/maps/src/e3/lq_e3m1.map", kDisplayPower},                                       // 0.48, lin. 0.85: _sunlight 400 walls
    {"quake_map_source/dm3.map", kLongReach}, // 1.58, lin. 1.48 (1.19 under the fixed 128-unit match)
    {"quake_map_source/e4m8.map", kHotSpot},  // 2.55, lin. 2.36 (2.34 before)
};

TEST(PhysicalBrightness, EverySharedQuake1LevelButTheHeldAgreesWithFaithfulWithinOneAndAHalf) {
  BT_REQUIRE_SHARED(shared);
  int held = 0;
  const int levels = forEachQuake1Level(shared, [&held](const std::string& name, const RenderScene& rs, const CameraPose& pose) {
    const double faithful = meanLuminance(rs, pose, LightingMode::Faithful, 1);
    const double physical = meanLuminance(rs, pose, LightingMode::Physical, 8);
    const double ratio = physical / std::max(faithful, 1e-12);
    std::printf("%-70s faithful %.5f physical %.5f ratio %.3f\n", name.c_str(), faithful, physical, ratio);
    const bool black = faithful < kBlack && physical < kBlack;
    const bool agrees = black || (ratio <= kMaxRatio && ratio >= 1.0 / kMaxRatio);
    if (const auto h = kHeld.find(name); h != kHeld.end()) {
      ++held;
      EXPECT_FALSE(agrees) << name << " now agrees (ratio " << ratio << "): take it off kHeld (" << h->second << ")";
      return;
    }
    if (black) return;
    EXPECT_LE(ratio, kMaxRatio) << name << ": physical is brighter than faithful";
    EXPECT_GE(ratio, 1.0 / kMaxRatio) << name << ": physical is darker than faithful";
  });
  std::printf("%d Quake 1 levels, %d held\n", levels, held);
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
