// The viewer in a real window. CTest runs this binary under xvfb-run (tests/viewer/CMakeLists.txt)
// with BT_GL_DEBUG=1; without a display it exits with kSkipped, which ctest reports as skipped.
#include "renderer/difference.h"
#include "tests/test_data.h"
#include "viewer/viewer.h"
#include "tests/viewer/viewer_test_fixture.h"

#include "renderer/cpu/cpu_renderer.h"
#include "renderer/image_output.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

namespace bt {
namespace {

namespace fs = std::filesystem;

using namespace viewer_test;

TEST_F(ViewerWindowTest, OpensRefinesReloadsOnSaveAndTakesScreenshots) {
  Viewer viewer(options());
  EXPECT_EQ(viewer.camera().origin, glm::vec3(-96, 0, -42)) << "starts at the render camera (player start + 22)";

  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 3; })) << "no progressive refinement";

  const fs::path first = viewer.screenshot();
  ASSERT_TRUE(fs::exists(first));
  EXPECT_TRUE(fs::exists(fs::path(first).replace_extension(".exr")));
  const double lit = meanPixel(first);
  EXPECT_GT(lit, 5.0) << "the lit room rendered black";
  // The window shows the GPU's tonemap of the accumulated sum; the PNG is the CPU's tonemap
  // of the same sum read back.
  EXPECT_LE(largestDifference(first, viewer.displayed()), 1) << "the screen and the screenshot differ";

  // A save that brightens the light reloads the level, keeps the camera and restarts
  // refinement. The save also moves the player start, where a camera reset would go.
  save(roomMap(900, 64));
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.reloads() == 1; })) << "the save was not noticed";
  EXPECT_TRUE(viewer.error().empty());
  EXPECT_EQ(viewer.camera().origin, glm::vec3(-96, 0, -42)) << "the reload moved the camera";
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 3; }));
  const fs::path brighter = viewer.screenshot();
  EXPECT_NE(brighter, first) << "a screenshot overwrote the previous one";
  EXPECT_GT(meanPixel(brighter), lit) << "the reloaded light is not brighter";

  // A broken save keeps the last good level on screen and reports the error.
  save("{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 1 0");
  ASSERT_TRUE(frameUntil(viewer, [&] { return !viewer.error().empty(); })) << "the broken save was not reported";
  EXPECT_NE(viewer.error().find("room.map"), std::string::npos) << viewer.error();
  EXPECT_EQ(viewer.reloads(), 1);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));

  // The other views render too.
  viewer.setMode(ViewMode::Fullbright);
  EXPECT_TRUE(viewer.frame());
  viewer.setMode(ViewMode::Normal);
  EXPECT_TRUE(viewer.frame());
  EXPECT_GT(meanPixel(viewer.screenshot()), 5.0);
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

TEST_F(ViewerWindowTest, ReloadsWhenATextureImageOrCompanionMapTheMapUsesIsSaved) {
  Viewer viewer(options());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 2; }));
  const double grey = meanPixel(viewer.screenshot());
  EXPECT_GT(grey, 5.0);

  // An image in the same folder that the map does not use is not watched: no reload within
  // several debounce intervals (the watcher's is 250 ms).
  writeTexture(dir_ / "textures/unused.png", 255);
  EXPECT_FALSE(frameUntil(
      viewer, [&] { return viewer.reloads() > 0; }, 1.0))
      << "reloaded for a file the map does not use";

  writeTexture(dir_ / "textures/wall.png", 250);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.reloads() == 1; })) << "the texture's save was not noticed";
  EXPECT_TRUE(viewer.error().empty()) << viewer.error();
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 2; }));
  const fs::path brighter = viewer.screenshot();
  EXPECT_GT(meanPixel(brighter), grey * 1.3) << "the reloaded texture is not brighter";
  EXPECT_LE(largestDifference(brighter, viewer.displayed()), 1) << "the screen and the screenshot differ";

  // Companion maps are watched as well as the base image.
  writeTexture(dir_ / "textures/wall_norm.png", 127);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.reloads() == 2; })) << "the companion map's save was not noticed";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

