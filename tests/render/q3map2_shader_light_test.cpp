// Quake 3 light from shaders as q3map2 computes it (lighting/q3map2_shader_light.h): surface
// lights, sky shaders' suns and sky lights, worldspawn _ambient. The levels are
// maps/q3map2/shader_light/maps/*.map with their shaders in ../scripts/q3map2_light.shader; each
// test writes q3map2's rules out again (shaders.c ParseShaderFile, light.c CreateSunLight /
// CreateSkyLights, light_bounce.c RadSubdivideDiffuseLight, light_ydnar.c
// LightContributionToSample) and compares every floor luxel and every camera pixel, in colour,
// with them at that point. Nothing casts a shadow on the floors, so the comparison is exact.
#include "importers/bsp/q3_shader_light.h"
#include "importers/import.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "renderer/camera.h"
#include "renderer/cpu/cpu_renderer.h"
#include "scene/color.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <functional>
#include <vector>

namespace bt {
namespace {

using LightAt = std::function<glm::vec3(const glm::vec3& p, const glm::vec3& n)>;

// LightContributionToSample, area light under -faster: photons / max(d, 16)² × cos on the
// receiver × cos on the emitting face, nothing beyond sqrt(photons) (the envelope we keep).
glm::vec3 areaLight(const glm::vec3& o, const glm::vec3& normal, float photons, const glm::vec3& color, const glm::vec3& p,
                    const glm::vec3& n) {
  const float dist = glm::length(o - p);
  if (dist >= std::sqrt(photons)) return glm::vec3(0.0f);
  const glm::vec3 dir = (o - p) / dist;
  const float cosReceiver = glm::dot(n, dir), cosEmitter = -glm::dot(normal, dir);
  if (cosReceiver <= 0.0f || cosEmitter <= 0.0f) return glm::vec3(0.0f);
  const float d = std::max(dist, 16.0f);
  return color * (photons / (d * d) * cosReceiver * cosEmitter);
}

// ... and the backsplash: a q3map2 point light (inverse square, Lambert, envelope sqrt(photons)).
glm::vec3 pointLight(const glm::vec3& o, float photons, const glm::vec3& color, const glm::vec3& p, const glm::vec3& n) {
  const float dist = glm::length(o - p);
  if (dist >= std::sqrt(photons)) return glm::vec3(0.0f);
  const float cosReceiver = glm::dot(n, (o - p) / dist);
  if (cosReceiver <= 0.0f) return glm::vec3(0.0f);
  const float d = std::max(dist, 16.0f);
  return color * (photons / (d * d) * cosReceiver);
}

// surface_light.map's two 64×64 panels, their faces at z = 128 looking down: q3map2 makes two
// triangles of each, every one smaller than 120 units, so two area lights at the panel's centre
// lifted 1 unit, each of surfacelight × 2048 × 0.25 photons, and their backsplash points.
glm::vec3 surfaceLightSum(const glm::vec3& p, const glm::vec3& n) {
  struct Panel {
    float x, value;
    glm::vec3 color;
    float splashFraction, splashDistance;
  };
  const Panel panels[] = {
      {-80.0f, 1200.0f, {1.0f, 0.5f, 0.25f}, 0.05f, 23.0f},                    // q3map_lightRGB; default backsplash
      {80.0f, 900.0f, {1.0f, 456.0f / 810.0f, 150.0f / 810.0f}, 0.10f, 32.0f}, // warm.png's texel sums, normalised
  };
  const glm::vec3 down(0, 0, -1);
  glm::vec3 sum(0.0f);
  for (const Panel& panel : panels) {
    const glm::vec3 origin(panel.x, 0.0f, 127.0f);
    const float photons = panel.value * 2048.0f * 0.25f;
    for (int triangle = 0; triangle < 2; ++triangle) {
      sum += areaLight(origin, down, photons, panel.color, p, n);
      sum += pointLight(origin + down * panel.splashDistance, photons * panel.splashFraction, panel.color, p, n);
    }
  }
  return sum;
}

glm::vec3 towardsSun(float degrees, float elevation) {
  const float a = degrees / 180.0f * 3.14159265f, e = elevation / 180.0f * 3.14159265f;
  return {std::cos(a) * std::cos(e), std::sin(a) * std::cos(e), std::sin(e)};
}

// sun.map: q3map_sun 1 0.8 0.6 150 30 30 (colour VectorNormalize'd, photons × cos; a low sun,
// where a degree of elevation moves the floor's light by 3 %), plus
// worldspawn _ambient 10 in _color 1 0.75 0.5 (not normalised), added before any light.
glm::vec3 sunSum(const glm::vec3& p, const glm::vec3& n) {
  (void)p;
  const glm::vec3 color = glm::normalize(glm::vec3(1.0f, 0.8f, 0.6f));
  const glm::vec3 ambient = 10.0f * glm::vec3(1.0f, 0.75f, 0.5f);
  return ambient + color * (150.0f * std::max(glm::dot(n, towardsSun(30.0f, 30.0f)), 0.0f));
}

// skylight.map: q3map_skylight 200 3 in q3map_lightRGB 0.5 0.75 1 (normalised: 0.5/1 ...).
// CreateSkyLights with 3 iterations: 2 rings of 8 suns at 15° and 45°, the second turned by
// half a step, and one straight up; 200 / 17 photons each.
glm::vec3 skyLightSum(const glm::vec3& p, const glm::vec3& n) {
  (void)p;
  const int iterations = 3, rings = iterations - 1, perRing = rings * 4;
  const float photons = 200.0f / float(rings * perRing + 1);
  float sum = 0.0f, azimuth = 0.0f, elevation = 90.0f / iterations * 0.5f;
  for (int i = 0; i < rings; ++i, elevation += 90.0f / iterations, azimuth += 360.0f / perRing / rings)
    for (int j = 0; j < perRing; ++j, azimuth += 360.0f / perRing)
      sum += photons * std::max(glm::dot(n, towardsSun(azimuth, elevation)), 0.0f);
  sum += photons * std::max(n.z, 0.0f);
  return glm::vec3(0.5f, 0.75f, 1.0f) * sum;
}

// What ioquake3 uploads for a luxel: 2 × the sum, its hue kept below 255 (q3map2_light_test.cpp).
glm::vec3 engineLuxel(glm::vec3 sum) {
  sum *= 2.0f;
  const float peak = std::max({sum.x, sum.y, sum.z});
  return peak > 255.0f ? sum * (255.0f / peak) : sum;
}

struct Level {
  Scene scene;
  RenderScene render;
};

std::unique_ptr<Level> load(const char* map) {
  auto level = std::make_unique<Level>();
  ImportOptions options;
  options.textures.textureDirs.push_back((test::mapsDir() / "q3map2" / "textures").string());
  level->scene = importScene((test::mapsDir() / "q3map2" / "shader_light" / "maps" / map).string(), options);
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, RenderSceneOptions{}, diagnostics);
  return level;
}

// Every luxel of the floor's top, in colour, within one byte of the formula at its sample point;
// more than `litShare` of them lit below the clamp.
void expectFloorLuxels(const Level& level, const LightAt& lightSum, double litShare = 0.5) {
  Lightmaps lightmaps = layoutLightmaps(level.render);
  const std::vector<GpuLuxelSample> samples = luxelSamples(level.render, lightmaps, 1);
  bakeLightmaps(level.render, lightmaps);
  ASSERT_EQ(samples.size(), lightmaps.luxels.size());
  size_t compared = 0, lit = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    const GpuLuxelSample& s = samples[i];
    const glm::vec3 n = level.scene.faces[s.face].plane.normal;
    const glm::vec3 p(s.position[0], s.position[1], s.position[2]);
    if (n.z < 0.99f || p.z > 8.0f || (s.flags & kLuxelSampleOccluded)) continue; // the floor's top
    const glm::vec3 expected = glm::floor(engineLuxel(lightSum(p, n)));
    const glm::vec3 got = unpackLuxel(lightmaps.luxels[i]);
    ASSERT_LE(glm::length(got - expected), 1.75f)
        << "luxel " << i << " at " << p.x << " " << p.y << " " << p.z << ": got " << got.x << " " << got.y << " " << got.z << ", q3map2 "
        << expected.x << " " << expected.y << " " << expected.z;
    ++compared;
    const float peak = std::max({expected.x, expected.y, expected.z});
    lit += peak > 20.0f && peak < 254.0f;
  }
  EXPECT_GT(compared, 500u);
  EXPECT_GT(double(lit), litShare * double(compared)) << "the luxels must be lit below the clamp, where a wrong scale shows";
}

