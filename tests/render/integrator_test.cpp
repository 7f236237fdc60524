// Analytic scenes: a lit floor per light type and formula, against the value worked out by
// hand (faithful mode) or the radiometric integral (physical mode), and a furnace.
#include "scene/color.h"
#include "lighting/physical_light.h"
#include "quake/bspfile_q2.h"
#include "renderer/camera.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/cpu/integrator.h"
#include "tests/render/box_scene.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace bt {
namespace {

// A white floor whose top is z = 0, large enough to be the only thing in view.
test::BoxSceneBuilder floorScene() {
  test::BoxSceneBuilder b;
  b.material("white", 255, 255, 255);
  b.box({-2048, -2048, -16}, {2048, 2048, 0}, "white");
  return b;
}

// A ray straight down onto the floor at (x, y).
Ray downAt(float x, float y) {
  return Ray{{x, y, 64.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 1e9f};
}

// The light sum a faithful render implies, recovered from the displayed radiance of a white
// texel: display = lightmap / 128, lightmap = sum * range.
float faithfulSumFromRadiance(const glm::vec3& radiance, float range = 0.5f) {
  return linearToSrgb(radiance.x) * 128.0f / range;
}

struct DelayCase {
  const char* delay;
  float expected; // light 300 at (0 0 80) seen from (60 0 0): dist 100, cos 0.8
};

TEST(FaithfulRender, LitFloorPerDelayMode) {
  const float angle = 0.5f + 0.5f * 0.8f; // half-Lambert at the default anglescale
  const DelayCase cases[] = {
      {"0", (300.0f - 100.0f) * angle},
      {"1", 300.0f * 128.0f / 100.0f * angle},
      {"2", 300.0f * 128.0f * 128.0f / (100.0f * 100.0f) * angle},
      {"3", 300.0f * angle},
      {"4", 300.0f * angle}, // local minlight alone: its own value
      {"5", 300.0f * 128.0f * 128.0f / (228.0f * 228.0f) * angle},
  };
  for (const DelayCase& c : cases) {
    test::BoxSceneBuilder b = floorScene();
    b.entity({{"classname", "light"}, {"origin", "0 0 80"}, {"delay", c.delay}});
    const Scene scene = b.build();
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    Rng rng = pixelRng(0, 0, 0, 0);
    const glm::vec3 l = radiance(rs, {LightingMode::Faithful, 0}, downAt(60.0f, 0.0f), rng);
    const float expectedLightmap = std::min(c.expected * 0.5f, 255.0f);
    EXPECT_NEAR(faithfulSumFromRadiance(l), expectedLightmap / 0.5f, 0.01f * expectedLightmap) << "delay " << c.delay;
  }
}

TEST(FaithfulRender, ShadowsSunAndMinlight) {
  test::BoxSceneBuilder b = floorScene();
  b.worldKey("_sunlight", "100");
  b.worldKey("light", "20");
  b.entity({{"classname", "light"}, {"origin", "0 0 80"}, {"delay", "3"}});
  b.box({100, -10, 2}, {140, 10, 4}, "white"); // a low shelf: the floor under it sees neither light
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  Rng rng = pixelRng(0, 0, 0, 0);
  // In the open: point light (300, angle (0.5 + 0.5 cos)) + sun from straight above (100).
  const float cosAtX60 = 80.0f / 100.0f;
  const float open = faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, downAt(60.0f, 0.0f), rng));
  EXPECT_NEAR(open, 300.0f * (0.5f + 0.5f * cosAtX60) + 100.0f, 1.0f);
  // Under the shelf: sun and point light are blocked, worldspawn minlight remains.
  const float shadowed = faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, Ray{{120, 0, 1}, 0, {0, 0, -1}, 1e9f}, rng));
  EXPECT_NEAR(shadowed, 20.0f, 0.5f);
}

TEST(FaithfulRender, SpotlightConeOnTheFloor) {
  test::BoxSceneBuilder b = floorScene();
  b.entity({{"classname", "light"}, {"origin", "0 0 100"}, {"mangle", "0 -90 0"}, {"delay", "3"}, {"angle", "40"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  Rng rng = pixelRng(0, 0, 0, 0);
  EXPECT_NEAR(faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, downAt(0, 0), rng)), 300.0f, 1.0f);
  // 20 units off axis at 100 below is 11.3 degrees: inside the 20 degree half-angle.
  const float cos20 = 100.0f / std::sqrt(100.0f * 100.0f + 400.0f);
  EXPECT_NEAR(faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, downAt(20, 0), rng)), 300.0f * (0.5f + 0.5f * cos20), 1.0f);
  // 50 units off axis is 26.6 degrees: outside.
  EXPECT_NEAR(faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, downAt(50, 0), rng)), 0.0f, 0.01f);
}

TEST(FaithfulRender, SkyDomeMeanOverTheHemisphere) {
  test::BoxSceneBuilder b = floorScene();
  b.worldKey("_sunlight2", "100");
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  // Uniform directions over the upper hemisphere: E[0.5 + 0.5 cos] = 0.75.
  double sum = 0.0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    Rng rng = pixelRng(0, 0, uint32_t(i), 7);
    sum += faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x;
  }
  EXPECT_NEAR(sum / n, 75.0, 1.0); // standard error ~0.2
}

