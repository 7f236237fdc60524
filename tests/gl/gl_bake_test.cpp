// Faithful mode's light compiler on the GPU (renderer/gl/gl_bake.h) against the CPU's
// (lighting/lightmap_bake.h): the same sample points, passes and random streams, so the
// same stored luxels up to float rounding.
#include "importers/import.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_bake.h"
#include "renderer/gl/gl_lighting.h"
#include "tests/gl/test_scenes.h"
#include "tests/render/box_scene.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace {

using namespace bt;
using namespace bt::gl;

// A floor and four walls 16 units thick around a square of half-width `half`, `height` tall,
// under a sky brush (materials "wall" and "sky1").
void skyWell(test::BoxSceneBuilder& b, double half, double height) {
  b.material("wall", 150, 140, 120);
  b.material("sky1", 40, 60, 200);
  b.box({-half, -half, -16}, {half, half, 0}, "wall");
  b.box({-half - 16, -half, 0}, {-half, half, height}, "wall");
  b.box({half, -half, 0}, {half + 16, half, height}, "wall");
  b.box({-half, -half - 16, 0}, {half, -half, height}, "wall");
  b.box({-half, half, 0}, {half, half + 16, height}, "wall");
  b.box({-half - 16, -half - 16, height}, {half + 16, half + 16, height + 16}, "sky1");
}

// A courtyard open to a sky brush, a pillar in it: every kind of light the bake passes treat
// differently (a plain point light, a `_deviance` light, a sun with a penumbra, the sky dome),
// with dirt, so every branch of bake.comp runs.
Scene courtyard() {
  test::BoxSceneBuilder b;
  skyWell(b, 128, 192);
  b.box({-16, -16, 0}, {16, 16, 96}, "wall");
  b.worldKey("_sunlight", "150");
  b.worldKey("_sun_mangle", "30 -60 0");
  b.worldKey("_sunlight_penumbra", "4");
  b.worldKey("_sunlight2", "60");
  b.worldKey("_dirt", "1");
  b.entity({{"classname", "light"}, {"origin", "-64 -64 48"}, {"light", "250"}});
  b.entity(
      {{"classname", "light"}, {"origin", "64 48 64"}, {"light", "200"}, {"_deviance", "12"}, {"_samples", "4"}, {"_color", "1 0.6 0.3"}});
  return b.build();
}

// The luxels of the packed buffer (scene/gpu_structs.h layout: its word 2 is where they start).
std::vector<uint32_t> packedLuxels(const std::vector<uint32_t>& packed, size_t count) {
  return {packed.begin() + packed[2], packed.begin() + packed[2] + std::ptrdiff_t(count)};
}

int largestChannelDifference(uint32_t a, uint32_t b) {
  int largest = 0;
  for (int shift = 0; shift < 24; shift += 8) largest = std::max(largest, std::abs(int((a >> shift) & 255u) - int((b >> shift) & 255u)));
  return largest;
}

// The GPU's luxels against the CPU's: how many lie within one level of them in every channel, and
// how many of the CPU's are lit (a dark bake proves nothing).
struct LuxelAgreement {
  size_t within = 0, lit = 0;
};
LuxelAgreement agreement(const std::vector<uint32_t>& gpu, const std::vector<uint32_t>& cpu) {
  LuxelAgreement a;
  for (size_t i = 0; i < gpu.size(); ++i) {
    a.within += largestChannelDifference(gpu[i], cpu[i]) <= 1;
    a.lit += (cpu[i] & 0xffffffu) != 0u;
  }
  return a;
}

// Bakes `cpu`'s luxels on the CPU (left in `cpu`) and the same job on the GPU into an empty
// atlas, with default options; returns the GPU's luxels.
std::vector<uint32_t> bakeOnBoth(const Scene& scene, RenderScene& rs, Lightmaps& cpu) {
  const LuxelBakeJob job = luxelBakeJob(rs, cpu, {});
  bakeLightmaps(rs, cpu, {});
  rs.lightmaps = cpu;
  std::fill(rs.lightmaps.luxels.begin(), rs.lightmaps.luxels.end(), 0u); // the GPU must fill them
  GlTracer tracer(test::sharedGlContext(), scene, rs.tracer, TextureMode::Arrays, lightingFor(rs));
  GlLightmapBake bake(tracer, job);
  bake.finish();
  return packedLuxels(tracer.readLightmaps(), cpu.luxels.size());
}

