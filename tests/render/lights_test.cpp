// Light entity parsing and the faithful formulas, against values worked out by hand from
// ericw-tools' definitions.
#include "lighting/faithful.h"
#include "lighting/lights.h"
#include "lighting/physical_light.h"
#include "quake/bspfile_q2.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

namespace bt {
namespace {

GpuLight pointLight(LightFormula formula, float value = 300.0f) {
  GpuLight l;
  l.formula = uint32_t(formula);
  l.value = value;
  return l;
}

TEST(FaithfulFormula, DistanceFalloffPerDelay) {
  // 300 units of light, 100 units away, wait 1.
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Linear), 100.0f), 200.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Linear), 400.0f), 0.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Inverse), 100.0f), 300.0f * 128.0f / 100.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Inverse2), 100.0f), 300.0f * 128.0f * 128.0f / 10000.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Infinite), 5000.0f), 300.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::LocalMin), 5000.0f), 300.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Inverse2A), 100.0f), 300.0f * 128.0f * 128.0f / (228.0f * 228.0f));
  // Inverse formulas give the light's own value at 128 units.
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Inverse2), 128.0f), 300.0f);
}

TEST(FaithfulFormula, WaitScalesDistanceAndFalloffOverridesLinear) {
  GpuLight l = pointLight(LightFormula::Linear);
  l.atten = 2.0f;
  EXPECT_FLOAT_EQ(faithful::distanceValue(l, 100.0f), 100.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(l, 100.0f, 0.5f), 200.0f); // worldspawn _dist 0.5
  l.atten = 1.0f;
  l.falloff = 400.0f;
  EXPECT_FLOAT_EQ(faithful::distanceValue(l, 100.0f), 225.0f);
  EXPECT_FLOAT_EQ(faithful::distanceValue(l, 500.0f), 0.0f);
  // Negative lights fall off towards zero.
  EXPECT_FLOAT_EQ(faithful::distanceValue(pointLight(LightFormula::Linear, -300.0f), 100.0f), -200.0f);
}

TEST(FaithfulFormula, AngleScaleAndBackFaces) {
  const GpuLight l = pointLight(LightFormula::Infinite);
  const glm::vec3 up(0, 0, 1);
  EXPECT_FLOAT_EQ(faithful::pointLightValue(l, up, up, 10.0f), 300.0f);
  // Grazing light at the default anglescale 0.5 gives half, not zero.
  EXPECT_NEAR(faithful::pointLightValue(l, up, glm::vec3(1, 0, 0), 10.0f), 150.0f, 1e-3f);
  const glm::vec3 at60 = glm::normalize(glm::vec3(std::sqrt(3.0f), 0.0f, 1.0f));
  EXPECT_NEAR(faithful::pointLightValue(l, up, at60, 10.0f), 300.0f * 0.75f, 1e-3f);
  EXPECT_FLOAT_EQ(faithful::pointLightValue(l, up, -up, 10.0f), 0.0f);
  GpuLight bleed = l;
  bleed.flags |= kLightFlagBleed;
  EXPECT_FLOAT_EQ(faithful::pointLightValue(bleed, up, -up, 10.0f), 300.0f);
}

TEST(FaithfulFormula, SpotlightCone) {
  GpuLight l = pointLight(LightFormula::Infinite);
  l.direction = {0, 0, -1};
  l.cosOuter = std::cos(glm::radians(20.0f)); // angle 40
  l.cosInner = std::cos(glm::radians(10.0f)); // _softangle 20
  const glm::vec3 up(0, 0, 1);
  EXPECT_FLOAT_EQ(faithful::spotTerm(l, up), 1.0f);
  const glm::vec3 at15 = glm::normalize(glm::vec3(std::sin(glm::radians(15.0f)), 0.0f, std::cos(glm::radians(15.0f))));
  const float expected = (std::cos(glm::radians(15.0f)) - l.cosOuter) / (l.cosInner - l.cosOuter);
  EXPECT_NEAR(faithful::spotTerm(l, at15), expected, 1e-5f);
  EXPECT_GT(expected, 0.1f);
  EXPECT_LT(expected, 0.9f);
  const glm::vec3 at30 = glm::normalize(glm::vec3(std::sin(glm::radians(30.0f)), 0.0f, std::cos(glm::radians(30.0f))));
  EXPECT_FLOAT_EQ(faithful::spotTerm(l, at30), 0.0f);
}

