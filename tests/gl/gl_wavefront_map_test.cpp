// The wavefront form against the megakernel on real levels (tests/gl/gl_wavefront_test.cpp has
// the hand-built room): a LibreQuake map with its textures, and maps/start.map, whose sun, sky,
// spotlights and emitting lamp exercise every kind of ray in both lighting modes.
#include "importers/import.h"
#include "lighting/compiled_lightmaps.h"
#include "lighting/lightmaps.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_lighting.h"
#include "renderer/gl/gl_render.h"
#include "tests/gl/test_scenes.h"
#include "tests/render/box_scene.h"
#include "tests/render/normal_map_room.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace bt::gl {
namespace {

constexpr int kWidth = 72;
constexpr int kHeight = 40;

// The two forms' images compared pixel by pixel: how many are bit-exact, and how many differ
// beyond a float tolerance (the two forms are separate programs for the driver's optimiser; on
// llvmpipe and the H100 they were bit-identical).
struct FormsCompared {
  size_t exact = 0, differing = 0;
};
FormsCompared compareForms(const BeautyImage& mega, const BeautyImage& wave) {
  FormsCompared out;
  for (size_t i = 0; i < mega.beauty.size(); ++i) {
    const glm::vec3 a = mega.beauty[i], b = wave.beauty[i];
    out.exact += a == b;
    const glm::vec3 d = glm::abs(a - b);
    if (std::max(d.x, std::max(d.y, d.z)) > 1e-4f * std::max(1.0f, std::max(a.x, std::max(a.y, a.z)))) ++out.differing;
  }
  return out;
}

// The same image from both forms, pixel for pixel, at 2 spp, from `pose` (the level's start by
// default), with more than 1 / litShare of its pixels lit.
void expectFormsAgree(const Scene& scene, const RenderScene& render, bool physical, const CameraPose& pose, size_t litShare = 2) {
  GlTracer tracer(test::sharedGlContext(), scene, render.tracer, test::textureModeUnderTest(), lightingFor(render));
  const CameraBasis camera = cameraFrom(pose, kWidth, kHeight);
  BeautySettings settings{.width = kWidth, .height = kHeight, .spp = 2, .seed = 11, .physical = physical, .bounces = 2};
  settings.form = PathTracerForm::Megakernel;
  const BeautyImage mega = tracer.renderBeauty(camera, settings);
  settings.form = PathTracerForm::Wavefront;
  const BeautyImage wave = tracer.renderBeauty(camera, settings);
  ASSERT_EQ(wave.wavefrontSamples, 2);
  ASSERT_EQ(mega.beauty.size(), wave.beauty.size());
  size_t lit = 0;
  for (const glm::vec3& a : mega.beauty) lit += a != glm::vec3(0.0f);
  const FormsCompared c = compareForms(mega, wave);
  EXPECT_GT(lit, mega.beauty.size() / litShare) << "a black image proves nothing";
  EXPECT_LE(c.differing, mega.beauty.size() / 200) << c.differing << " of " << mega.beauty.size() << " pixels differ";
  std::printf("wavefront vs megakernel: %zu of %zu pixels bit-exact\n", c.exact, mega.beauty.size());
}

void expectFormsAgree(const Scene& scene, bool physical) {
  Diagnostics diagnostics;
  expectFormsAgree(scene, buildRenderScene(scene, {}, diagnostics), physical, defaultCameraPose(scene));
}

TEST(GlWavefrontMap, TexturedLibreQuakeMapFaithful) {
  BT_REQUIRE_SHARED(shared);
  ImportOptions options;
  for (const auto& dir : std::filesystem::directory_iterator(shared / "maps/librequake/texture-wads"))
    if (dir.is_directory()) options.textures.textureDirs.push_back(dir.path().string());
  const Scene scene = importScene((shared / "maps/librequake/lq1/maps/src/misc/slope.map").string(), options);
  expectFormsAgree(scene, false);
}

TEST(GlWavefrontMap, StartMapPhysicalWithEmitters) {
  const Scene scene = importScene((test::mapsDir() / "start.map").string(), ImportOptions{});
  expectFormsAgree(scene, true);
}

// Translucent water (maps/liquids/pool.map, `_wateralpha 0.5`): the faithful veil of the liquids
// passed (Path::veil) is kept between dispatches; physical mode's pass through the liquids and
// the glowing lava (pools.map) draw the same numbers in both forms.
TEST(GlWavefrontMap, TranslucentWaterFaithful) {
  expectFormsAgree(importScene((test::mapsDir() / "liquids/pool.map").string(), ImportOptions{}), false);
}

TEST(GlWavefrontMap, LiquidsPhysical) {
  expectFormsAgree(importScene((test::mapsDir() / "liquids/pools.map").string(), ImportOptions{}), true);
}

// A PNG fence's holes (maps/engine_rules/fence.map): the wavefront form's trace kernel does the
// alpha test of a closest hit for its shade kernel (trace.glsl closestHitMasked), the megakernel
// in advance() (pathtrace.comp hitMasked): both pass the same holes.
TEST(GlWavefrontMap, AlphaTestedFenceFaithful) {
  expectFormsAgree(importScene((test::mapsDir() / "engine_rules/fence.map").string(), ImportOptions{}), false);
}

TEST(GlWavefrontMap, AlphaTestedFencePhysical) {
  expectFormsAgree(importScene((test::mapsDir() / "engine_rules/fence.map").string(), ImportOptions{}), true);
}

// Quake 3's blends (maps/q3blend/): the filter's per-channel weight and the additive panel's
// light outlive a dispatch (path_fields.glsl veilKeep, radiance).
TEST(GlWavefrontMap, Quake3BlendsFaithful) {
  expectFormsAgree(importScene((test::mapsDir() / "q3blend/maps/blends.map").string(), ImportOptions{}), false);
}

TEST(GlWavefrontMap, Quake3BlendsPhysical) {
  expectFormsAgree(importScene((test::mapsDir() / "q3blend/maps/blends.map").string(), ImportOptions{}), true);
}

// Faithful `_bounce` with more bounce lights in a cell than kBounceShadowRays: the draw among
// them keeps its place in the path between the wavefront's dispatches (Path's bounce fields).
TEST(GlWavefrontMap, ManyBounceLightsFaithful) {
  Scene scene = test::manyLightsRoom(24, false, 7);
  scene.entities[0].keys.emplace_back("_bounce", "1");
  Entity start; // the camera: in the room, looking across it
  start.keys = {{"classname", "info_player_start"}, {"origin", "400 -400 150"}, {"angle", "135"}};
  scene.entities.push_back(start);
  expectFormsAgree(scene, false);
}

// Physical mode's shading normal (Bsdf::n, from a normal map) outlives a dispatch: a mirrored,
// glossy wall of bumps (tests/render/normal_map_room.h), seen from the room's middle.
TEST(GlWavefrontMap, NormalMappedWallPhysical) {
  const test::NormalMapRoom room({test::bumpsNormalMap(12, 12), true, {96.0f, -120.0f, 128.0f}, true});
  Scene scene = room.scene();
  Entity start;
  start.keys = {{"classname", "info_player_start"}, {"origin", "-8 0 106"}, {"angle", "0"}};
  scene.entities.push_back(start);
  expectFormsAgree(scene, true);
}

// A .bsp's own lightmaps (--lighting compiled), a Quake one and a Half-Life one (GoldSrc's luxel
// display table), which both forms read in faithfulSurface(). The views are
// gl_cpu_parity_test.cpp's (litView): the Half-Life level's start looks at a dark wall.
TEST(GlWavefrontMap, CompiledLightmapsFaithful) {
  BT_REQUIRE_SHARED(shared);
  for (const char* file : {"lit/maps_ericw-tools_testmaps_q1_light_hlform.bsp", "lit-games/maps_ericw-tools_testmaps_hl_basic.bsp"}) {
    SCOPED_TRACE(file);
    const Scene scene = importScene((shared / "oracle" / file).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderScene render = buildRenderScene(scene, {}, diagnostics);
    ASSERT_EQ(showCompiledLightmaps(scene, render, ""), "");
    CameraPose pose = defaultCameraPose(scene);
    if (scene.format == "bsp30") {
      pose.origin = {-102.4f, 83.2f, 144.0f};
      pose.pitch = -90.0f, pose.yaw = 0.0f;
    }
    expectFormsAgree(scene, render, false, pose, 4);
  }
}

// Luxels that come after the first images (a bake that lands, the viewer's compiled view): the
// wavefront form draws a level with no baked face with a shade kernel that has no luxels' read
// (FaithfulFeatures::luxels), and once they are set it draws them as the megakernel does.
TEST(GlWavefrontMap, LuxelsSetAfterTheFirstImagesFaithful) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "oracle" / "lit/maps_ericw-tools_testmaps_q1_light_hlform.bsp").string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderScene render = buildRenderScene(scene, {}, diagnostics);
  ASSERT_EQ(showCompiledLightmaps(scene, render, ""), "");
  const std::vector<uint32_t> packed = packLightmaps(render.lightmaps);
  render.lightmaps = {};
  GlTracer tracer(test::sharedGlContext(), scene, render.tracer, test::textureModeUnderTest(), lightingFor(render));
  ASSERT_FALSE(tracer.faithfulFeatures().luxels);
  const CameraBasis camera = cameraFrom(defaultCameraPose(scene), kWidth, kHeight);
  BeautySettings settings{.width = kWidth, .height = kHeight, .spp = 2, .seed = 11};
  settings.form = PathTracerForm::Wavefront;
  const BeautyImage unbaked = tracer.renderBeauty(camera, settings);
  tracer.setLightmaps(packed);
  ASSERT_TRUE(tracer.faithfulFeatures().luxels);
  const BeautyImage wave = tracer.renderBeauty(camera, settings);
  settings.form = PathTracerForm::Megakernel;
  const BeautyImage mega = tracer.renderBeauty(camera, settings);
  ASSERT_EQ(wave.wavefrontSamples, 2);
  ASSERT_EQ(mega.beauty.size(), wave.beauty.size());
  size_t shown = 0;
  for (size_t i = 0; i < wave.beauty.size(); ++i) shown += wave.beauty[i] != unbaked.beauty[i];
  const FormsCompared c = compareForms(mega, wave);
  EXPECT_GT(shown, mega.beauty.size() / 4) << "the luxels change too few pixels to tell";
  EXPECT_LE(c.differing, mega.beauty.size() / 200) << c.differing << " of " << mega.beauty.size() << " pixels differ";
  std::printf("wavefront vs megakernel once the luxels are set: %zu of %zu pixels bit-exact, %zu changed by the luxels\n", c.exact,
              mega.beauty.size(), shown);
}

} // namespace
} // namespace bt::gl
