// The GL integrator against closed-form values: faithful mode's ericw-tools formulas and
// physical mode's direct lighting, on the hand-built room.
#include "lighting/render_scene.h"
#include "lighting/sampling.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_lighting.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"
#include "scene/color.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace bt::gl {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;

// The tracer's pixel jitter in physical mode: the first pair of the pixel's Sobol sequence
// (lighting/sampling.h pixelSampler).
glm::vec2 pixelJitter(uint32_t x, uint32_t y, uint32_t sample, uint32_t seed) {
  Rng rng = pixelSampler(x, y, sample, seed);
  return rng.next2();
}

float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Pixels whose 3x3 neighbourhood sees only the untextured material: every jittered sample
// lands on the same flat grey face.
std::vector<size_t> plainInteriorPixels(const Scene& scene, const AovImages& aov) {
  std::vector<size_t> pixels;
  const uint32_t plain = *scene.findMaterial("plain");
  for (int y = 1; y + 1 < aov.height; ++y)
    for (int x = 1; x + 1 < aov.width; ++x) {
      const uint32_t f = aov.face[static_cast<size_t>(y) * aov.width + x];
      bool interior = f != AovImages::kNothingHit && scene.faces[f - 1].material == plain;
      for (int dy = -1; dy <= 1 && interior; ++dy)
        for (int dx = -1; dx <= 1; ++dx) interior &= aov.face[static_cast<size_t>(y + dy) * aov.width + x + dx] == f;
      if (interior) pixels.push_back(static_cast<size_t>(y) * aov.width + x);
    }
  return pixels;
}

TEST(GlBeauty, FaithfulInfiniteLightGivesTheOverbrightFormula) {
  // delay 3 (no falloff) and _anglescale 0: every lit point of the grey wall receives exactly
  // `light`, the compiler stores light * _range, and the engine shows texture * stored / 128.
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeTestRoom();
  GlLighting lighting;
  GpuLight light;
  light.origin = {-100, 0, 200};
  light.value = 200.0f;
  light.formula = 3;
  light.anglescale = 0.0f;
  lighting.lights = {light};
  GlTracer tracer(*context, scene, test::textureModeUnderTest(), lighting);
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  const AovImages aov = tracer.renderAovs(camera, kWidth, kHeight);
  const BeautyImage image = tracer.renderBeauty(camera, {.width = kWidth, .height = kHeight, .spp = 4});
  ASSERT_EQ(image.samples, 4);

  const float expected = srgbToLinear(0.5f * (200.0f * 0.5f) / 128.0f);
  const auto pixels = plainInteriorPixels(scene, aov);
  ASSERT_GT(pixels.size(), 50u);
  size_t lit = 0, dark = 0;
  for (size_t i : pixels) {
    const glm::vec3 c = image.beauty[i];
    if (glm::length(c - glm::vec3(expected)) < 1e-5f)
      ++lit;
    else if (glm::length(c) < 1e-6f)
      ++dark;
    else
      ADD_FAILURE() << "pixel " << i << " = (" << c.x << ", " << c.y << ", " << c.z << "), expected " << expected << " or 0";
  }
  EXPECT_GT(lit, pixels.size() / 2) << "the wall should be mostly lit (" << dark << " in shadow)";
}

// The viewer's style sliders scale a `_surface` template's colour in place (viewer.cpp
// scaleLights, GlTracer::setSurfaceLights): physical mode's area emitters then give, every pixel,
// what the room gives when built with a template a quarter as bright.
TEST(GlBeauty, ReplacedSurfaceTemplatesLightAsTheLevelBuiltWithThem) {
  GlContext* context = &test::sharedGlContext();
  const auto room = [](const char* value) {
    Scene scene = test::makeTestRoom();
    Entity light;
    light.keys = {{"classname", "light"}, {"origin", "0 0 128"}, {"light", value}, {"_surface", "stripes"}};
    scene.entities.push_back(light);
    return scene;
  };
  const Scene bright = room("40"), dim = room("10");
  Diagnostics diagnostics;
  RenderScene brightRs = buildRenderScene(bright, {}, diagnostics);
  const RenderScene dimRs = buildRenderScene(dim, {}, diagnostics);
  ASSERT_FALSE(brightRs.emitters.empty()) << "the stripes faces emit";
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  const BeautySettings settings{.width = kWidth, .height = kHeight, .spp = 4, .physical = true, .bounces = 1};
  GlTracer dimTracer(*context, dim, test::textureModeUnderTest(), lightingFor(dimRs));
  const BeautyImage expected = dimTracer.renderBeauty(camera, settings);
  GlTracer tracer(*context, bright, test::textureModeUnderTest(), lightingFor(brightRs));
  const BeautyImage before = tracer.renderBeauty(camera, settings);
  for (GpuLight& t : brightRs.surfaceLights) t.color *= 0.25f;
  tracer.setSurfaceLights(brightRs.surfaceLights);
  const BeautyImage after = tracer.renderBeauty(camera, settings);
  float worst = 0.0f, changed = 0.0f;
  for (size_t i = 0; i < expected.beauty.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      worst = std::max(worst, std::abs(after.beauty[i][c] - expected.beauty[i][c]) / std::max(expected.beauty[i][c], 1e-3f));
      changed = std::max(changed, std::abs(before.beauty[i][c] - expected.beauty[i][c]) / std::max(expected.beauty[i][c], 1e-3f));
    }
  EXPECT_LE(worst, 1e-5f) << "the replaced templates do not light as the level built with them";
  EXPECT_GT(changed, 0.5f) << "the template's brightness changes nothing: the test cannot tell";
}