// Dirt under a slab: the floor point's occlusion rays leave 1 unit above it (the compiler's
// sample lift) and every one meets the slab's underside 16 units up, at 16 / cos(elevation)
// for the pattern's three elevations (1/6, 3/6, 5/6 of 88 degrees), all within _dirtdepth 128.
float slabOcclusion() {
  double mean = 0.0;
  for (int j = 0; j < 3; ++j) mean += 16.0 / std::cos((j + 0.5) * (88.0 / 3.0) * 3.14159265358979 / 180.0) / 3.0;
  return float(1.0 - mean / 128.0);
}

RenderScene dirtSlabScene(test::BoxSceneBuilder& b, std::vector<std::pair<std::string, std::string>> lightKeys) {
  b.worldKey("_dirt", "1");
  b.box({-512, -512, 17}, {512, 512, 33}, "white"); // underside at z = 17
  lightKeys.insert(lightKeys.end(), {{"classname", "light"}, {"origin", "0 0 9"}, {"delay", "3"}});
  b.entity(lightKeys);
  Diagnostics diags;
  return buildRenderScene(b.scene(), {}, diags);
}

TEST(FaithfulDirt, OcclusionUnderASlabIsTheConeMean) {
  test::BoxSceneBuilder b = floorScene();
  b.box({1600, -64, 0}, {1616, 64, 256}, "white"); // a wall facing -x at x = 1600
  const RenderScene rs = dirtSlabScene(b, {});
  ASSERT_TRUE(rs.world.dirtSettings.enabled);
  Rng rng = pixelRng(0, 0, 0, 0);
  const float occlusion = faithfulDirtOcclusion(rs, {0, 0, 0}, {0, 0, 1}, rng);
  EXPECT_NEAR(occlusion, slabOcclusion(), 1e-4f);
  EXPECT_NEAR(occlusion, 0.7537f, 0.001f); // by hand: 1 - (16.54 + 22.24 + 55.79) / 3 / 128
  // In the open, beyond the slab's reach: nothing within _dirtdepth.
  EXPECT_NEAR(faithfulDirtOcclusion(rs, {1000, 0, 0}, {0, 0, 1}, rng), 0.0f, 1e-6f);
  // 8 units from the wall: the rays of the half of the cone facing it meet it, the rest go free.
  const float nearWall = faithfulDirtOcclusion(rs, {1592, 0, 0}, {0, 0, 1}, rng);
  EXPECT_GT(nearWall, 0.2f);
  EXPECT_LT(nearWall, 0.5f);
}

TEST(FaithfulDirt, LightIsDimmedByOneMinusDirt) {
  // An infinite light (delay 3, 300) straight above: 300 without dirt.
  {
    test::BoxSceneBuilder b = floorScene();
    const RenderScene rs = dirtSlabScene(b, {});
    Rng rng = pixelRng(0, 0, 0, 0);
    EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 300.0f * (1.0f - slabOcclusion()),
                0.05f);
  }
  { // The light's own _dirt -1: no dirt.
    test::BoxSceneBuilder b = floorScene();
    const RenderScene rs = dirtSlabScene(b, {{"_dirt", "-1"}});
    Rng rng = pixelRng(0, 0, 0, 0);
    EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 300.0f, 0.05f);
  }
  { // _dirtscale 2 and _dirtgain 0.5: min(1, sqrt(occlusion) x 2) = 1: all dirt.
    test::BoxSceneBuilder b = floorScene();
    const RenderScene rs = dirtSlabScene(b, {{"_dirtscale", "2"}, {"_dirtgain", "0.5"}});
    Rng rng = pixelRng(0, 0, 0, 0);
    EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 0.0f, 0.05f);
  }
  { // The light is 9 units away: between _dirt_off_radius 5 and _dirt_on_radius 13, half the dirt.
    test::BoxSceneBuilder b = floorScene();
    const RenderScene rs = dirtSlabScene(b, {{"_dirt_off_radius", "5"}, {"_dirt_on_radius", "13"}});
    Rng rng = pixelRng(0, 0, 0, 0);
    EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x,
                300.0f * (1.0f - 0.5f * slabOcclusion()), 0.05f);
  }
  { // Nearer than _dirt_off_radius: no dirt.
    test::BoxSceneBuilder b = floorScene();
    const RenderScene rs = dirtSlabScene(b, {{"_dirt_off_radius", "10"}, {"_dirt_on_radius", "20"}});
    Rng rng = pixelRng(0, 0, 0, 0);
    EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 300.0f, 0.05f);
  }
}

TEST(FaithfulDirt, MinlightIsDimmedByDefaultUnderDirt) {
  test::BoxSceneBuilder b = floorScene();
  b.worldKey("light", "40");
  const RenderScene rs = dirtSlabScene(b, {{"light", "0"}});
  Rng rng = pixelRng(0, 0, 0, 0);
  EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 40.0f * (1.0f - slabOcclusion()), 0.01f);

  test::BoxSceneBuilder off = floorScene();
  off.worldKey("light", "40");
  off.worldKey("_minlight_dirt", "0");
  const RenderScene rsOff = dirtSlabScene(off, {{"light", "0"}});
  EXPECT_NEAR(faithfulLight(rsOff, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 40.0f, 0.01f);
}

