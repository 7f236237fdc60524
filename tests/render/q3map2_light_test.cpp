// Faithful light of Quake 3 levels as q3map2 computes it (lighting/q3map2_light.h), against
// q3map2's formulas written out again here (light.c CreateEntityLights, light_ydnar.c
// LightContributionToSample, ColorToBytes) and evaluated at each luxel's sample point and at
// each pixel's surface point: no q3map2 output exists in ../shared to compare with.
#include "importers/import.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "renderer/cpu/cpu_renderer.h"
#include "scene/color.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace bt {
namespace {

// One light of maps/q3map2/point_lights.map as q3map2 reads it.
struct Q3Light {
  glm::vec3 origin;
  glm::vec3 color;           // _color / its brightest channel
  float photons;             // light × scale × 7500 (pointScale, spotScale)
  bool linear;               // spawnflags 1
  bool angle;                // not spawnflags 1 or 2
  float radiusByDist = 0.0f; // spotlights: (radius + 16) / distance to the target
};

const std::vector<Q3Light>& mapLights() {
  static const std::vector<Q3Light> lights = {
      {{-256, -256, 128}, {1.0f, 128.0f / 255.0f, 64.0f / 255.0f}, 100 * 7500.0f, false, true},
      {{256, -256, 64}, {1, 1, 1}, 150 * 7500.0f, true, false},
      {{0, 256, 128}, {1, 1, 1}, 150 * 7500.0f, false, true, (96.0f + 16.0f) / 128.0f},
      {{256, 256, 128}, {0.25f, 0.5f, 1.0f}, 50 * 2 * 7500.0f, false, false},
  };
  return lights;
}

// LightContributionToSample for a point or spot light at sample point p with normal n, no shadow.
glm::vec3 contribution(const Q3Light& l, const glm::vec3& p, const glm::vec3& n) {
  const float linearScale = 1.0f / 8000.0f;
  const float dist = glm::length(l.origin - p);
  const float envelope = l.linear ? l.photons * linearScale - 1.0f : std::sqrt(l.photons / 1.0f);
  if (dist >= envelope) return glm::vec3(0.0f);
  const float d = std::max(dist, 16.0f);
  const float angle = l.angle ? glm::dot(n, (l.origin - p) / dist) : 1.0f;
  float add = l.linear ? angle * l.photons * linearScale - d : l.photons / (d * d) * angle;
  if (l.radiusByDist > 0.0f) {
    const glm::vec3 axis(0, 0, -1);
    const float along = glm::dot(p - l.origin, axis);
    if (along < 0.0f) return glm::vec3(0.0f);
    const float sampleRadius = glm::length(p - (l.origin + along * axis));
    const float radiusAtDist = l.radiusByDist * along;
    if (sampleRadius >= radiusAtDist) return glm::vec3(0.0f);
    if (sampleRadius > radiusAtDist - 32.0f) add *= (radiusAtDist - sampleRadius) / 32.0f;
  }
  return add > 0.0f ? l.color * add : glm::vec3(0.0f);
}

glm::vec3 lightSum(const glm::vec3& p, const glm::vec3& n) {
  glm::vec3 sum(0.0f);
  for (const Q3Light& l : mapLights()) sum += contribution(l, p, n);
  return sum;
}

// What ioquake3 uploads for a luxel (q3map2's ColorToBytes at its defaults, then
// R_ColorShiftLightingBytes' one bit): 2 × the sum, its hue kept below 255.
glm::vec3 engineLuxel(glm::vec3 sum) {
  sum *= 2.0f;
  const float peak = std::max({sum.x, sum.y, sum.z});
  return peak > 255.0f ? sum * (255.0f / peak) : sum;
}

struct Level {
  Scene scene;
  RenderScene render;
};

std::unique_ptr<Level> loadPointLights() {
  auto level = std::make_unique<Level>();
  ImportOptions options;
  options.textures.textureDirs.push_back((test::mapsDir() / "q3map2" / "textures").string());
  level->scene = importScene((test::mapsDir() / "q3map2" / "point_lights.map").string(), options);
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, RenderSceneOptions{}, diagnostics);
  return level;
}