TEST(GlBeauty, PhysicalPointLightGivesInverseSquareLambert) {
  // Direct light only (bounces 0) from a point light on a diffuse grey wall:
  // L = albedo / pi * I * W(d) * cos(theta) / d^2: an inverse-square (delay 2) `light 300` ends
  // where the compiler's light falls to 1, 128 sqrt(300) units away, and matches it at 128
  // (lighting/physical_light.h), so I = 300 * 128^2 / W(128) * _range * pi * 0.6 / 128 (0.6 the
  // display match, lighting/README.md "Physical mode"), with Karis' window W(d) = (1 - (d / reach)^4)^2.
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeTestRoom();
  GlLighting lighting;
  GpuLight light;
  light.origin = {-100, 0, 200};
  light.value = 300.0f;
  light.formula = uint32_t(LightFormula::Inverse2);
  lighting.lights = {light};
  GlTracer tracer(*context, scene, test::textureModeUnderTest(), lighting);
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  const AovImages aov = tracer.renderAovs(camera, kWidth, kHeight);
  constexpr int kSpp = 8;
  const BeautyImage image = tracer.renderBeauty(camera, {.width = kWidth, .height = kHeight, .spp = kSpp, .physical = true, .bounces = 0});

  const float albedo = srgbToLinear(0.5f);
  const auto window = [](float d) {
    const float x = d / (128.0f * std::sqrt(300.0f)), w = std::max(1.0f - x * x * x * x, 0.0f);
    return w * w;
  };
  const float intensity = 300.0f * 128.0f * 128.0f / window(128.0f) * 0.5f * 3.14159265f * 0.6f / 128.0f;
  size_t compared = 0;
  for (size_t i : plainInteriorPixels(scene, aov)) {
    const int x = static_cast<int>(i % kWidth), y = static_cast<int>(i / kWidth);
    const Plane& plane = scene.faces[aov.face[i] - 1].plane;
    const glm::vec3 n(plane.normal);
    // The mean over the tracer's own jittered rays, each meeting the wall's plane.
    float expected = 0.0f;
    for (int s = 0; s < kSpp; ++s) {
      const glm::vec2 j = pixelJitter(x, y, s, 0);
      const glm::vec3 dir =
          glm::normalize(camera.forward + ((x + j.x) / kWidth * 2 - 1) * camera.right - ((y + j.y) / kHeight * 2 - 1) * camera.up);
      const glm::vec3 p = camera.origin + dir * ((float(plane.dist) - glm::dot(n, camera.origin)) / glm::dot(n, dir));
      const glm::vec3 toLight = light.origin - p;
      const float d2 = glm::dot(toLight, toLight);
      expected += albedo / 3.14159265f * intensity * window(std::sqrt(d2)) * (glm::dot(n, toLight) / std::sqrt(d2)) / d2 / kSpp;
    }
    const float got = image.beauty[i].x;
    if (got == 0.0f) continue; // in the pillar's shadow
    // Float error only (the 0.03-unit surface offset of the shadow ray's origin is ignored).
    EXPECT_NEAR(got, expected, 2e-3f * expected) << "pixel " << i;
    ++compared;
  }
  EXPECT_GT(compared, 50u);
}

TEST(GlBeauty, SameSeedAndSampleCountGiveTheSameImage) {
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeTestRoom();
  GlLighting lighting;
  lighting.lights = {GpuLight{.origin = {0, 0, 200}}};
  GlTracer tracer(*context, scene, test::textureModeUnderTest(), lighting);
  const CameraBasis camera = test::testCamera(32, 24);
  const BeautySettings settings{.width = 32, .height = 24, .spp = 3, .seed = 7, .physical = true, .bounces = 2};
  const BeautyImage a = tracer.renderBeauty(camera, settings);
  const BeautyImage b = tracer.renderBeauty(camera, settings);
  EXPECT_EQ(a.beauty, b.beauty);
  BeautySettings other = settings;
  other.seed = 8;
  EXPECT_NE(a.beauty, tracer.renderBeauty(camera, other).beauty);
}

} // namespace
} // namespace bt::gl