// The CPU tracer's picture of the floor from `height` above it, every pixel in colour, the
// light at each pixel's point (--luxels off) shown as ioquake3 shows it.
void expectFloorPixels(const Level& level, const LightAt& lightSum, float height) {
  constexpr int kWidth = 64, kHeight = 48;
  CameraPose pose;
  pose.origin = {0.0f, 0.0f, height};
  pose.pitch = 90.0f; // looking down
  const Camera camera(pose, kWidth, kHeight);
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 1;
  settings.threads = 2;
  const RenderImage image = renderCpu(level.render, camera, settings);
  const glm::vec3 texture = linearToSrgb(image.albedo[0]); // flat_grey.png: one grey
  const auto shown = [&](float x, float y) {
    const Ray ray = camera.ray(x, y);
    const glm::vec3 p = ray.origin + ray.direction * (-ray.origin.z / ray.direction.z);
    return srgbToLinear(texture * engineLuxel(lightSum(p, glm::vec3(0, 0, 1))) / 127.5f);
  };
  size_t bright = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      ASSERT_GT(image.normal[i].z, 0.99f) << "pixel " << x << "," << y << " must see the floor's top";
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
  EXPECT_GT(bright, size_t(kWidth * kHeight / 2)) << "a dark picture proves little";
}

TEST(Q3map2ShaderLight, SurfaceLightLuxelsAreQ3map2sAreaLightsAndBacksplash) {
  const auto level = load("surface_light.map");
  expectFloorLuxels(*level, surfaceLightSum, 0.25); // the panels light the middle of the floor
}