// Every luxel of the floor's top, in colour: the byte the test's own q3map2 formula gives at
// its sample point, within one (float rounding at the truncation).
TEST(Q3map2Light, FloorLuxelsAreQ3map2sPointSpotAndLinearLights) {
  const auto level = loadPointLights();
  ASSERT_EQ(level->scene.format.substr(0, 6), "quake3");
  Lightmaps lightmaps = layoutLightmaps(level->render);
  const std::vector<GpuLuxelSample> samples = luxelSamples(level->render, lightmaps, 1);
  bakeLightmaps(level->render, lightmaps);
  ASSERT_EQ(samples.size(), lightmaps.luxels.size());
  size_t compared = 0, lit = 0, unclamped = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const GpuLuxelSample& s = samples[i];
    const glm::vec3 n = level->scene.faces[s.face].plane.normal;
    if (n.z < 0.99f || (s.flags & kLuxelSampleOccluded)) continue;
    const glm::vec3 p(s.position[0], s.position[1], s.position[2]);
    const glm::vec3 expected = glm::floor(engineLuxel(lightSum(p, n)));
    const glm::vec3 got = unpackLuxel(lightmaps.luxels[i]);
    ASSERT_LE(glm::length(got - expected), 1.75f)
        << "luxel " << i << " at " << p.x << " " << p.y << " " << p.z << ": got " << got.x << " " << got.y << " " << got.z << ", q3map2 "
        << expected.x << " " << expected.y << " " << expected.z;
    ++compared;
    lit += expected.x + expected.y + expected.z > 6.0f;
    const float peak = std::max({expected.x, expected.y, expected.z});
    unclamped += peak < 254.0f && peak > 20.0f;
  }
  EXPECT_GT(compared, 1000u);
  EXPECT_GT(lit, compared / 2) << "the lights must reach most of the floor";
  EXPECT_GT(unclamped, compared / 8) << "most luxels must lie below the clamp, where a wrong scale shows";
  EXPECT_FLOAT_EQ(lightmaps.displayScale, 1.0f / 127.5f); // ioquake3: texture × luxel × 2 / 255
}

// The CPU tracer's picture from above, every pixel in colour: the one-coloured floor shown as ioquake3
// shows the light at that point (texture × luxel × 2/255 in sRGB), the light evaluated at each
// pixel's point (--luxels off). A pixel's sample lies somewhere in it: its value must lie between
// the formula's values at the pixel's corners and centre.
TEST(Q3map2Light, PixelsShowTheLightAsIoquake3Does) {
  const auto level = loadPointLights();
  constexpr int kWidth = 96, kHeight = 64;
  CameraPose pose;
  pose.origin = {0.0f, 0.0f, 400.0f};
  pose.pitch = 90.0f; // looking down
  const Camera camera(pose, kWidth, kHeight);
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 1;
  settings.threads = 2;
  const RenderImage image = renderCpu(level->render, camera, settings);
  const glm::vec3 up(0, 0, 1);
  const glm::vec3 texture = linearToSrgb(image.albedo[0]); // maps/q3map2/textures/flat_grey.png: one grey (204)
  const auto shown = [&](float x, float y) {
    const Ray ray = camera.ray(x, y);
    const glm::vec3 p = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
    return srgbToLinear(texture * engineLuxel(lightSum(p, up)) / 127.5f);
  };
  size_t bright = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      ASSERT_GT(image.normal[i].z, 0.99f) << "pixel " << x << "," << y << " must see the floor's top";
      ASSERT_LT(glm::length(image.albedo[i] - image.albedo[0]), 1e-3f) << "the floor's texture is one colour";
      glm::vec3 lo(1e30f), hi(-1e30f);
      for (const glm::vec2 c : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(0, 1), glm::vec2(1, 1), glm::vec2(0.5f, 0.5f)}) {
        const glm::vec3 v = shown(float(x) + c.x, float(y) + c.y);
        lo = glm::min(lo, v), hi = glm::max(hi, v);
      }
      const glm::vec3 got = image.beauty[i];
      for (int k = 0; k < 3; ++k)
        ASSERT_TRUE(got[k] >= lo[k] * 0.99f - 1e-3f && got[k] <= hi[k] * 1.01f + 1e-3f)
            << "pixel " << x << "," << y << " channel " << k << ": " << got[k] << ", q3map2 between " << lo[k] << " and " << hi[k];
      bright += std::max({got.x, got.y, got.z}) > 0.05f;
    }
  EXPECT_GT(bright, size_t(kWidth * kHeight / 5)) << "a dark picture proves little";
}

} // namespace
} // namespace bt