TEST(FaithfulDirt, SunlightIsDimmedUnlessSunlightDirtIsOff) {
  // A sun straight down on a floor point 8 units from a wall: in the open above, dimmed by the
  // wall's occlusion (`_dirt 1` turns `_sunlight_dirt` on); `_sunlight_dirt -1` turns it off.
  for (const char* sunDirt : {"", "-1"}) {
    SCOPED_TRACE(std::string("_sunlight_dirt ") + sunDirt);
    test::BoxSceneBuilder b = floorScene();
    b.box({1600, -64, 0}, {1616, 64, 256}, "white");
    b.worldKey("_dirt", "1");
    b.worldKey("_sunlight", "100");
    if (*sunDirt) b.worldKey("_sunlight_dirt", sunDirt);
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(b.scene(), {}, diags);
    Rng rng = pixelRng(0, 0, 0, 0);
    const float occlusion = faithfulDirtOcclusion(rs, {1592, 0, 0}, {0, 0, 1}, rng);
    ASSERT_GT(occlusion, 0.2f);
    const float expected = *sunDirt ? 100.0f : 100.0f * (1.0f - occlusion);
    EXPECT_NEAR(faithfulLight(rs, {.p = {1592, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, expected, 0.05f);
  }
}

TEST(FaithfulDirt, MinlightDirtDimsARadiosityTemplatesFaceMinlight) {
  // The floor is a radiosity _surface template (light 100): its faces get 100 as minlight, and
  // its own point lights sit on its plane, so they add nothing to it. Under the slab, dirt takes
  // its share of that minlight unless _minlight_dirt is 0 (ericw-tools LightFace_Min).
  for (const char* minlightDirt : {"", "0"}) {
    SCOPED_TRACE(std::string("_minlight_dirt ") + minlightDirt);
    test::BoxSceneBuilder b;
    b.material("lamp", 255, 255, 255);
    b.material("white", 255, 255, 255);
    b.box({-2048, -2048, -16}, {2048, 2048, 0}, "lamp");
    b.entity({{"classname", "light"}, {"origin", "0 0 -1000"}, {"light", "100"}, {"_surface", "lamp"}, {"_surface_radiosity", "1"}});
    if (*minlightDirt) b.worldKey("_minlight_dirt", minlightDirt);
    const RenderScene rs = dirtSlabScene(b, {{"light", "0"}});
    Rng rng = pixelRng(0, 0, 0, 0);
    const float sum = faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, Ray{{0, 0, 10}, 0, {0, 0, -1}, 1e9f}, rng));
    EXPECT_NEAR(sum, *minlightDirt ? 100.0f : 100.0f * (1.0f - slabOcclusion()), 0.5f);
  }
}

TEST(FaithfulDirt, LevelsWithoutDirtTraceNoOcclusion) {
  test::BoxSceneBuilder b = floorScene();
  b.box({-512, -512, 17}, {512, 512, 33}, "white");
  b.entity({{"classname", "light"}, {"origin", "0 0 9"}, {"delay", "3"}});
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(b.scene(), {}, diags);
  EXPECT_FALSE(rs.world.dirtSettings.enabled);
  Rng rng = pixelRng(0, 0, 0, 0);
  EXPECT_EQ(faithfulDirtOcclusion(rs, {0, 0, 0}, {0, 0, 1}, rng), 0.0f);
  EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .lights = LightSet::All}, rng).x, 300.0f, 0.05f);
}

TEST(FaithfulRender, LiquidsAreFullbrightUnlessLitwater) {
  for (bool litwater : {false, true}) {
    test::BoxSceneBuilder b;
    b.material("*water", 100, 100, 100);
    b.box({-512, -512, -16}, {512, 512, 0}, "*water");
    if (litwater) b.worldKey("_litwater", "1");
    b.entity({{"classname", "light"}, {"origin", "0 0 50"}, {"light", "50"}, {"delay", "3"}});
    const Scene scene = b.build();
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    Rng rng = pixelRng(0, 0, 0, 0);
    const float display = linearToSrgb(radiance(rs, {LightingMode::Faithful, 0}, downAt(0, 0), rng).x);
    const float texel = 100.0f / 255.0f;
    EXPECT_NEAR(display, litwater ? texel * 50.0f * 0.5f / 128.0f : texel, 1e-3f);
  }
}

// Bit 0x8 of a face's surface flags is Quake 2's SURF_WARP (water, slime, lava: drawn unlit at the
// texture's colour without _litwater) but Quake 3's SURF_LADDER: a Quake 3 ladder is lit like any
// floor, where the same bit in a Quake 2 level makes the floor a liquid.
TEST(FaithfulRender, Bit8IsAQuake2LiquidButAQuake3Ladder) {
  auto floorSeen = [](const char* game, std::optional<SurfaceAttributes> surface) {
    test::BoxSceneBuilder b;
    b.material("floor", 100, 100, 100);
    b.box({-512, -512, -16}, {512, 512, 0}, "floor");
    b.entity({{"classname", "light"}, {"origin", "0 0 50"}, {"light", "50"}, {"delay", "3"}});
    Scene scene = b.build();
    scene.game = game;
    for (Face& face : scene.faces) face.surface = surface;
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    Rng rng = pixelRng(0, 0, 0, 0);
    return linearToSrgb(radiance(rs, {LightingMode::Faithful, 0}, downAt(0, 0), rng).x);
  };
  const SurfaceAttributes bit8{0, 0x8, 0.0};
  const float texel = 100.0f / 255.0f;
  const float quake3Floor = floorSeen("quake3", std::nullopt);
  // Lit by q3map2's rules (lighting/q3map2_light.h), so not the texel an unlit liquid shows.
  EXPECT_GT(std::abs(quake3Floor - texel), 0.05f);
  EXPECT_EQ(floorSeen("quake3", bit8), quake3Floor);
  EXPECT_NEAR(floorSeen("quake2", bit8), texel, 1e-3f);
  EXPECT_EQ(classifyTexture("textures/base/ladder", bit8, Game::Quake3), 0u);
  EXPECT_EQ(classifyTexture("e1u1/water", bit8, Game::Quake2), kFaceLiquid);
  EXPECT_EQ(classifyTexture("textures/liquids/water", SurfaceAttributes{0x20, 0, 0.0}, Game::Quake3), kFaceLiquid);
}