TEST(Q3map2ShaderLight, SurfaceLightPixelsShowTheLightAsIoquake3Does) {
  const auto level = load("surface_light.map");
  expectFloorPixels(*level, surfaceLightSum, 100.0f); // below the panels
}

TEST(Q3map2ShaderLight, SunAndAmbientLuxelsAreQ3map2s) {
  const auto level = load("sun.map");
  expectFloorLuxels(*level, sunSum);
}

TEST(Q3map2ShaderLight, SunAndAmbientPixelsShowTheLightAsIoquake3Does) {
  const auto level = load("sun.map");
  expectFloorPixels(*level, sunSum, 200.0f);
}

TEST(Q3map2ShaderLight, SkyLightLuxelsAreQ3map2sSuns) {
  const auto level = load("skylight.map");
  expectFloorLuxels(*level, skyLightSum);
}

TEST(Q3map2ShaderLight, SkyLightPixelsShowTheLightAsIoquake3Does) {
  const auto level = load("skylight.map");
  expectFloorPixels(*level, skyLightSum, 200.0f);
}

// The light a picture shows at pixel i, as the luxel ioquake3 would draw there: 127.5 × shown /
// texture in sRGB (summed over the channels); negative where no lit texture is seen.
float shownLuxel(const RenderImage& image, const RenderScene& rs, size_t i) {
  if (image.face[i] == 0 || (rs.faceFlags[image.face[i] - 1] & (kFaceSky | kFaceLiquid))) return -1.0f;
  const glm::vec3 texture = linearToSrgb(image.albedo[i]), shown = linearToSrgb(image.beauty[i]);
  const float t = texture.x + texture.y + texture.z;
  return t < 0.3f ? -1.0f : 127.5f * (shown.x + shown.y + shown.z) / t;
}

