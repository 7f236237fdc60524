// Issue 22, "Done when" 3: the Half-Life and Quake 3 levels of ../shared/maps render with
// believable light in both modes. Each level is rendered small from its default camera on the
// CPU tracer, faithful (light at each pixel's point, the game's display) and physical (automatic
// exposure, ACES, as `render` writes a PNG), and the displayed luminance of the pixels that show
// a lit surface (not sky, not the void, not unlit liquids) must have a mean and a spread that a
// black or a white picture fails. Each level's figures are printed for the closing note.
//
// Two Half-Life levels are dark where their player starts, in the game too: ericw-tools lights
// hl_basic's room with one `_light` 200 (linear, reach 200) above the ceiling's middle and
// hl_light_black with one narrow spotlight, and the walls the eye sees get no light (their
// compiled luxels are 0). Faithful mode shows the game, so there it must show what the compiled
// level (../shared/oracle/lit-games/) shows through GoldSrc's display from the same camera, dark
// as it is. In physical mode hl_light_black's room is lit by what its one spot's disc on the far
// wall bounces: paths find that small disc rarely, so its picture needs many samples before the
// walls come out of black (black share 80 / 44 / 20 / 6 / 0 % at 32 / 128 / 256 / 512 / 2048 spp;
// mean 0.43 converged), so it is measured at 512 spp (about 3 s of this test).
#include "importers/import.h"
#include "lighting/compiled_lightmaps.h"
#include "renderer/camera.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/exposure.h"
#include "renderer/render.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace bt {
namespace {

constexpr int kWidth = 64, kHeight = 36;

// The levels: every .map under ../shared/maps that reads as Half-Life (WAD3 textures, or in a
// Half-Life test folder) or Quake 3, and has a light source. hl_currents has none (its compile's
// lightmaps are empty, 0 bytes) and the TrenchBroom fixtures are parser fixtures without WADs.
struct Level {
  const char* path;
  const char* game;         // --game
  const char* darkCompiled; // faithful: held to this compiled level's view (lit-games), not the bar
  int physicalSpp = 8;      // enough for the figures; a small level lit by bounce light needs more
};
constexpr Level kLevels[] = {
    {"ericw-tools/testmaps/hl_basic.map", "halflife", "maps_ericw-tools_testmaps_hl_basic.bsp", 32},
    {"ericw-tools/testmaps/hl_light_black.map", "halflife", "maps_ericw-tools_testmaps_hl_light_black.bsp", 512},
    {"unvanquished-plat23/maps/plat23.map", "quake3", nullptr},
    {"unvanquished-chasm/maps/chasm.map", "quake3", nullptr},
};

// The displayed luminance (Rec. 709 of the 8-bit sRGB values, 0..1) of the lit surfaces' pixels.
struct Figures {
  size_t pixels = 0;
  double mean = 0.0, deviation = 0.0, p10 = 0.0, p50 = 0.0, p90 = 0.0, black = 0.0, white = 0.0;

  std::string describe() const {
    return fmt::format("{} pixels, mean {:.3f}, sd {:.3f}, p10 {:.3f}, p50 {:.3f}, p90 {:.3f}, black {:.0f} %, white {:.0f} %", pixels,
                       mean, deviation, p10, p50, p90, 100.0 * black, 100.0 * white);
  }
};

Figures figures(const RenderScene& rs, const RenderImage& image, const OutputSettings& output) {
  const std::vector<uint8_t> rgb = displayPixels(image, output);
  std::vector<double> l;
  for (size_t i = 0; i < image.face.size(); ++i) {
    if (image.face[i] == 0) continue;
    const uint32_t flags = rs.faceFlags[image.face[i] - 1];
    if ((flags & kFaceSky) || ((flags & kFaceLiquid) && !rs.world.litwater)) continue;
    l.push_back((0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2]) / 255.0);
  }
  Figures f;
  f.pixels = l.size();
  if (l.empty()) return f;
  std::sort(l.begin(), l.end());
  for (double v : l) f.mean += v / double(l.size());
  for (double v : l) f.deviation += (v - f.mean) * (v - f.mean) / double(l.size());
  f.deviation = std::sqrt(f.deviation);
  const auto at = [&](double q) { return l[std::min(l.size() - 1, size_t(q * double(l.size())))]; };
  f.p10 = at(0.1), f.p50 = at(0.5), f.p90 = at(0.9);
  f.black = double(std::count_if(l.begin(), l.end(), [](double v) { return v < 2.0 / 255.0; })) / double(l.size());
  f.white = double(std::count_if(l.begin(), l.end(), [](double v) { return v > 253.0 / 255.0; })) / double(l.size());
  return f;
}