// ericw-tools lights a lit liquid from both sides (ltface.cc "twosided"): a light under the
// surface counts at |cos|, where any other face ignores a light behind it.
TEST(FaithfulRender, LitLiquidsTakeLightFromBelowToo) {
  for (const char* texture : {"*water", "floor"}) {
    test::BoxSceneBuilder b;
    b.material(texture, 100, 100, 100);
    b.box({-512, -512, -64}, {512, 512, 0}, texture);
    b.worldKey("_litwater", "1");
    b.entity({{"classname", "light"}, {"origin", "0 0 -32"}, {"light", "50"}, {"delay", "3"}});
    const Scene scene = b.build();
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    const bool liquid = texture[0] == '*';
    Rng rng = pixelRng(0, 0, 0, 0);
    // Straight below: |cos| = 1; 32 units aside: |cos| = 1/sqrt(2), half-Lambert.
    EXPECT_NEAR(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .twoSided = true, .lights = LightSet::All}, rng).x, 50.0f, 1e-3f);
    EXPECT_NEAR(faithfulLight(rs, {.p = {32, 0, 0}, .n = {0, 0, 1}, .twoSided = true, .lights = LightSet::All}, rng).x,
                50.0f * (0.5f + 0.5f / std::sqrt(2.0f)), 1e-3f);
    EXPECT_EQ(faithfulLight(rs, {.p = {0, 0, 0}, .n = {0, 0, 1}, .twoSided = false, .lights = LightSet::All}, rng).x, 0.0f);
    // The renderer lights liquid faces two-sided, and only those.
    const float display = linearToSrgb(radiance(rs, {LightingMode::Faithful, 0}, downAt(0, 0), rng).x);
    const float texel = 100.0f / 255.0f;
    EXPECT_NEAR(display, liquid ? texel * 50.0f * 0.5f / 128.0f : 0.0f, 1e-3f) << texture;
  }
}