// Faithful mode bakes the level's luxels on the GPU over the first frames, then shows what
// `render` shows: the same stream of samples from the same luxels, so after the bake the
// viewer's image equals the CPU's render of the same camera and sample count.
TEST_F(ViewerWindowTest, BakesTheLuxelsThenShowsWhatRenderShows) {
  ViewerOptions o = options();
  Viewer viewer(o);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.luxelsBaked() && viewer.samples() >= 2; })) << "the bake never ended";
  const Viewer::DisplayImage shown = viewer.displayed();

  const Scene scene = importScene(o.map, o.import);
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  rs.lightmaps = layoutLightmaps(rs);
  bakeLightmaps(rs, rs.lightmaps);
  RenderSettings settings;
  settings.width = o.width;
  settings.height = o.height;
  settings.spp = viewer.samples();
  const RenderImage cpu = renderCpu(rs, Camera(viewer.camera(), o.width, o.height), settings);
  const fs::path png = dir_ / "cpu.png";
  writeImage(png.string(), cpu, OutputSettings{});
  const int worst = largestDifference(png, shown);
  EXPECT_LE(worst, 2) << "the viewer's baked luxels are not render's";

  // The comparison can tell: luxels of a light 5 % brighter are another picture.
  for (GpuLight& light : rs.lights) light.color *= 1.05f;
  bakeLightmaps(rs, rs.lightmaps);
  writeImage(png.string(), renderCpu(rs, Camera(viewer.camera(), o.width, o.height), settings), OutputSettings{});
  EXPECT_GT(largestDifference(png, shown), 4) << "a 5 % brighter light looks the same: the test cannot tell";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

TEST_F(ViewerWindowTest, DrawsPhysicalLighting) {
  Viewer viewer(options());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 2; }));
  const fs::path faithful = viewer.screenshot();

  viewer.setLighting(LightingMode::Physical);
  EXPECT_EQ(viewer.samples(), 0) << "switching the lighting restarts refinement";
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 4; }));
  const fs::path physical = viewer.screenshot();
  EXPECT_GT(meanPixel(physical), 5.0) << "the physically lit room rendered black";
  EXPECT_GT(std::abs(meanPixel(physical) - meanPixel(faithful)), 1.0) << "the physical image is the faithful one";
  // Physical lighting is shown through ACES, on screen as in the PNG.
  EXPECT_LE(largestDifference(physical, viewer.displayed()), 1) << "the screen and the screenshot differ";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

// Key 6 shows a lit .bsp's own lightmaps, key 7 where they differ from faithful light as the
// heat map render --lighting difference draws (every pixel a colour of its scale); a level
// without lightmaps keeps faithful light and says why.
TEST_F(ViewerWindowTest, ShowsTheCompiledLightmapsAndTheirDifference) {
  {
    Viewer room(options());
    EXPECT_FALSE(room.showCompiled());
    EXPECT_NE(room.notice().find("not a compiled .bsp"), std::string::npos) << room.notice();
    EXPECT_FALSE(room.showDifference());
  }
  BT_REQUIRE_SHARED(shared);
  ViewerOptions o = options();
  // Faithful light per pixel (--luxels off: the light itself, not the compiler's 16-texel luxels
  // filtered), so that switching views shows: baked into luxels, faithful mode now gives this
  // level's .bsp the compiler's own light (its `_surface` points are the compiler's: issue 14),
  // and the two agree within 8/255.
  o.map = (shared / "oracle/lit/maps_ericw-tools_testmaps_deprecated_testsurfacelight.bsp").string();
  o.luxels = false;
  Viewer viewer(o);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 2; }));
  const fs::path faithful = viewer.screenshot();
  ASSERT_TRUE(viewer.showCompiled()) << viewer.notice();
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 2; }));
  const fs::path compiled = viewer.screenshot();
  EXPECT_LE(largestDifference(compiled, viewer.displayed()), 1) << "the screen and the screenshot differ";
  EXPECT_GT(largestDifference(faithful, viewer.displayed()), 8) << "the compiled view is the faithful one";

  ASSERT_TRUE(viewer.showDifference());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 4; }));
  const Viewer::DisplayImage heat = viewer.displayed();
  size_t offScale = 0, coloured = 0;
  for (size_t i = 0; i + 3 < heat.rgba.size(); i += 4) {
    int best = 256;
    for (int steps = 0; steps <= kDifferenceFullScale; ++steps) {
      const glm::vec3 c = differenceColour(steps) * 255.0f;
      best = std::min(best,
                      std::max({std::abs(int(std::lround(c.x)) - heat.rgba[i]), std::abs(int(std::lround(c.y)) - heat.rgba[i + 1]),
                                std::abs(int(std::lround(c.z)) - heat.rgba[i + 2])}));
    }
    offScale += best > 1;
    coloured += heat.rgba[i] + heat.rgba[i + 1] + heat.rgba[i + 2] > 0;
  }
  EXPECT_EQ(offScale, 0u) << "pixels that are no colour of the heat scale";
  EXPECT_GT(coloured, 0u) << "the compiled and faithful light agree everywhere: the map shows nothing";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