TEST(GlBake, GpuBakeStoresTheCpuLuxels) {
  const Scene scene = courtyard();
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  LightmapBakeOptions options;
  options.samples = 8; // soft lights' samples: fewer than the compiler's 64, for llvmpipe's sake
  Lightmaps cpu = layoutLightmaps(rs);
  ASSERT_GT(cpu.luxels.size(), 1000u);
  const LuxelBakeJob job = luxelBakeJob(rs, cpu, options);
  ASSERT_EQ(job.passes, 65) << "the sky dome's directions, one a pass";
  bakeLightmaps(rs, cpu, options);

  GlContext& context = test::sharedGlContext();
  rs.lightmaps = cpu;
  std::fill(rs.lightmaps.luxels.begin(), rs.lightmaps.luxels.end(), 0u); // the GPU must fill them
  GlTracer tracer(context, scene, rs.tracer, TextureMode::Arrays, lightingFor(rs));
  GlLightmapBake bake(tracer, job);
  bake.run(1);
  EXPECT_EQ(bake.passesDone(), 1);
  EXPECT_FALSE(bake.done());
  bake.finish();
  EXPECT_TRUE(bake.done());
  const std::vector<uint32_t> gpu = packedLuxels(tracer.readLightmaps(), cpu.luxels.size());

  // Float rounding (a shader may fuse multiply-adds; its sin and cos are not libm's) moves a
  // luxel across a byte's edge, and a soft light's sample ray that grazes an edge across the
  // shadow's: one sun sample of 8 is 19 levels here. Within 1 nearly everywhere (llvmpipe: 99.8 %,
  // an H200: 96.9 %, 3 % of luxels a sample apart at the pillar's edges); a bake drawing other
  // random numbers (its seed + 1) has 23 % of its luxels off by more and a mean 1.4 levels away.
  size_t within = 0, lit = 0;
  double sum = 0.0;
  for (size_t i = 0; i < gpu.size(); ++i) {
    const int d = largestChannelDifference(gpu[i], cpu.luxels[i]);
    within += d <= 1;
    sum += d;
    lit += (cpu.luxels[i] & 0xffffffu) != 0;
  }
  EXPECT_GE(double(within), 0.95 * double(gpu.size()));
  EXPECT_LE(sum / double(gpu.size()), 1.0) << "mean difference, in levels of the brightest channel";
  EXPECT_GT(double(lit), 0.7 * double(gpu.size())) << "a dark bake proves nothing (the walls' outer faces are dark)";
}