// Believable: a lit picture with shadows and light, neither black nor white. A black picture
// fails the mean, the black share and the spread (standard deviation); a white one the mean, the
// white share and the spread.
void expectBelievable(const Figures& f, const std::string& what) {
  EXPECT_GT(f.pixels, size_t(kWidth * kHeight / 4)) << what << ": the camera sees too little of the level";
  EXPECT_GT(f.mean, 0.05) << what << ": too dark: " << f.describe();
  EXPECT_LT(f.mean, 0.85) << what << ": too bright: " << f.describe();
  EXPECT_GT(f.deviation, 0.02) << what << ": no light and shade: " << f.describe();
  EXPECT_LT(f.black, 0.5) << what << ": mostly black: " << f.describe();
  EXPECT_LT(f.white, 0.5) << what << ": mostly white: " << f.describe();
}

// The compiled level `bsp` from `pose`, as `--lighting compiled` shows it.
Figures compiledFigures(const std::filesystem::path& bsp, const CameraPose& pose) {
  const Scene scene = importScene(bsp.string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diagnostics);
  EXPECT_EQ(showCompiledLightmaps(scene, rs, ""), "");
  RenderSettings settings;
  settings.width = kWidth, settings.height = kHeight, settings.threads = 2, settings.spp = 1;
  return figures(rs, renderCpu(rs, Camera(pose, kWidth, kHeight), settings), OutputSettings{});
}

TEST(BelievableLight, HalfLifeAndQuake3LevelsInBothModes) {
  BT_REQUIRE_SHARED(shared);
  for (const Level& level : kLevels) {
    SCOPED_TRACE(level.path);
    ImportOptions options;
    options.textures.game.game = level.game;
    const Scene scene = importScene((shared / "maps" / level.path).string(), options);
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diagnostics);
    const CameraPose pose = defaultCameraPose(scene);
    const Camera camera(pose, kWidth, kHeight);
    RenderSettings settings;
    settings.width = kWidth, settings.height = kHeight, settings.threads = 2;

    settings.spp = 1; // faithful light at each pixel's point: exact at one sample, but for soft lights
    const RenderImage faithful = renderCpu(rs, camera, settings);
    const Figures f = figures(rs, faithful, OutputSettings{});
    std::printf("%s", fmt::format("believable {} faithful: {}\n", level.path, f.describe()).c_str());
    if (level.darkCompiled) {
      const Figures c = compiledFigures(shared / "oracle" / "lit-games" / level.darkCompiled, pose);
      std::printf("%s", fmt::format("believable {} compiled (the game): {}\n", level.path, c.describe()).c_str());
      EXPECT_NEAR(f.mean, c.mean, 0.01) << "faithful: " << f.describe() << "; compiled: " << c.describe();
      EXPECT_NEAR(f.p90, c.p90, 0.03) << "faithful: " << f.describe() << "; compiled: " << c.describe();
    } else {
      expectBelievable(f, "faithful");
    }

    settings.spp = level.physicalSpp;
    settings.integrator.mode = LightingMode::Physical;
    settings.integrator.bounces = 2;
    const RenderImage physical = renderCpu(rs, camera, settings);
    OutputSettings output;
    output.tonemap = Tonemap::Aces;
    output.exposureEv = autoExposureEv(physical.beauty, kWidth, kHeight);
    const Figures p = figures(rs, physical, output);
    std::printf("%s",
                fmt::format("believable {} physical: exposure {:+.2f} EV, {}\n", level.path, output.exposureEv, p.describe()).c_str());
    expectBelievable(p, "physical");
  }
}

} // namespace
} // namespace bt