// Physical mode's hue skips the pow where a channel's share is exactly 1 (the brightest channel,
// every channel of a white light): the decode of every channel must stay srgbToLinear's float.
TEST(PhysicalColour, HueIsTheSrgbDecodeOfEachChannelsShare) {
  const glm::vec3 colours[] = {{1.0f, 1.0f, 1.0f},    {300.0f, 300.0f, 300.0f}, {1.0f, 0.5f, 0.25f},      {255.0f, 127.0f, 0.0f},
                               {0.2f, 1.0f, 0.2f},    {0.3f, 0.3f, 0.9f},       {1e-30f, 1e-30f, 5e-31f}, {7.0f, 7.0f, 6.9999995f},
                               {0.04f, 1.0f, 0.041f}, {0.0f, 0.0f, 0.0f}};
  for (const glm::vec3& c : colours) {
    const float m = std::max({c.x, c.y, c.z});
    const glm::vec3 h = physical::hue(c);
    for (int i = 0; i < 3; ++i) {
      const float expected = m > 0.0f ? srgbToLinear(c[i] / m) : 0.0f;
      EXPECT_EQ(std::bit_cast<uint32_t>(h[i]), std::bit_cast<uint32_t>(expected))
          << "colour " << c.x << " " << c.y << " " << c.z << " channel " << i << ": " << h[i] << " against " << expected;
    }
    if (m > 0.0f) EXPECT_EQ(std::max({h.x, h.y, h.z}), 1.0f); // the brightest channel decodes to exactly 1
  }
}

TEST(FaithfulFormula, LightmapRangeAndClamp) {
  EXPECT_FLOAT_EQ(faithful::lightmapValue(300.0f), 150.0f);
  EXPECT_FLOAT_EQ(faithful::lightmapValue(1000.0f), 255.0f);
  EXPECT_FLOAT_EQ(faithful::lightmapValue(-10.0f), 0.0f);
  EXPECT_FLOAT_EQ(faithful::lightmapValue(300.0f, 1.0f), 255.0f);
}

TEST(LightEntities, KeysAndDefaults) {
  test::BoxSceneBuilder b;
  b.entity({{"classname", "light"}, {"origin", "1 2 3"}});
  b.entity({{"classname", "light_fluoro"},
            {"origin", "0 0 0"},
            {"light", "200"},
            {"_color", "255 128 0"},
            {"delay", "2"},
            {"wait", "0.5"},
            {"_anglescale", "1"},
            {"_falloff", "300"}});
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"_color", "0.5 1 0.25"}});
  b.scene().entities.back().line = 42;
  Diagnostics diags;
  const SceneLights lights = collectLights(b.build(), {}, diags);
  ASSERT_EQ(lights.lights.size(), 3u);
  const GpuLight& a = lights.lights[0];
  EXPECT_EQ(a.origin, glm::vec3(1, 2, 3));
  EXPECT_FLOAT_EQ(a.value, 300.0f);
  EXPECT_EQ(a.formula, uint32_t(LightFormula::Linear));
  EXPECT_FLOAT_EQ(a.anglescale, 0.5f);
  EXPECT_LT(a.cosOuter, -1.0f); // not a spotlight
  const GpuLight& c = lights.lights[1];
  EXPECT_FLOAT_EQ(c.value, 200.0f);
  EXPECT_NEAR(c.color.y, 128.0f / 255.0f, 1e-6f);
  EXPECT_EQ(c.formula, uint32_t(LightFormula::Inverse2));
  EXPECT_FLOAT_EQ(c.atten, 0.5f);
  EXPECT_FLOAT_EQ(c.anglescale, 1.0f);
  EXPECT_FLOAT_EQ(c.falloff, 300.0f);
  EXPECT_EQ(lights.lights[2].color, glm::vec3(0.5f, 1.0f, 0.25f)); // 0..1 colours stay as they are
  EXPECT_TRUE(diags.empty());
}

TEST(LightEntities, BadValuesAreReportedWithTheEntityLine) {
  test::BoxSceneBuilder b;
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"delay", "9"}});
  b.scene().entities.back().line = 17;
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"light", "bright"}});
  b.entity({{"classname", "light"}, {"origin", "0 0"}});
  Diagnostics diags;
  const SceneLights lights = collectLights(b.build(), {}, diags);
  // The invalid delay drops its light (ericw-tools lights nothing with it); the bad value falls back to 300.
  ASSERT_EQ(lights.lights.size(), 1u);
  EXPECT_EQ(lights.lights[0].formula, uint32_t(LightFormula::Linear));
  EXPECT_FLOAT_EQ(lights.lights[0].value, 300.0f);
  ASSERT_EQ(diags.size(), 4u); // bad delay, bad light, bad origin, origin missing -> ignored
  EXPECT_EQ(diags[0].line, 17);
  bool sawDelay = false;
  for (const Diagnostic& d : diags) sawDelay |= d.message.find("invalid delay 9") != std::string::npos;
  EXPECT_TRUE(sawDelay);
}