// q3map2 strips the light entities from a compiled Quake 3 level: without --lighting the viewer
// opens one in the compiled view (as render does), with a note saying why; asked for faithful
// light (its shaders' light only), it keeps it.
TEST_F(ViewerWindowTest, OpensACompiledQuake3LevelInTheCompiledView) {
  const fs::path openArena = "/usr/share/games/openarena/baseoa/pak1-maps.pk3";
  if (!fs::exists(openArena)) GTEST_SKIP() << openArena << " not found: the Quake 3 default is not checked";
  ViewerOptions o = options();
  o.map = openArena.string() + ":maps/aggressor.bsp";
  const auto shownAfterOneSample = [&](Viewer& viewer) {
    EXPECT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));
    return viewer.displayed();
  };
  o.lightingGiven = true; // --lighting faithful: the level's lights, which q3map2 removed
  Viewer::DisplayImage faithful;
  {
    Viewer told(o); // one window at a time (ImGui's context is global)
    EXPECT_EQ(told.note(), "");
    faithful = shownAfterOneSample(told);
  }
  o.lightingGiven = false;
  Viewer viewer(o);
  EXPECT_NE(viewer.note().find("a compiled Quake 3 level keeps no lights"), std::string::npos) << viewer.note();
  EXPECT_EQ(viewer.notice(), "");
  const Viewer::DisplayImage compiled = shownAfterOneSample(viewer);
  ASSERT_EQ(compiled.rgba.size(), faithful.rgba.size());
  // Faithful light here is the shaders' light alone (sky suns, surface lights: q3map2 keeps
  // those), the compiled view q3map2's lightmaps of every light: pictures far apart.
  size_t differing = 0;
  for (size_t i = 0; i + 3 < compiled.rgba.size(); i += 4) {
    const int c = compiled.rgba[i] + compiled.rgba[i + 1] + compiled.rgba[i + 2];
    differing += std::abs(c - (faithful.rgba[i] + faithful.rgba[i + 1] + faithful.rgba[i + 2])) > 24;
  }
  EXPECT_GT(differing, compiled.rgba.size() / 4 / 10) << "the compiled view shows the lightmaps, not faithful light";
}

} // namespace
} // namespace bt

// ctest's SKIP_RETURN_CODE for this test (tests/viewer/CMakeLists.txt): no display is a skip,
// not a pass.
constexpr int kSkipped = 77;

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  if (!std::getenv("DISPLAY")) {
    std::fprintf(stderr, "viewer_window_tests: no X display (run under xvfb-run, as ctest does where it has it): skipped\n");
    return kSkipped;
  }
  return RUN_ALL_TESTS();
}