// Quake 3's q3map2 lights (lighting/q3map2_light.h: the Q3Point and Q3Linear formulas, q3map2's
// spotlight cone) bake to the same luxels on the GPU: maps/q3map2/point_lights.map, one light of
// each kind over a floor, no soft light, so every luxel within float rounding of the CPU's.
TEST(GlBake, GpuBakeStoresTheCpuLuxelsOfQ3map2Lights) {
  const Scene scene = importScene((test::mapsDir() / "q3map2" / "point_lights.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  Lightmaps cpu = layoutLightmaps(rs);
  ASSERT_GT(cpu.luxels.size(), 1000u);
  const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
  const auto [within, lit] = agreement(gpu, cpu.luxels);
  EXPECT_GE(double(within), 0.999 * double(gpu.size()));
  EXPECT_GT(double(lit), 0.4 * double(gpu.size())) << "a dark bake proves nothing (the floor's sides and bottom are dark)";
}

// q3map2's light from Quake 3 shaders (lighting/q3map2_shader_light.h): surface lights (the
// Q3Area formula and their backsplash points), a sky shader's q3map_sun with worldspawn
// _ambient, a q3map_skylight dome (maps/q3map2/shader_light/maps). No soft light: every luxel
// within float rounding of the CPU's.
TEST(GlBake, GpuBakeStoresTheCpuLuxelsOfQ3map2ShaderLight) {
  for (const char* map : {"surface_light.map", "sun.map", "skylight.map"}) {
    SCOPED_TRACE(map);
    const Scene scene = importScene((test::mapsDir() / "q3map2" / "shader_light" / "maps" / map).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    Lightmaps cpu = layoutLightmaps(rs);
    ASSERT_GT(cpu.luxels.size(), 500u);
    const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
    const auto [within, lit] = agreement(gpu, cpu.luxels);
    EXPECT_GE(double(within), 0.999 * double(gpu.size()));
    EXPECT_GT(double(lit), 0.2 * double(gpu.size())) << "a dark bake proves nothing";
  }
}

// ericw-tools' suntest: a green light on lighting channel 2 (`_light_channel_mask 2`), which
// lights only the func_wall on channels 1 and 2 (`_object_channel_mask 3`) and shines through the
// world (channel 1), the func_wall casting the shadows of both channels. The GPU bake reads the
// masks as the CPU's does: without them the green light lights the floor and walls around.
TEST(GlBake, LightingChannelsGiveTheCpuLuxels) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/deprecated/suntest.map").string(), ImportOptions{});
  RenderSceneOptions sceneOptions;
  sceneOptions.lights.styleZeroOnly = true;
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, sceneOptions, diagnostics);
  ASSERT_FALSE(rs.faceChannels.empty()) << "suntest's func_wall is on channels 1 and 2";
  // The faces within 320 units of the green light (56 568 -264): the func_wall, the floor and
  // walls around it, which the light reaches only through the world.
  std::vector<uint32_t> near;
  for (uint32_t f = 0; f < scene.faces.size(); ++f)
    for (const dvec3& v : scene.faces[f].winding)
      if (glm::distance(glm::vec3(v), glm::vec3(56.0f, 568.0f, -264.0f)) < 320.0f) {
        near.push_back(f);
        break;
      }
  Lightmaps cpu = layoutLightmaps(rs, near);
  ASSERT_GT(cpu.luxels.size(), 500u);
  const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
  size_t within = 0, far = 0, green = 0;
  for (size_t i = 0; i < gpu.size(); ++i) {
    const int d = largestChannelDifference(gpu[i], cpu.luxels[i]);
    within += d <= 1;
    far += d > 8;
    green += int((cpu.luxels[i] >> 8) & 255u) > int(cpu.luxels[i] & 255u) + 16;
  }
  EXPECT_GT(green, 20u) << "the green light lights the func_wall";
  EXPECT_GE(double(within), 0.98 * double(gpu.size()));
  EXPECT_LE(double(far), 0.002 * double(gpu.size())) << far << " of " << gpu.size() << " luxels more than 8 levels apart";
}

// ericw-tools' q2_light_negative: a light -1000 in a room with minlight 0.5 (64 stored). The
// compiler takes negative lights off after the floors, so where the light reaches the luxels go
// to 0, below the minlight; the GPU bake keeps their sum apart as the CPU's does (without it the
// floor would hold them at 64).
TEST(GlBake, NegativeLightsComeOffAfterTheFloorsAsOnTheCpu) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/q2_light_negative.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  Lightmaps cpu = layoutLightmaps(rs);
  ASSERT_GT(cpu.luxels.size(), 500u);
  const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
  size_t within = 0, black = 0, minlight = 0;
  for (size_t i = 0; i < gpu.size(); ++i) {
    within += largestChannelDifference(gpu[i], cpu.luxels[i]) <= 1;
    black += (gpu[i] & 0xffffffu) == 0u;
    minlight += (gpu[i] & 255u) == 64u;
  }
  EXPECT_GE(double(within), 0.999 * double(gpu.size()));
  EXPECT_GT(black, gpu.size() / 10) << "the negative light takes the minlight away where it reaches";
  EXPECT_GT(minlight, 20u) << "and only there";
}