// A key the compiler reads and faithful mode does not model is named in one warning line, at
// the first entity that uses it (lighting/lights.cpp warnPhong).
TEST(LightEntities, PhongShadingIsNamedOnceAsNotModelled) {
  test::BoxSceneBuilder b;
  b.entity({{"classname", "func_detail"}, {"_phong", "0"}});
  b.entity({{"classname", "func_detail"}, {"_phong", "1"}});
  b.scene().entities.back().line = 23;
  b.entity({{"classname", "func_wall"}, {"_phong_angle", "45"}});
  Diagnostics diags;
  collectLights(b.build(), {}, diags);
  ASSERT_EQ(diags.size(), 1u);
  EXPECT_EQ(diags[0].severity, Severity::Warning);
  EXPECT_EQ(diags[0].line, 23);
  EXPECT_NE(diags[0].message.find("func_detail: _phong: phong shading is not modelled; the faces of the 2 brush entities"),
            std::string::npos)
      << diags[0].message;
}

TEST(LightEntities, SpotlightsFromTargetAndMangle) {
  test::BoxSceneBuilder b;
  b.entity({{"classname", "light"}, {"origin", "0 0 100"}, {"target", "t1"}, {"angle", "60"}, {"_softangle", "30"}});
  b.entity({{"classname", "info_null"}, {"origin", "0 0 0"}, {"targetname", "t1"}});
  b.entity({{"classname", "light_spot"}, {"origin", "0 0 0"}, {"mangle", "90 0 0"}});
  Diagnostics diags;
  const SceneLights lights = collectLights(b.build(), {}, diags);
  ASSERT_EQ(lights.lights.size(), 2u);
  EXPECT_NEAR(glm::distance(lights.lights[0].direction, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
  EXPECT_NEAR(lights.lights[0].cosOuter, std::cos(glm::radians(30.0f)), 1e-6f);
  EXPECT_NEAR(lights.lights[0].cosInner, std::cos(glm::radians(15.0f)), 1e-6f);
  EXPECT_NEAR(glm::distance(lights.lights[1].direction, glm::vec3(0, 1, 0)), 0.0f, 1e-6f); // yaw 90
  EXPECT_NEAR(lights.lights[1].cosOuter, std::cos(glm::radians(20.0f)), 1e-6f);            // default 40
}

TEST(LightEntities, StylesStartOffAndSurfaceTemplates) {
  test::BoxSceneBuilder b;
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"targetname", "sw"}, {"spawnflags", "1"}});
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"style", "5"}});
  b.entity({{"classname", "light"}, {"origin", "0 0 0"}, {"_surface", "lamp1"}, {"light", "150"}});
  Diagnostics diags;
  SceneLights lights = collectLights(b.build(), {}, diags);
  ASSERT_EQ(lights.lights.size(), 1u); // the start-off light is dark
  EXPECT_EQ(lightStyle(lights.lights[0]), 5u);
  ASSERT_EQ(lights.surfaceTemplates.size(), 1u);
  EXPECT_EQ(lights.surfaceTemplates[0].texture, "lamp1");
  EXPECT_FLOAT_EQ(lights.surfaceTemplates[0].light.value, 150.0f);

  lights = collectLights(b.build(), {.includeStartOff = true}, diags);
  EXPECT_EQ(lights.lights.size(), 2u);
  lights = collectLights(b.build(), {.styleZeroOnly = true}, diags);
  EXPECT_EQ(lights.lights.size(), 0u);
}