// Unvanquished's plat23 and chasm (../shared/maps) have no light entities: their light is their
// shaders' (q3map_surfacelight panels and the sky shader's q3map_skylight). From each level's
// default camera, the light at each pixel (--luxels off) read back from the picture is that of a
// compiled Quake 3 level (stated range below), no pixel NaN; and without the sky light's suns
// the outside the camera sees goes darker.
TEST(Q3map2ShaderLight, Plat23AndChasmAreLitByTheirShaders) {
  BT_REQUIRE_SHARED(shared);
  struct Case {
    const char* map;
    size_t skySuns; // q3map_skylight 65 4: 3 rings of 12 and the zenith; 88 7: 6 rings of 24 and the zenith
  };
  for (const Case& c : {Case{"unvanquished-plat23/maps/plat23.map", 37}, Case{"unvanquished-chasm/maps/chasm.map", 145}}) {
    SCOPED_TRACE(c.map);
    const Scene scene = importScene((shared / "maps" / c.map).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diagnostics);
    size_t suns = 0, pieces = 0;
    for (const GpuLight& l : rs.lights) {
      suns += l.type == uint32_t(LightType::Sun);
      pieces += l.formula == uint32_t(LightFormula::Q3Area);
    }
    EXPECT_EQ(suns, c.skySuns) << "the sky shader's q3map_skylight";
    EXPECT_GT(pieces, 50u) << "the q3map_surfacelight panels";
    constexpr int kWidth = 80, kHeight = 45;
    const Camera camera(defaultCameraPose(scene), kWidth, kHeight);
    RenderSettings settings;
    settings.width = kWidth;
    settings.height = kHeight;
    settings.spp = 1;
    settings.threads = 2;
    const RenderImage image = renderCpu(rs, camera, settings);
    for (GpuLight& l : rs.lights)
      if (l.type == uint32_t(LightType::Sun)) l.value = 0.0f;
    const RenderImage withoutSky = renderCpu(rs, camera, settings);
    double sum = 0.0;
    size_t measured = 0, lit = 0, skyLit = 0;
    for (size_t i = 0; i < image.beauty.size(); ++i) {
      ASSERT_TRUE(std::isfinite(image.beauty[i].x + image.beauty[i].y + image.beauty[i].z)) << "pixel " << i;
      const float luxel = shownLuxel(image, rs, i);
      if (luxel < 0.0f) continue;
      sum += luxel;
      ++measured;
      lit += luxel > 8.0f;
      skyLit += luxel > shownLuxel(withoutSky, rs, i) + 2.0f;
    }
    ASSERT_GT(measured, image.beauty.size() / 2);
    // A compiled level's lightmaps: a mean of 12 (plat23) and 18 (chasm) a channel seen (no
    // bounce); half or ten times that is a wrong scale.
    const double perChannel = sum / double(measured) / 3.0;
    std::printf("%s: mean luxel %.1f a channel, %zu of %zu pixels lit, %zu lit by the sky\n", c.map, perChannel, lit, measured, skyLit);
    EXPECT_GT(perChannel, 8.0);
    EXPECT_LT(perChannel, 100.0);
    EXPECT_GT(lit, measured * 3 / 4) << "a black level";
    EXPECT_GT(skyLit, measured / 20) << "the sky light must light the outside the camera sees";
  }
}

// Cut finer (q3map_lightSubdivide 16), a panel becomes pieces no wider than 16 units on any
// axis, lying on it, whose photons add up to the panel's: surfacelight × area × 0.25.
TEST(Q3map2ShaderLight, SubdividedPanelKeepsItsPhotons) {
  auto level = load("surface_light.map");
  const auto m = level->scene.findMaterial("q3map2/ceiling_light");
  ASSERT_TRUE(m);
  level->scene.materials[*m].q3.subdivide = 16.0f;
  level->scene.materials[*level->scene.findMaterial("q3map2/image_light")].q3.surfaceLight = 0.0f;
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(level->scene, RenderSceneOptions{}, diagnostics);
  double photons = 0.0;
  size_t pieces = 0;
  for (const GpuLight& l : rs.lights) {
    if (l.formula != uint32_t(LightFormula::Q3Area)) continue;
    ++pieces;
    photons += double(l.value) * 128.0 * 128.0;
    EXPECT_NEAR(l.origin.z, 127.0f, 1e-3f);
    EXPECT_TRUE(l.origin.x > -112.0f && l.origin.x < -48.0f && std::abs(l.origin.y) < 32.0f) << l.origin.x << " " << l.origin.y;
  }
  EXPECT_GE(pieces, 16u); // each triangle's 2048 units² in pieces of at most 16 × 16 bounds
  EXPECT_NEAR(photons, 1200.0 * 64.0 * 64.0 * 0.25, 1.0);
}