// A Quake 2 liquid brush drawn as a wall (contents water, no SURF_WARP) has its faces on both
// sides in the compiled level, and ericw-tools' Embree hits them from either side: the light of a
// lamp beside the water does not reach the floor under it, whose shadow rays leave the water
// through its wall (q2_light_visapprox2). With SURF_WARP the water passes light both ways, as a
// Quake 1 `*water` does; the floor beside the water, on the lamp's side, is lit in every case.
TEST(FaithfulRender, AQuake2WaterDrawnAsAWallShadowsFromInside) {
  // Display of the floor seen straight down from (x, 0, 100), inside the water for x > 0.
  auto floorSeen = [](const char* game, const char* water, std::optional<SurfaceAttributes> surface, float x) {
    const Scene scene = test::waterBesideALight(game, water, surface);
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    Rng rng = pixelRng(0, 0, 0, 0);
    return linearToSrgb(radiance(rs, {LightingMode::Faithful, 0}, Ray{{x, 0.0f, 100.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 1e9f}, rng).x);
  };
  using namespace quake::q2;
  const SurfaceAttributes wall{CONTENTS_WATER, 0, 0.0}, warped{CONTENTS_WATER, SURF_WARP, 0.0};
  const float beside = floorSeen("quake2", "e1u1/water", wall, -32.0f);
  EXPECT_GT(beside, 0.1f);
  EXPECT_EQ(floorSeen("quake2", "e1u1/water", warped, -32.0f), beside);
  // Under the water, 64 units from its side: lit where the water passes light, black behind the wall.
  EXPECT_EQ(floorSeen("quake2", "e1u1/water", wall, 64.0f), 0.0f);
  EXPECT_GT(floorSeen("quake2", "e1u1/water", warped, 64.0f), 0.03f); // (0.063: farther, more grazing)
  EXPECT_GT(floorSeen("quake", "*water", std::nullopt, 64.0f), 0.03f);
}

// What physical mode's light shows in linear terms over the compiler's light fraction
// (lighting/README.md, "Physical mode", the display match: 0.65^1.2 rounded).
constexpr double kDisplayMatch = 0.6;

// Karis' windowed falloff, written out again here: (1 - (d / reach)^4)^2, clamped.
double karisWindow(double d, double reach) {
  const double x = d / reach;
  const double w = std::clamp(1.0 - x * x * x * x, 0.0, 1.0);
  return w * w;
}

// The fixed rule (physical::matchDistance): what a light listed by hand, or one whose light
// lands nowhere, is matched by. buildRenderScene matches a level's Quake lights where their light
// lands (the test after these two), so these prepare the level's light again by the fixed rule.
void prepareByTheFixedRule(RenderScene& rs) {
  for (GpuLight& l : rs.lights) physical::prepare(l, rs.world.scaledist);
}

TEST(PhysicalRender, PointLightInverseSquareWindowedAtItsReach) {
  test::BoxSceneBuilder b = floorScene();
  b.entity({{"classname", "light"}, {"origin", "0 0 80"}});
  const Scene scene = b.build();
  Diagnostics diags;
  RenderScene rs = buildRenderScene(scene, {}, diags);
  prepareByTheFixedRule(rs);
  Rng rng = pixelRng(0, 0, 0, 0);
  const glm::vec3 l = radiance(rs, {LightingMode::Physical, 0}, downAt(60.0f, 0.0f), rng);
  // `light 300`, linear: reach 300; it matches the compiler's 172 at 128 units, so
  // I = 172 * 128^2 / W(128); white Lambertian L = (1 / pi) * I * range * pi * 0.6 / 128 * W(d) * cos / d^2.
  const double intensity = 172.0 * 128.0 * 128.0 / karisWindow(128.0, 300.0);
  const double expected = intensity * 0.5 * kDisplayMatch / 128.0 * karisWindow(100.0, 300.0) * 0.8 / (100.0 * 100.0);
  EXPECT_NEAR(l.x, expected, 1e-3 * expected);
}

// Head-on at its match distance, a white floor's physical radiance is the compiler's light there
// x _range / 128 (the faithful lightmap over 128) x the display match: per formula, the distance and the light the
// compiler gives there written out from ltface.cc GetLightValue.
TEST(PhysicalRender, EachFormulaMatchesTheCompiledLightAtItsMatchDistance) {
  struct Case {
    const char* delay;
    const char* wait;
    const char* falloff;
    double distance, compiled;
  };
  const Case cases[] = {
      {"0", "1", "", 128.0, 172.0},                               // linear: 128 units, nearer than half its reach of 300
      {"0", "0.3", "", 128.0, 300.0 - 0.3 * 128.0},               // a long reach (1000) is matched at 128 too
      {"0", "4", "", 37.5, 150.0},                                // wait 4: half its reach of 75 is nearer
      {"0", "1", "200", 100.0, 150.0},                            // _falloff 200: 300 * (1 - 100 / 200), at half of it
      {"1", "1", "", 128.0, 300.0},                               // inverse: 300 * 128 / d
      {"2", "2", "", 64.0, 300.0},                                // inverse square, wait 2: 300 * (128 / (2 d))^2
      {"5", "1", "", 128.0, 300.0 * 128 * 128 / (256.0 * 256.0)}, // inverse square without the pole
      {"3", "1", "", 128.0, 300.0},                               // no falloff: never ends (no window)
  };
  for (const Case& c : cases) {
    test::BoxSceneBuilder b = floorScene();
    std::vector<std::pair<std::string, std::string>> keys = {
        {"classname", "light"}, {"origin", fmt::format("0 0 {}", c.distance)}, {"delay", c.delay}, {"wait", c.wait}};
    if (*c.falloff) keys.emplace_back("_falloff", c.falloff);
    b.entity(keys);
    const Scene scene = b.build();
    Diagnostics diags;
    RenderScene rs = buildRenderScene(scene, {}, diags);
    prepareByTheFixedRule(rs);
    Rng rng = pixelRng(0, 0, 0, 0);
    const glm::vec3 l = radiance(rs, {LightingMode::Physical, 0}, downAt(0.0f, 0.0f), rng);
    // The shadow ray leaves 0.03 units above the floor: the light is that much nearer (its window
    // opens by as little again, below 5e-4).
    const double nearer = c.distance / (c.distance - 0.03);
    const double expected = c.compiled * 0.5 * kDisplayMatch / 128.0 * nearer * nearer;
    EXPECT_NEAR(l.x, expected, 5e-4 * expected) << "delay " << c.delay << " wait " << c.wait << " _falloff " << c.falloff;
  }
}

// A level's Quake light is matched over the surfaces its light lands on (lighting/README.md,
// "Physical mode"; lighting/physical_reference.h), written out again here for `light 300` 80
// units over the floor: of the 256 directions of a Fibonacci sphere, the 16 in the wedge
// 0 <= y < x, z > 0, each mirrored and swapped into 16, 8 of them down; those that reach the floor
// within the light's reach of 300 land at d = 80 / cos; each counts the compiler's (300 - d) x
// (0.5 + 0.5 cos) x d^2 / cos (d at least 16, cos at least 0.2) against physical light's W(d),
// and the intensity is the ratio of the sums: 1.50 times the fixed rule's here.
TEST(PhysicalRender, AQuakeLightIsMatchedOverTheSurfacesItsLightLandsOn) {
  test::BoxSceneBuilder b = floorScene();
  b.entity({{"classname", "light"}, {"origin", "0 0 80"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  double compiled = 0.0, windowed = 0.0;
  constexpr int kSpiral = 256;
  int wedge = 0;
  for (int i = 0; i < kSpiral; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / kSpiral, r = std::sqrt(1.0 - z * z), phi = 2.39996322972865332 * i;
    const double x = r * std::cos(phi), y = r * std::sin(phi);
    if (!(z > 0.0 && y >= 0.0 && y < x)) continue;
    ++wedge;
    if (!(80.0 / z < 300.0)) continue;
    const double d = std::max(80.0 / z, 16.0), cosine = std::max(z, 0.2);
    compiled += 8.0 * (300.0 - d) * (0.5 + 0.5 * cosine) / cosine * d * d;
    windowed += 8.0 * karisWindow(d, 300.0);
  }
  ASSERT_EQ(wedge, 16);
  const double intensity = compiled / windowed;
  Rng rng = pixelRng(0, 0, 0, 0);
  const glm::vec3 l = radiance(rs, {LightingMode::Physical, 0}, downAt(60.0f, 0.0f), rng);
  const double expected = intensity * 0.5 * kDisplayMatch / 128.0 * karisWindow(100.0, 300.0) * 0.8 / (100.0 * 100.0);
  EXPECT_NEAR(l.x, expected, 1e-3 * expected);
}

// A light inside water is matched as the same light in the open (lighting/physical_reference.h):
// the compiler lights what lies beyond a liquid, so the rays that find where its light lands go
// on through the liquid's faces, also when they leave it from within (q1_litwater's green light
// sits in a water box; its rays were all dropped at the box's faces and the light kept the fixed
// 128-unit rule, 0.58 of the level's faithful brightness). Shadow rays cross water untinted, so
// the floor beside the box shows the same light either way.
TEST(PhysicalRender, ALightInsideWaterIsMatchedOverWhatItLightsBeyondTheWater) {
  auto floorBeside = [](bool water) {
    test::BoxSceneBuilder b = floorScene();
    if (water) {
      b.material("*water", 100, 100, 100);
      b.box({-24, -24, 56}, {24, 24, 104}, "*water");
    }
    b.entity({{"classname", "light"}, {"origin", "0 0 80"}});
    const Scene scene = b.build();
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    Rng rng = pixelRng(0, 0, 0, 0);
    return radiance(rs, {LightingMode::Physical, 0}, downAt(60.0f, 0.0f), rng).x;
  };
  const float open = floorBeside(false);
  ASSERT_GT(open, 0.0f);
  EXPECT_NEAR(floorBeside(true), open, 1e-3f * open);
}

// Worldspawn minlight in physical mode (lighting/README.md, "Physical mode"): the same floor on
// every face, so the camera sees it as the game's display shows it, whatever the bounces (the
// compiler's bounce leaves minlight out too): a brown floor in a level with no light but `light
// 100` and an orange `_minlight_color` shows, channel by channel, what faithful mode draws there
// (srgbToLinear(texture x 50 / 128) in the texture's gamma space, 0.15 of a mid grey's linear
// colour), not the display match's linear k x 0.39 (0.23).
TEST(PhysicalRender, MinlightShowsTheFloorTheGameShows) {
  test::BoxSceneBuilder b;
  b.material("brown", 200, 140, 80);
  b.box({-2048, -2048, -16}, {2048, 2048, 0}, "brown");
  b.worldKey("light", "100");
  b.worldKey("_minlight_color", "255 160 64");
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  Rng faithfulRng = pixelRng(0, 0, 0, 0);
  const glm::vec3 game = radiance(rs, {LightingMode::Faithful, 0}, downAt(0.0f, 0.0f), faithfulRng);
  ASSERT_GT(game.z, 0.0f);
  for (int bounces : {0, 3}) {
    Rng rng = pixelRng(0, 0, 0, 0);
    const glm::vec3 l = radiance(rs, {LightingMode::Physical, bounces}, downAt(0.0f, 0.0f), rng);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(l[c], game[c], 1e-4f * game[c]) << bounces << " bounces, channel " << c;
  }
}

// A coloured light in physical mode shows the hue the game shows (lighting/physical_light.h
// colour): a white room lit by `_color 255 127 0`, seen from a camera in both modes, compared
// pixel by pixel in colour. The game multiplies the texture by the lightmap in gamma space, so its
// green is sRGB-to-linear of half the red's display value, about 0.21 to 0.25 of the red in
// linear light where the wall is well lit; a light whose colour were used as linear would give 0.5.
// Every pixel whose faithful red displays between 0.5 and 0.95 (well lit, below the clamp)
// holds physical mode's green-to-red ratio within 8 % of faithful mode's.
TEST(PhysicalRender, AColouredLightKeepsTheHueTheGameShows) {
  test::BoxSceneBuilder b;
  b.material("white", 255, 255, 255);
  b.room({-256, -256, 0}, {256, 256, 256}, "white");
  b.entity({{"classname", "light"}, {"origin", "0 0 128"}, {"light", "600"}, {"_color", "255 127 0"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const Camera camera(CameraPose{{-200.0f, 0.0f, 100.0f}, 10.0f, 0.0f}, 64, 36);
  RenderSettings settings;
  settings.width = 64;
  settings.height = 36;
  settings.spp = 4;
  settings.threads = 2;
  settings.integrator.bounces = 0; // the light itself: the game's hue is that of its direct light
  settings.integrator.mode = LightingMode::Faithful;
  const RenderImage faithful = renderCpu(rs, camera, settings);
  settings.integrator.mode = LightingMode::Physical;
  const RenderImage physical = renderCpu(rs, camera, settings);
  int compared = 0, held = 0;
  double worst = 0.0;
  for (size_t i = 0; i < faithful.beauty.size(); ++i) {
    const float shown = linearToSrgb(faithful.beauty[i].x);
    if (!(shown >= 0.5f && shown <= 0.95f) || !(physical.beauty[i].x > 0.0f)) continue;
    const double game = faithful.beauty[i].y / faithful.beauty[i].x, ours = physical.beauty[i].y / physical.beauty[i].x;
    const double error = std::abs(ours / game - 1.0);
    worst = std::max(worst, error);
    ++compared;
    held += error <= 0.08;
  }
  EXPECT_GE(compared, 300) << "the camera should see most of the lit walls";
  EXPECT_EQ(held, compared) << "worst green-to-red ratio off by " << worst * 100.0 << " %";
}

// A sun with `_suntexture` shines only through sky faces of that texture, in physical mode as in
// the compiler (lighting/README.md, light keys): in test::twoSkiesRoom the floor under `sky_b`
// shows the sun's light (value x _range x the display match / 128 on white), the floor under
// `sky_a` nothing (no bounce; the sky itself lights nothing without a dome).
TEST(PhysicalRender, ASunWithASkyTextureShinesOnlyThroughThatSky) {
  const Scene scene = test::twoSkiesRoom();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  Rng rng = pixelRng(0, 0, 0, 0);
  const glm::vec3 underB = radiance(rs, {LightingMode::Physical, 0}, downAt(128.0f, 0.0f), rng);
  const glm::vec3 underA = radiance(rs, {LightingMode::Physical, 0}, downAt(-128.0f, 0.0f), rng);
  const double expected = 300.0 * 0.5 * kDisplayMatch / 128.0;
  EXPECT_NEAR(underB.x, expected, 1e-4 * expected) << "the sun through its own sky";
  EXPECT_EQ(underA, glm::vec3(0.0f)) << "the sun through another sky";
}

// `delay 3` never falls off in the compiler: its physical light has no reach, so far beyond its
// match distance (128) it is the plain inverse square of its matched intensity, unwindowed.
TEST(PhysicalRender, ALightThatNeverFallsOffHasNoWindow) {
  test::BoxSceneBuilder b = floorScene();
  b.entity({{"classname", "light"}, {"origin", "0 0 2000"}, {"delay", "3"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  Rng rng = pixelRng(0, 0, 0, 0);
  const glm::vec3 l = radiance(rs, {LightingMode::Physical, 0}, downAt(0.0f, 0.0f), rng);
  const double d = 2000.0 - 0.03; // the shadow ray leaves 0.03 units above the floor
  const double expected = 300.0 * 128.0 * 128.0 / (d * d) * 0.5 * kDisplayMatch / 128.0;
  EXPECT_NEAR(l.x, expected, 5e-4 * expected);
}

// A mapper's short light (high `wait`) ends in physical mode where the compiled one does: the end
// wall of a corridor 1.5 reaches away, facing the light, gets at most 5 % of the light of the floor
// under it, with four bounces (an unwindowed inverse square gives it (24 / 90)^2 = 7 % directly).
TEST(PhysicalRender, AShortLightEndsWhereTheCompiledOneDoes) {
  test::BoxSceneBuilder b;
  b.material("white", 200, 200, 200);
  b.box({-64, -64, -16}, {90, 64, 0}, "white");   // floor
  b.box({-64, -64, 128}, {90, 64, 144}, "white"); // ceiling
  b.box({-64, -80, 0}, {90, -64, 128}, "white");  // side walls
  b.box({-64, 64, 0}, {90, 80, 128}, "white");
  b.box({-80, -64, 0}, {-64, 64, 128}, "white");                                             // the near end
  b.box({90, -80, -16}, {106, 80, 144}, "white");                                            // the far end
  b.entity({{"classname", "light"}, {"origin", "0 0 24"}, {"light", "300"}, {"wait", "5"}}); // reach 60
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const auto mean = [&](const Ray& ray) {
    glm::dvec3 sum(0.0);
    constexpr int kSamples = 4096;
    for (int i = 0; i < kSamples; ++i) {
      Rng rng = pixelRng(uint32_t(i), 0, 0, 7);
      sum += glm::dvec3(radiance(rs, {LightingMode::Physical, 4}, ray, rng));
    }
    return sum / double(kSamples);
  };
  const glm::dvec3 nearFloor = mean(downAt(0.0f, 0.0f)), farWall = mean(Ray{{40.0f, 0.0f, 24.0f}, 0.0f, {1.0f, 0.0f, 0.0f}, 1e9f});
  for (int c = 0; c < 3; ++c)
    EXPECT_LE(farWall[c], 0.05 * nearFloor[c]) << "channel " << c << ": " << farWall[c] << " against " << nearFloor[c];
  EXPECT_GT(nearFloor.x, 0.0);
}

// Form factor from a point to a parallel rectangle [0, a] x [0, b] at height c, the point
// below a corner (Howell's catalogue, C-11).
double cornerFormFactor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2.0 * 3.14159265358979);
}

TEST(PhysicalRender, AreaLightMatchesFormFactorWithinMonteCarloError) {
  test::BoxSceneBuilder b = floorScene();
  b.material("black", 0, 0, 0);
  b.material("lamp", 0, 0, 0); // emits, reflects nothing
  const uint32_t firstLampFace = uint32_t(b.scene().faces.size());
  b.box({-32, -32, 100}, {32, 32, 104}, "lamp");
  // Only the downward face emits: the sides and top get the black, non-emitting material.
  const uint32_t black = *b.scene().findMaterial("black");
  for (uint32_t f = firstLampFace; f < firstLampFace + 6; ++f)
    if (b.scene().faces[f].plane.normal.z > -0.5) {
      b.scene().faces[f].material = black;
      b.scene().faces[f].texture = "black";
    }
  b.entity({{"classname", "light"}, {"origin", "0 0 -500"}, {"_surface", "lamp"}, {"light", "200"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  ASSERT_EQ(rs.emitters.size(), 2u);

  const double le = 200.0 * 0.5 * 3.14159265358979 * kDisplayMatch / 128.0;
  // Under the lamp's centre, and under the middle of its edge x = 32, where its two triangles
  // (either diagonal) light the floor unequally: each must be picked in proportion to its area.
  struct Point {
    float x;
    double formFactor;
  };
  for (const Point& p : {Point{0.0f, 4.0 * cornerFormFactor(32, 32, 100)}, Point{32.0f, 2.0 * cornerFormFactor(64, 32, 100)}}) {
    const double expected = le * p.formFactor; // white floor: L = albedo * Le * F
    const int n = 20000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < n; ++i) {
      Rng rng = pixelRng(3, 4, uint32_t(i), 11);
      const double v = radiance(rs, {LightingMode::Physical, 2}, downAt(p.x, 0), rng).x;
      sum += v;
      sum2 += v * v;
    }
    const double mean = sum / n;
    const double stderr_ = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, expected, std::max(4.0 * stderr_, 1e-4 * expected)) << "x " << p.x << ", standard error " << stderr_;
    EXPECT_LT(stderr_, 0.02 * expected) << "x " << p.x; // and the estimate is actually tight
  }
}

// The emitter pick searches only between two entries of RenderScene::emitterGuide: for every u
// (the Sobol draws' 24-bit floats, the guide's bucket edges and the cdfs themselves among them),
// the emitter whose cdf interval holds u, the first whose cdf reaches u (the last where none
// does), lies between the entries for floor(u K) and the next.
TEST(PhysicalRender, EmitterGuideBracketsEveryPick) {
  std::mt19937 random(7);
  for (const size_t count : {size_t(1), size_t(2), size_t(3), size_t(37), size_t(1000)}) {
    std::vector<GpuEmitter> emitters(count);
    float total = 0.0f;
    for (size_t i = 0; i < count; ++i) {
      // Some zero and some tiny areas: equal cdfs, several in one bucket, buckets with none.
      const uint32_t kind = random() % 4;
      total += kind == 0 ? 0.0f : kind == 1 ? 1e-4f : float(random() % 1000 + 1);
      emitters[i].cdf = total;
    }
    for (GpuEmitter& e : emitters) e.cdf = total > 0.0f ? e.cdf / total : 1.0f;
    emitters.back().cdf = 1.0f;
    const std::vector<uint32_t> guide = makeEmitterGuide(emitters);
    const size_t buckets = guide.size() - 1;
    ASSERT_GE(buckets, count < 65536 ? count : 65536) << count;
    std::vector<float> us;
    for (int i = 0; i < 20000; ++i) us.push_back(float(random() >> 8) * (1.0f / 16777216.0f));
    for (size_t k = 0; k < buckets; ++k) us.push_back(float(k) / float(buckets));
    for (const GpuEmitter& e : emitters)
      if (e.cdf < 1.0f) us.push_back(e.cdf), us.push_back(std::nextafter(e.cdf, 1.0f));
    for (const float u : us) {
      size_t first = 0;
      while (first + 1 < count && emitters[first].cdf < u) ++first;
      const size_t k = std::min(size_t(u * float(buckets)), buckets - 1);
      EXPECT_LE(guide[k], first) << count << " emitters, u " << u;
      EXPECT_GE(guide[k + 1], first) << count << " emitters, u " << u;
    }
  }
}

TEST(PhysicalRender, FurnaceConvergesToEmissionOverOneMinusAlbedo) {
  test::BoxSceneBuilder b;
  b.material("grey", 188, 188, 188);
  b.room({-64, -64, -64}, {64, 64, 64}, "grey");
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"_surface", "grey"}, {"light", "100"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const double albedo = srgbToLinear(188.0f / 255.0f);
  const double le = 100.0 * 0.5 * 3.14159265358979 * kDisplayMatch / 128.0;
  const double expected = le / (1.0 - albedo);
  const int n = 6000;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    Rng rng = pixelRng(1, 2, uint32_t(i), 5);
    const glm::vec3 dir = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    const double v = radiance(rs, {LightingMode::Physical, 64}, Ray{{0, 0, 0}, 0, dir, 1e9f}, rng).y;
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  const double stderr_ = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, expected, 4.0 * stderr_) << "standard error " << stderr_;
  EXPECT_LT(stderr_, 0.02 * expected);
}

TEST(Tracing, HiddenFacesAreSkippedAndBlockNothing) {
  test::BoxSceneBuilder b = floorScene();
  b.material("clip", 255, 0, 0);
  b.box({-100, -100, 20}, {100, 100, 30}, "clip");
  b.entity({{"classname", "light"}, {"origin", "0 0 80"}, {"delay", "3"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const SurfaceHit hit = traceVisible(rs, downAt(0, 0));
  ASSERT_TRUE(hit.found);
  EXPECT_FLOAT_EQ(hit.position.z, 0.0f);
  Rng rng = pixelRng(0, 0, 0, 0);
  EXPECT_NEAR(faithfulSumFromRadiance(radiance(rs, {LightingMode::Faithful, 0}, downAt(0, 0), rng)), 300.0f, 1.0f);

  RenderSceneOptions show;
  show.showHidden = true;
  const RenderScene shown = buildRenderScene(scene, show, diags);
  EXPECT_FLOAT_EQ(traceVisible(shown, downAt(0, 0)).position.z, 30.0f);
}

TEST(Tracing, TextureNamesClassify) {
  EXPECT_EQ(classifyTexture("CLIP", std::nullopt, Game::Quake), kFaceHidden);
  EXPECT_EQ(classifyTexture("trigger", std::nullopt, Game::Quake), kFaceHidden);
  EXPECT_EQ(classifyTexture("e1u1/skip", std::nullopt, Game::Quake), kFaceHidden);
  EXPECT_EQ(classifyTexture("common/caulk", std::nullopt, Game::Quake), kFaceHidden);
  EXPECT_EQ(classifyTexture("sky4", std::nullopt, Game::Quake), kFaceSky);
  EXPECT_EQ(classifyTexture("*lava1", std::nullopt, Game::Quake), kFaceLiquid);
  EXPECT_EQ(classifyTexture("!water", std::nullopt, Game::Quake), kFaceLiquid);
  EXPECT_EQ(classifyTexture("wbrick1_5", std::nullopt, Game::Quake), 0u);
  EXPECT_EQ(classifyTexture("e1u1/floor", SurfaceAttributes{32, 0, 0.0}, Game::Quake2), kFaceLiquid); // Q2 water contents
  EXPECT_EQ(classifyTexture("e1u1/sky1", SurfaceAttributes{0, 4, 0.0}, Game::Quake2), kFaceSky);
}

} // namespace
} // namespace bt