TEST(LightEntities, WorldspawnSunDomesAndMinlight) {
  test::BoxSceneBuilder b;
  b.worldKey("_sunlight", "250");
  b.worldKey("_sun_mangle", "0 -60 0");
  b.worldKey("_sunlight_color", "255 255 128");
  b.worldKey("_sunlight_penumbra", "4");
  b.worldKey("_sunlight2", "80");
  b.worldKey("_sunlight3", "20");
  b.worldKey("light", "10");
  b.worldKey("_minlight_color", "255 0 0");
  b.worldKey("_range", "1");
  b.worldKey("_anglescale", "0.8");
  b.worldKey("_bounce", "1");
  Diagnostics diags;
  const SceneLights lights = collectLights(b.build(), {}, diags);
  ASSERT_EQ(lights.lights.size(), 3u);
  const GpuLight& sun = lights.lights[0];
  EXPECT_EQ(sun.type, uint32_t(LightType::Sun));
  EXPECT_FLOAT_EQ(sun.value, 250.0f);
  EXPECT_NEAR(sun.direction.z, -std::sin(glm::radians(60.0f)), 1e-6f);
  EXPECT_NEAR(sun.direction.x, std::cos(glm::radians(60.0f)), 1e-6f);
  EXPECT_NEAR(sun.deviance, glm::radians(4.0f), 1e-6f);
  EXPECT_FLOAT_EQ(sun.anglescale, 0.8f);
  EXPECT_EQ(lights.lights[1].type, uint32_t(LightType::Dome));
  EXPECT_FLOAT_EQ(lights.lights[1].direction.z, 1.0f);
  EXPECT_EQ(lights.lights[2].type, uint32_t(LightType::Dome));
  EXPECT_FLOAT_EQ(lights.lights[2].direction.z, -1.0f);
  EXPECT_EQ(lights.world.minlight, glm::vec3(10.0f, 0.0f, 0.0f));
  EXPECT_FLOAT_EQ(lights.world.range, 1.0f);
  EXPECT_EQ(lights.world.bounces, 1);
  EXPECT_TRUE(diags.empty());
}

// ericw-tools' Quake 2 target: its defaults before the level's keys, `_minlight` in 128ths,
// and a face with SURF_LIGHT and a value as a radiosity surface light of that value.
TEST(LightEntities, Quake2GameTargetAndSurfaceLights) {
  test::BoxSceneBuilder b;
  b.worldKey("_minlight", "0.5");
  b.worldKey("_bouncescale", "2");
  b.box({0, 0, 0}, {64, 64, 64}, b.material("e1u1/baselt_5", 200, 200, 160));
  Scene scene = b.build();
  scene.format = "ibsp38";
  ASSERT_GE(scene.faces.size(), 3u);
  scene.faces[0].surface = SurfaceAttributes{0, quake::q2::SURF_LIGHT, 300.0};
  scene.faces[1].surface = SurfaceAttributes{0, quake::q2::SURF_LIGHT | quake::q2::SURF_SKY, 100.0};
  scene.faces[2].surface = SurfaceAttributes{0, quake::q2::SURF_LIGHT, 0.0}; // no value: no light
  Diagnostics diags;
  const SceneLights lights = collectLights(scene, {}, diags);
  EXPECT_FLOAT_EQ(lights.world.range, 1.0f);
  EXPECT_EQ(lights.world.bounces, 1);
  EXPECT_TRUE(lights.world.bouncestyled);
  EXPECT_FLOAT_EQ(lights.world.bouncescale, 2.0f); // the level's key wins
  EXPECT_FLOAT_EQ(lights.world.bouncecolorscale, 0.5f);
  EXPECT_FLOAT_EQ(lights.world.surflightScale, 0.65f);
  EXPECT_TRUE(lights.world.surflightRadiosity);
  EXPECT_FLOAT_EQ(lights.world.overbrightOne, 255.0f);
  EXPECT_EQ(lights.world.minlight, glm::vec3(64.0f));
  ASSERT_EQ(lights.surfaceTemplates.size(), 1u);
  const SurfaceTemplate& t = lights.surfaceTemplates[0];
  EXPECT_EQ(t.texture, scene.faces[0].texture);
  EXPECT_EQ(t.q2Value, 300.0);
  EXPECT_TRUE(t.radiosity);
  EXPECT_FLOAT_EQ(t.light.value, 300.0f);
  ASSERT_EQ(diags.size(), 1u); // the sky emitter is named, not silently dropped
  EXPECT_NE(diags[0].message.find("SURF_LIGHT"), std::string::npos);

  // The same level as Quake's: none of it.
  scene.format = "quake2";
  scene.game = "quake";
  const SceneLights quake = collectLights(scene, {}, diags);
  EXPECT_FLOAT_EQ(quake.world.range, 0.5f);
  EXPECT_EQ(quake.world.bounces, 0);
  EXPECT_EQ(quake.world.minlight, glm::vec3(0.5f));
  EXPECT_FLOAT_EQ(quake.world.overbrightOne, 128.0f);
  EXPECT_TRUE(quake.surfaceTemplates.empty());
}

} // namespace
} // namespace bt
