// The compiler's penumbra suns: glibc's rand() from its default seed, and the directions
// ericw-tools' SetupSun makes of it, in the order its suns draw them.
#include "lighting/faithful.h"
#include "lighting/lights.h"
#include "lighting/penumbra_suns.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>

namespace bt {
namespace {

// What `int main() { for (...) printf("%d\n", rand()); }` prints with glibc, without srand().
TEST(GlibcRand, DefaultSeedGivesGlibcsSequence) {
  GlibcRand rand;
  const int32_t expected[] = {1804289383, 846930886, 1681692777, 1714636915, 1957747793,
                              424238335,  719885386, 1649760492, 596516649,  1189641421};
  for (int32_t e : expected) EXPECT_EQ(rand.next(), e);
}

TEST(GlibcRand, ExplicitSeedOneIsTheDefault) {
  GlibcRand a(1), b;
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.next(), b.next());
}

// Azimuth and elevation of a direction, as SetupSun measures them.
glm::dvec2 angles(const glm::vec3& d) {
  return {std::atan2(double(d.y), double(d.x)), std::atan2(double(d.z), std::sqrt(double(d.x) * d.x + double(d.y) * d.y))};
}

double jitter(int32_t draw, double degrees) {
  return (double(draw) / 2147483647.0 * 2.0 - 1.0) * glm::radians(degrees);
}

TEST(PenumbraSuns, TheWorldSunTakesItsOwnDirectionThenGlibcsDraws) {
  test::BoxSceneBuilder b;
  b.worldKey("_sunlight", "250");
  b.worldKey("_sun_mangle", "30 -60 0");
  b.worldKey("_sunlight_penumbra", "4");
  Diagnostics diags;
  const SceneLights lights = collectLights(b.build(), {}, diags);
  ASSERT_EQ(lights.lights.size(), 1u);
  const GpuLight& sun = lights.lights[0];
  ASSERT_TRUE(sun.flags & kLightFlagSunTable);
  ASSERT_EQ(lights.sunTable.size(), size_t(faithful::kSunSamples));
  EXPECT_EQ(lights.sunTable[sun.sunTable], sun.direction);
  // The first jittered sun: azimuth + the first draw, elevation + the second.
  const glm::dvec2 base = angles(sun.direction), first = angles(lights.sunTable[sun.sunTable + 1]);
  EXPECT_NEAR(first.x - base.x, jitter(1804289383, 4.0), 1e-6);
  EXPECT_NEAR(first.y - base.y, jitter(846930886, 4.0), 1e-6);
  for (const glm::vec3& d : lights.sunTable) {
    const glm::dvec2 a = angles(d);
    EXPECT_LE(std::abs(a.x - base.x), glm::radians(4.0) + 1e-6);
    EXPECT_LE(std::abs(a.y - base.y), glm::radians(4.0) + 1e-6);
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
  }
}

// entities.cc SetupLights: JitterEntities draws first (three numbers per extra copy of a
// `_deviance` light, a `_sun 1` light's too: 16 copies by default), then SetupSuns: the `_sun 1`
// lights in entity order, then their jittered copies (each a sun of its own), then the world's.
TEST(PenumbraSuns, SunsDrawInTheCompilersOrder) {
  test::BoxSceneBuilder b;
  b.worldKey("_sunlight", "250");
  b.worldKey("_sunlight_penumbra", "2");
  b.entity({{"classname", "light"}, {"origin", "0 0 32"}, {"_deviance", "4"}, {"_samples", "3"}});
  b.entity({{"classname", "light"}, {"origin", "0 0 48"}, {"_sun", "1"}, {"mangle", "0 -45 0"}, {"_deviance", "3"}});
  Diagnostics diags;
  const SceneLights lights = collectLights(b.build(), {}, diags);
  ASSERT_EQ(lights.lights.size(), 3u);
  const GpuLight& world = lights.lights[0];
  const GpuLight& entitySun = lights.lights[2];
  ASSERT_EQ(entitySun.type, uint32_t(LightType::Sun));
  EXPECT_EQ(entitySun.sunTable, 0u);
  EXPECT_EQ(world.sunTable, uint32_t(faithful::kSunSamples));

  GlibcRand rand;
  for (int i = 0; i < 3 * 2 + 3 * 15; ++i) rand.next(); // the extra copies: the light's 2, the sun's 15
  const auto entityTable = penumbraDirections(rand, entitySun.direction, 3.0, faithful::kSunSamples);
  for (int i = 0; i < 15 * 2 * (faithful::kSunSamples - 1); ++i) rand.next(); // the sun's copies' suns
  const auto worldTable = penumbraDirections(rand, world.direction, 2.0, faithful::kSunSamples);
  for (int k = 0; k < faithful::kSunSamples; ++k) {
    EXPECT_NEAR(glm::length(lights.sunTable[size_t(k)] - entityTable[size_t(k)]), 0.0f, 1e-6f) << k;
    EXPECT_NEAR(glm::length(lights.sunTable[size_t(faithful::kSunSamples + k)] - worldTable[size_t(k)]), 0.0f, 1e-6f) << k;
  }
}

} // namespace
} // namespace bt
