// The GL tracer on the sky level (maps/sky/; tests/render/sky_test.cpp holds the CPU tracer to
// the engine's formula): Quake's two-layer sky seen by direction, pixel for pixel in the albedo
// AOV and in the beauty of both lighting modes, against the CPU reference.
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_lighting.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/cpu_and_gl.h"
#include "tests/gl/test_scenes.h"
#include "tests/render/box_scene.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace bt::gl {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 64;

test::CpuAndGl renderSkyLevel(LightingMode mode, const std::filesystem::path& level = "sky_layers.map") {
  const Scene scene = importScene((test::mapsDir() / "sky" / level).string(), ImportOptions{});
  return test::renderCpuAndGl(scene, mode, kWidth, kHeight);
}

// Albedo pixel for pixel (one ray through each pixel centre in both); beauty as
// gl_engine_rules_test's: 97 % of pixels within 1 %, the means within `meanTolerance`.
void expectSkyAgrees(const test::CpuAndGl& r, double meanTolerance) {
  ASSERT_EQ(r.gpu.albedo.size(), r.cpu.albedo.size());
  size_t sameFace = 0, albedoClose = 0, beautyClose = 0;
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  for (size_t i = 0; i < r.cpu.albedo.size(); ++i) {
    sameFace += r.gpu.face[i] == r.cpu.face[i];
    const glm::vec3 d = glm::abs(r.gpu.albedo[i] - r.cpu.albedo[i]);
    albedoClose += std::max({d.x, d.y, d.z}) <= 2e-3f;
    beautyClose += glm::length(r.gpu.beauty[i] - r.cpu.beauty[i]) <= 0.01f * glm::length(r.cpu.beauty[i]) + 1e-3f;
    gpuSum += glm::dvec3(r.gpu.beauty[i]);
    cpuSum += glm::dvec3(r.cpu.beauty[i]);
  }
  const size_t n = r.cpu.albedo.size();
  EXPECT_GE(sameFace, n * 995 / 1000);
  EXPECT_GE(albedoClose, n * 995 / 1000) << albedoClose << " of " << n << " albedo pixels agree";
  EXPECT_GE(beautyClose, n * 97 / 100) << beautyClose << " of " << n << " beauty pixels agree";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], meanTolerance * cpuSum[c] + 1e-6) << "channel " << c;
}

// test::twoSkiesRoom's sun shines through `sky_b` alone: the CPU's floor under `sky_a` (the
// image's left third; the camera looks north) must be far darker than under `sky_b` (its right
// third), so that a GL tracer that let the sun through every sky would fail the comparison.
void expectFloorLitUnderSkyBOnly(const test::CpuAndGl& r) {
  double west = 0.0, east = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth / 3; ++x) {
      west += r.cpu.beauty[size_t(y) * kWidth + x].x;
      east += r.cpu.beauty[size_t(y) * kWidth + kWidth - 1 - x].x;
    }
  EXPECT_LT(west, 0.2 * east);
}

TEST(GlSky, TwoLayerSkyMatchesTheCpuInFaithfulMode) {
  expectSkyAgrees(renderSkyLevel(LightingMode::Faithful), 0.01);
}

TEST(GlSky, TwoLayerSkyMatchesTheCpuInPhysicalMode) {
  expectSkyAgrees(renderSkyLevel(LightingMode::Physical), 0.03);
}

// A physical sun with `_suntexture` shines only through sky faces of that texture on the GPU as
// on the CPU (test::twoSkiesRoom: the floor under the other sky is dark but for the bounces).
TEST(GlSky, PhysicalSunShinesOnlyThroughItsSkyTexture) {
  const test::CpuAndGl r = test::renderCpuAndGl(test::twoSkiesRoom(), LightingMode::Physical, kWidth, kHeight);
  expectSkyAgrees(r, 0.03);
  expectFloorLitUnderSkyBOnly(r);
}

// The same room in faithful mode's per-pixel light (`--luxels off`): the compiler's sun with
// `_suntexture` lights only the floor under `sky_b`, on the GPU as on the CPU (faithful mode has
// no bounce here, so the floor under `sky_a` gets nothing but the sky's own texture around it).
TEST(GlSky, FaithfulSunShinesOnlyThroughItsSkyTexture) {
  const test::CpuAndGl r = test::renderCpuAndGl(test::twoSkiesRoom(), LightingMode::Faithful, kWidth, kHeight);
  expectSkyAgrees(r, 0.01);
  expectFloorLitUnderSkyBOnly(r);
}

// The sky box's six images reach the GPU as materials no face uses (on either texture path).
TEST(GlSky, SkyBoxMatchesTheCpu) {
  const Scene scene = importScene((test::mapsDir() / "sky" / "id1/maps/sky_box.map").string(), ImportOptions{});
  if (!scene.sky || scene.sky->kind != Sky::Kind::Box)
    GTEST_SKIP() << "this build reads no .tga sky box images (the portable GPU bundle reads PNG only)";
  const test::CpuAndGl faithful = renderSkyLevel(LightingMode::Faithful, "id1/maps/sky_box.map");
  expectSkyAgrees(faithful, 0.01);
  expectSkyAgrees(renderSkyLevel(LightingMode::Physical, "id1/maps/sky_box.map"), 0.03);
  // Not the layers' blues: the box's sides (red rt ahead, cyan up, magenta dn at the frame's edges).
  size_t red = 0;
  for (const glm::vec3& a : faithful.gpu.albedo) red += a.x > 0.3f && a.y < 0.05f && a.z < 0.05f;
  EXPECT_GT(red, faithful.gpu.albedo.size() / 4);
}

// The wavefront form's shade kernel reads the sky where the megakernel does (pathtrace.comp
// advance): the same image from both forms, pixel for pixel, with the sky in view.
TEST(GlSky, WavefrontFormShowsTheSameSkyAsTheMegakernel) {
  const Scene scene = importScene((test::mapsDir() / "sky" / "sky_layers.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  const RenderScene render = buildRenderScene(scene, {}, diagnostics);
  GlTracer tracer(test::sharedGlContext(), scene, render.tracer, test::textureModeUnderTest(), lightingFor(render));
  const CameraBasis camera = cameraFrom(defaultCameraPose(scene), kWidth, kHeight);
  for (bool physical : {false, true}) {
    BeautySettings settings{.width = kWidth, .height = kHeight, .spp = 2, .seed = 11, .physical = physical, .bounces = 2};
    settings.form = PathTracerForm::Megakernel;
    const BeautyImage mega = tracer.renderBeauty(camera, settings);
    settings.form = PathTracerForm::Wavefront;
    const BeautyImage wave = tracer.renderBeauty(camera, settings);
    ASSERT_EQ(wave.wavefrontSamples, 2);
    size_t differing = 0, blue = 0;
    for (size_t i = 0; i < mega.beauty.size(); ++i) {
      const glm::vec3 a = mega.beauty[i], d = glm::abs(a - wave.beauty[i]);
      differing += std::max({d.x, d.y, d.z}) > 1e-4f * std::max({1.0f, a.x, a.y, a.z});
      blue += a.z > 2.0f * a.x && a.z > 0.05f; // the back layer showing through
    }
    EXPECT_GT(blue, mega.beauty.size() / 10) << "the sky should be in view; physical " << physical;
    EXPECT_LE(differing, mega.beauty.size() / 200) << differing << " pixels differ; physical " << physical;
  }
}

} // namespace
} // namespace bt::gl