// The keys ParseShaderFile reads for light, in one script; the colour of q3map_lightRGB normalised.
TEST(Q3map2ShaderLight, ParsesTheKeysQ3map2LightsWith) {
  Diagnostics diagnostics;
  const auto shaders = bsp::parseShaderLights(R"(// a comment
textures/a/lamp:q3map
{
	qer_editorImage textures/a/lamp_ed
	q3map_surfacelight 2500
	q3map_lightRGB 0.5 1 0.25
	q3map_lightSubdivide 64
	q3map_backsplash 0 0
	surfaceparm nolightmap
	{ map textures/a/lamp_stage }
}
textures/a/sky
{
	q3map_sunExt 1 1 1 140 45 60 2 16
	q3map_skylight 100 1
	skyparms env/a/sky - -
}
)",
                                              "a.shader", diagnostics);
  EXPECT_TRUE(diagnostics.empty());
  ASSERT_EQ(shaders.size(), 2u);
  const Q3ShaderLight& lamp = shaders.at("textures/a/lamp").light;
  EXPECT_FLOAT_EQ(lamp.surfaceLight, 2500.0f);
  EXPECT_TRUE(lamp.hasLightRGB);
  EXPECT_FLOAT_EQ(lamp.color[0], 0.5f);
  EXPECT_FLOAT_EQ(lamp.color[1], 1.0f);
  EXPECT_FLOAT_EQ(lamp.color[2], 0.25f);
  EXPECT_FLOAT_EQ(lamp.subdivide, 64.0f);
  EXPECT_FLOAT_EQ(lamp.backsplashFraction, 0.0f);
  EXPECT_TRUE(lamp.nolightmap);
  EXPECT_EQ(lamp.lightImage, ""); // the editor image came first: the stage's map is not taken
  EXPECT_EQ(shaders.at("textures/a/lamp").editorImage, "textures/a/lamp_ed");
  EXPECT_EQ(lamp.line, 2);
  const Q3ShaderLight& sky = shaders.at("textures/a/sky").light;
  ASSERT_EQ(sky.suns.size(), 1u);
  EXPECT_FLOAT_EQ(sky.suns[0].intensity, 140.0f);
  EXPECT_FLOAT_EQ(sky.suns[0].deviance, 2.0f);
  EXPECT_EQ(sky.suns[0].samples, 16);
  EXPECT_TRUE(sky.sky);
  EXPECT_EQ(sky.skyLightIterations, 2); // at least 2
  EXPECT_EQ(sky.lightImage, "env/a/sky_up");
}

// A light key without its number warns with the script and the line, and reads 0 as atof would.
TEST(Q3map2ShaderLight, MalformedNumberWarnsWithScriptAndLine) {
  Diagnostics diagnostics;
  const auto shaders =
      bsp::parseShaderLights("textures/a/lamp\n{\n\tq3map_surfacelight bright\n}\nnobrace\nx\n", "scripts/a.shader", diagnostics);
  ASSERT_EQ(diagnostics.size(), 2u);
  EXPECT_EQ(diagnostics[0].file, "scripts/a.shader");
  EXPECT_EQ(diagnostics[0].line, 3);
  EXPECT_NE(diagnostics[0].message.find("q3map_surfacelight"), std::string::npos) << diagnostics[0].message;
  EXPECT_EQ(diagnostics[1].line, 6); // "nobrace" is followed by "x", not "{"
  EXPECT_FLOAT_EQ(shaders.at("textures/a/lamp").light.surfaceLight, 0.0f);
}

} // namespace
} // namespace bt