// ericw-tools' q2_light_visapprox levels, compiled without vis data: the compiler culls a light
// from the faces that lie apart from its rays' box (lighting/vis_approx.h), which stay black. The
// GPU bake computes the lights' boxes itself, as a level prepared for the GL tracer leaves them
// (VisBoxes::Gpu; the CPU bake computes its own), and compares them with the compiled faces' as
// the CPU does: without them it lights those faces where the CPU leaves them black.
TEST(GlBake, VisapproxCullsTheLightsTheCpuCulls) {
  BT_REQUIRE_SHARED(shared);
  for (const char* map : {"q2_light_visapprox.map", "q2_light_visapprox2.map"}) {
    const Scene scene = importScene((shared / "maps/ericw-tools/testmaps" / map).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderSceneOptions options;
    options.visApproxBoxes = RenderSceneOptions::VisBoxes::Gpu;
    RenderScene rs = buildRenderScene(scene, options, diagnostics);
    ASSERT_FALSE(rs.visBoxLights.empty()) << map;
    ASSERT_TRUE(rs.visBoxes.empty()) << map << ": left to the GPU";
    Lightmaps cpu = layoutLightmaps(rs);
    ASSERT_GT(cpu.luxels.size(), 500u) << map;
    const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
    const auto [within, lit] = agreement(gpu, cpu.luxels);
    const size_t black = gpu.size() - lit;
    EXPECT_GE(double(within), 0.999 * double(gpu.size())) << map;
    EXPECT_GT(lit, gpu.size() / 50) << map; // q2_light_visapprox: 472 of 12,100, the light's own water
    EXPECT_GT(black, gpu.size() / 20) << map << ": the faces the compiler culls the light from";
  }
}

// A shaft open to a sky brush, lit by a strong sky dome alone: its walls take the dome's suns
// that lie along them (the zenith and the ring suns square to them) at (1 - anglescale), as
// ericw-tools' LightFace_Sky does (lighting/faithful.h sunAngleTerm), about 3 levels of a wall's
// 60 here. The GPU bake must take them too.
TEST(GlBake, DomeSunsAlongAWallLightItAsOnTheCpu) {
  test::BoxSceneBuilder b;
  skyWell(b, 64, 256);
  b.worldKey("_sunlight2", "300");
  const Scene scene = b.build();
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  Lightmaps cpu = layoutLightmaps(rs);
  ASSERT_GT(cpu.luxels.size(), 300u);
  const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
  const auto [within, lit] = agreement(gpu, cpu.luxels);
  EXPECT_GE(double(within), 0.999 * double(gpu.size()));
  EXPECT_GT(lit, gpu.size() / 2);
}

// The lights' visapprox boxes the GPU computes (bake.comp's box pass) are the CPU's, bit for bit
// where both tracers' rays stop at the same t: on llvmpipe (IEEE float throughout), as the stop
// points and the growth are computed with the same roundings on both. A GPU whose division is not
// correctly rounded may put a t an ulp off, and a box's side with it: there, 4 ulps of the box's
// largest coordinate on that axis. The levels: the visapprox levels (a light beside a water wall
// that stops its rays), Quake 2's alpha-tested fence and window, a sky window (the rays stop at
// sky), Quake 1's `{` fences, ericw-tools' light_general (44 lights) and id's e1m1 (a whole level).
TEST(GlBake, GpuVisapproxBoxesAreTheCpus) {
  BT_REQUIRE_SHARED(shared);
  const int ulps = test::sharedGlContext().info().softwareRenderer ? 0 : 4;
  const auto near = [ulps](const GpuVisBox& gpu, const GpuVisBox& cpu, int axis) {
    const float reach = std::max(std::abs(cpu.mins[axis]), std::abs(cpu.maxs[axis]));
    const float tolerance = float(ulps) * (std::nextafter(reach, INFINITY) - reach);
    return std::abs(gpu.mins[axis] - cpu.mins[axis]) <= tolerance && std::abs(gpu.maxs[axis] - cpu.maxs[axis]) <= tolerance;
  };
  size_t boxes = 0;
  for (const char* map : {"ericw-tools/testmaps/q2_light_visapprox.map", "ericw-tools/testmaps/q2_light_visapprox2.map",
                          "ericw-tools/testmaps/q2_light_translucency.map", "ericw-tools/testmaps/q2_alphatest_window.map",
                          "ericw-tools/testmaps/q1_sky_window.map", "ericw-tools/testmaps/q1_detail_fence.map",
                          "ericw-tools/testmaps/light_general.map", "quake_map_source/e1m1.map"}) {
    const Scene scene = importScene((shared / "maps" / map).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderScene rs = buildRenderScene(scene, {}, diagnostics); // the CPU's boxes
    ASSERT_EQ(rs.visBoxes.size(), rs.visBoxLights.size()) << map;
    LuxelBakeJob job; // no luxels: the boxes alone, the GPU's to compute
    for (uint32_t i : rs.visBoxLights) job.boxedLights.push_back(rs.lights[i].origin);
    GlTracer tracer(test::sharedGlContext(), scene, rs.tracer, TextureMode::Arrays, lightingFor(rs));
    GlLightmapBake bake(tracer, job);
    const std::vector<GpuVisBox> gpu = bake.lightBoxes();
    ASSERT_EQ(gpu.size(), rs.visBoxes.size()) << map;
    for (size_t k = 0; k < gpu.size(); ++k)
      for (int a = 0; a < 3; ++a)
        EXPECT_TRUE(near(gpu[k], rs.visBoxes[k], a))
            << map << ": light box " << k << " axis " << a << ": GPU " << gpu[k].mins[a] << " .. " << gpu[k].maxs[a] << ", CPU "
            << rs.visBoxes[k].mins[a] << " .. " << rs.visBoxes[k].maxs[a];
    boxes += gpu.size();
  }
  EXPECT_GT(boxes, 100u) << "lights to compare";
}

// Quake 2's glass (lit from both sides, passing the light) and `_world_units_per_luxel`'s
// decoupled luxel grid are the CPU's sample points and face classes: the GPU bakes the same
// luxels from them.
TEST(GlBake, GlassAndDecoupledGridsBakeAsOnTheCpu) {
  BT_REQUIRE_SHARED(shared);
  for (const char* map : {"light_q2_translucent_shadow.map", "q2_lightmap_custom_scale.map"}) {
    const Scene scene = importScene((shared / "maps/ericw-tools/testmaps" / map).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    Lightmaps cpu = layoutLightmaps(rs);
    ASSERT_GT(cpu.luxels.size(), 500u) << map;
    const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
    const auto [within, lit] = agreement(gpu, cpu.luxels);
    EXPECT_GE(double(within), 0.999 * double(gpu.size())) << map;
    EXPECT_GT(lit, gpu.size() / 20) << map;
  }
}

// Quake 2 water drawn as a wall shadows from inside (RenderScene::blocksFromInside): the GPU bake,
// built with the rule (BT_BLOCKS_FROM_INSIDE), stores the CPU's luxels of q2_light_visapprox2,
// where a sixth of them lie in the water's shadow seen from inside.
TEST(GlBake, WaterDrawnAsAWallShadowsFromInsideAsOnTheCpu) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/q2_light_visapprox2.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  ASSERT_FALSE(rs.blocksFromInside.empty());
  Lightmaps cpu = layoutLightmaps(rs);
  ASSERT_GT(cpu.luxels.size(), 1000u);
  const std::vector<uint32_t> gpu = bakeOnBoth(scene, rs, cpu);
  const auto [within, lit] = agreement(gpu, cpu.luxels);
  EXPECT_GE(double(within), 0.999 * double(gpu.size()));
  EXPECT_GT(lit, gpu.size() / 20);
}

} // namespace
