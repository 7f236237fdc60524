// Faithful `_surface` lights and `_deviance`/`_samples`: where ericw-tools `light` puts the
// point lights it makes from a template, what they carry, and what a jittered light adds up to.
// Expected values are worked out by hand from the compiler's rules (surface_lights.h).
#include "lighting/faithful.h"
#include "renderer/cpu/integrator.h"
#include "lighting/surface_lights.h"
#include "scene/winding.h"
#include "tests/render/box_scene.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace bt {
namespace {

std::vector<dvec3> square(double lo, double hi, double z = 0.0) {
  return {{lo, lo, z}, {hi, lo, z}, {hi, hi, z}, {lo, hi, z}};
}

TEST(SurfaceLightGrid, CutsAtMultiplesOf128NearestTheMiddle) {
  // 0..256: the middle 128 is on the grid; each half's middle rounds to 0/128/256, which
  // would cut off nothing, so four 128-unit pieces remain.
  const auto pieces = subdivideOnGrid(square(0, 256), 128.0);
  ASSERT_EQ(pieces.size(), 4u);
  for (const auto& p : pieces) EXPECT_NEAR(area(p), 128.0 * 128.0, 1e-6);
  // 0..100: the grid line nearest the middle (0) would leave a sliver under 8 units: no cut.
  EXPECT_EQ(subdivideOnGrid(square(0, 100), 128.0).size(), 1u);
  // 100..300: cut at 256 (nearest 200) only; 100..256 has its middle at 178 -> 128, cut again.
  EXPECT_EQ(subdivideOnGrid(square(100, 300), 128.0).size(), 9u);
}

// A lava box standing on a floor, its template far away.
test::BoxSceneBuilder lavaScene(std::vector<std::pair<std::string, std::string>> templateKeys) {
  test::BoxSceneBuilder b;
  b.material("floor", 255, 255, 255);
  b.material("lava", 255, 64, 0);
  b.box({-1024, -1024, -16}, {1024, 1024, 0}, "floor");
  b.box({128, 128, 0}, {384, 384, 32}, "lava");
  templateKeys.insert(templateKeys.begin(), {{"classname", "light"}, {"origin", "0 0 500"}, {"_surface", "lava"}});
  b.entity(std::move(templateKeys));
  return b;
}

std::vector<GpuLight> lightsAtHeight(const RenderScene& rs, float z) {
  std::vector<GpuLight> out;
  for (const GpuLight& l : rs.lights)
    if (std::abs(l.origin.z - z) < 1e-3f) out.push_back(l);
  return out;
}

TEST(SurfaceLightQ1, FullCopiesOnEveryPieceTwoUnitsOffTheFace) {
  const Scene scene = lavaScene({{"light", "150"}, {"delay", "2"}}).build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  // Top face 128..384 (256 texels): qbsp cuts at 128 + 224 = 352; the grid then cuts 128..352
  // at 256 and leaves 352..384 whole: 3 x 3 pieces, lights at z = 32 + 2.
  const std::vector<GpuLight> top = lightsAtHeight(rs, 34.0f);
  ASSERT_EQ(top.size(), 9u);
  for (const GpuLight& l : top) {
    EXPECT_FLOAT_EQ(l.value, 150.0f); // each copy keeps the template's value
    EXPECT_EQ(l.formula, uint32_t(LightFormula::Inverse2));
    EXPECT_TRUE(l.flags & kLightFlagFromSurface);
    EXPECT_GT(l.origin.x, 128.0f);
    EXPECT_LT(l.origin.x, 384.0f);
  }
  // Texel t runs along -y on a floor (Quake's projection), so qbsp's 32-unit strip is at the
  // high x and the low y end: the piece 352..384 x 128..160 has its light at its centre.
  EXPECT_TRUE(std::any_of(top.begin(), top.end(), [](const GpuLight& l) {
    return std::abs(l.origin.x - 368.0f) < 1e-3f && std::abs(l.origin.y - 144.0f) < 1e-3f;
  }));
  // The bottom face lies on the floor: its lights would sit inside the floor brush.
  EXPECT_TRUE(lightsAtHeight(rs, -2.0f).empty());
  // 4 sides of 3 pieces each (the 32-unit height is not cut) + the top.
  EXPECT_EQ(rs.lights.size(), 9u + 12u);
}

// Two bars cross a lava surface and end halfway along it. qbsp's faces come from its BSP
// tree, which splits first along the bars' ends (the plane that two brushes face and that cuts
// only the lava: SelectSplitSide's best), so the lava beyond the bars is one face and only the
// part between the bars is cut into strips, one face each. Then qbsp's T-junction fix puts the
// strips' corners (x 48, 64, 128, 144 on y 96) on the edge of the face beyond and cuts it into
// fans (lighting/qbsp_tjunc.h), which `light` cuts on its 128 grid: x 0..128 so gets four points
// where it had two (testsurfacelight's lava: 107 of the compiler's 111 points stand where its do
// with this cut; session 24 had 94 with this cut, 85 without). Those corners lie symmetrically,
// so the two mirrored fans tie and where the face starts decides: where qbsp's portal on the
// lava's plane starts (session 25, starting from our own winding, had the mirror: four points
// at x 128..192).
TEST(SurfaceLightQ1, BarsAcrossTheSurfaceSplitItAlongTheirEndsFirst) {
  test::BoxSceneBuilder b;
  b.material("lava", 255, 64, 0);
  b.material("bar", 128, 128, 128);
  b.box({0, 0, 0}, {192, 192, 64}, "lava"); // narrower than 240 texels: no qbsp subdivision
  b.box({48, -16, 48}, {64, 96, 96}, "bar");
  b.box({128, -16, 48}, {144, 96, 96}, "bar");
  b.entity({{"classname", "light"}, {"origin", "0 0 500"}, {"_surface", "lava"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  std::vector<glm::vec2> top;
  for (const GpuLight& l : lightsAtHeight(rs, 66.0f)) top.push_back({l.origin.x, l.origin.y});
  std::sort(top.begin(), top.end(), [](glm::vec2 a, glm::vec2 c) { return a.y != c.y ? a.y < c.y : a.x < c.x; });
  // Between the bars: the strips 0..48, 64..128 and 144..192, each too small for the grid to
  // cut. Beyond them: 0..192 x 96..192, its fans cut by the 128 grid at x = 128 and y = 128.
  const std::vector<glm::vec2> expected = {
      {24, 48},   {96, 48},           {168, 48}, {27.022f, 110.933f}, {160, 112}, {90.413f, 112.762f}, {14.222f, 149.333f},
      {160, 160}, {73.956f, 162.133f}};
  ASSERT_EQ(top.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(top[i].x, expected[i].x, 1e-3f) << i;
    EXPECT_NEAR(top[i].y, expected[i].y, 1e-3f) << i;
  }
}

// A lava pool that runs out through the wall of a sealed room: qbsp fills the void outside and
// makes no face that looks into it, so only the part inside gets lights. A level that leaks
// (an entity in the void) is not filled, and then every part keeps its lights.
TEST(SurfaceLightQ1, NoLightsOnFacesThatLookIntoTheVoid) {
  for (bool leak : {false, true}) {
    test::BoxSceneBuilder b;
    b.material("wall", 128, 128, 128);
    b.material("lava", 255, 64, 0);
    b.room({-256, -256, 0}, {256, 256, 256}, "wall");
    b.box({0, 0, 0}, {400, 64, 32}, "lava"); // through the wall at x = 256..272
    b.entity({{"classname", "info_player_start"}, {"origin", "-128 0 64"}});
    b.entity({{"classname", "light"}, {"origin", leak ? "1000 0 100" : "0 0 200"}, {"_surface", "lava"}});
    const Scene scene = b.build();
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene, {}, diags);
    std::vector<float> topX;
    for (const GpuLight& l : lightsAtHeight(rs, 34.0f)) topX.push_back(l.origin.x);
    std::sort(topX.begin(), topX.end());
    // Inside, 0..256: qbsp cuts at 224 (240 texels), the grid at 128. Outside, 272..400: the grid
    // cuts at 384.
    const std::vector<float> expected = leak ? std::vector<float>{64, 176, 240, 328, 392} : std::vector<float>{64, 176, 240};
    ASSERT_EQ(topX.size(), expected.size()) << (leak ? "leaking" : "sealed");
    for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(topX[i], expected[i], 1e-3f);
  }
}

TEST(SurfaceLightQ1, SpotlightAlongTheFaceNormalAndOffset) {
  const Scene scene = lavaScene({{"_surface_spotlight", "1"}, {"_surface_offset", "8"}, {"angle", "60"}}).build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const std::vector<GpuLight> top = lightsAtHeight(rs, 40.0f);
  ASSERT_EQ(top.size(), 9u);
  EXPECT_EQ(top[0].direction, glm::vec3(0, 0, 1));
  EXPECT_NEAR(top[0].cosOuter, std::cos(glm::radians(30.0f)), 1e-6f);
}

TEST(SurfaceLightRadiosity, OnePointPerFaceCarryingValueTimesArea) {
  // "_surface_radiosity " with a trailing space, as q1_surflight_minlight spells it.
  const Scene scene = lavaScene({{"light", "100"}, {"_color", "255 127.5 0"}, {"_surface_radiosity ", "1"}}).build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const std::vector<GpuLight> top = lightsAtHeight(rs, 33.0f); // lifted 1 unit
  ASSERT_EQ(top.size(), 1u);
  const GpuLight& l = top[0];
  EXPECT_EQ(l.formula, uint32_t(LightFormula::SurfaceRadiosity));
  EXPECT_FLOAT_EQ(l.value, 100.0f * 256.0f * 256.0f);
  EXPECT_NEAR(l.color.y, 0.5f, 1e-6f);
  EXPECT_EQ(l.origin, glm::vec3(256, 256, 33));
  EXPECT_EQ(rs.lights.size(), 5u); // top + 4 sides; the bottom is inside the floor

  // value / d^2 with half-Lambert on both ends: 100 units straight above, both cosines 1.
  const glm::vec3 up(0, 0, 1);
  EXPECT_FLOAT_EQ(faithful::pointLightValue(l, -up, -up, 100.0f), l.value / 10000.0f);
  // Grazing on the emitter's side: half.
  EXPECT_FLOAT_EQ(faithful::pointLightValue(l, -glm::vec3(1, 0, 0), glm::vec3(-1, 0, 0), 100.0f), 0.5f * l.value / 10000.0f);
  // Closer than 16 units counts as 16; behind the emitting face nothing.
  EXPECT_FLOAT_EQ(faithful::pointLightValue(l, -up, -up, 4.0f), l.value / 256.0f);
  EXPECT_FLOAT_EQ(faithful::pointLightValue(l, up, up, 100.0f), 0.0f);

  // Its faces are lit at least at the template's value, in its colour.
  const uint32_t lava = *scene.findMaterial("lava");
  const glm::vec3 floor = faithful::surfaceFaceMinlight(rs.surfaceLights[lava]);
  EXPECT_FLOAT_EQ(floor.x, 100.0f);
  EXPECT_FLOAT_EQ(floor.y, 50.0f);
  EXPECT_EQ(faithful::surfaceFaceMinlight(rs.surfaceLights[*scene.findMaterial("floor")]), glm::vec3(0.0f));
}

TEST(SurfaceLightQ1, PhysicalModeLightsTheFacesAsAreaEmittersOnly) {
  // The spread points are faithful-only: physical mode gives the same image without them.
  const Scene scene = lavaScene({{"light", "100"}}).build();
  Diagnostics diags;
  RenderScene rs = buildRenderScene(scene, {}, diags);
  ASSERT_FALSE(rs.emitters.empty());
  ASSERT_FALSE(rs.lights.empty());
  const Ray ray{{0.0f, 0.0f, 64.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 1e9f};
  std::vector<glm::vec3> with;
  for (int i = 0; i < 64; ++i) {
    Rng rng = pixelRng(1, 1, uint32_t(i), 3);
    with.push_back(radiance(rs, {LightingMode::Physical, 1}, ray, rng));
  }
  rs.lights.clear();
  glm::vec3 total(0.0f);
  for (int i = 0; i < 64; ++i) {
    Rng rng = pixelRng(1, 1, uint32_t(i), 3);
    const glm::vec3 without = radiance(rs, {LightingMode::Physical, 1}, ray, rng);
    EXPECT_EQ(with[size_t(i)], without) << i;
    total += without;
  }
  EXPECT_GT(total.x, 0.0f); // and the lava does light the floor, as an area light
}

// A lava floor 2 x halfSide units square with a `_surface` light over it: the template makes
// kMaxSurfaceLights points, no more, and says so.
void expectLavaFloorStopsAtTheCap(double halfSide) {
  test::BoxSceneBuilder b;
  b.material("lava", 255, 64, 0);
  b.box({-halfSide, -halfSide, -16}, {halfSide, halfSide, 0}, "lava");
  b.entity({{"classname", "light"}, {"origin", "0 0 500"}, {"_surface", "lava"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  EXPECT_EQ(rs.lights.size(), kMaxSurfaceLights);
  ASSERT_FALSE(diags.empty());
  EXPECT_NE(diags.back().message.find("surface light points"), std::string::npos) << diags.back().message;
}

TEST(SurfaceLightQ1, AHugeTemplateFaceStopsAtTheCapWithAWarning) {
  expectLavaFloorStopsAtTheCap(20000); // 40000 units square on the 128 grid would be ~100k point lights
}

// Found by tests/fuzz/fuzz_bsp: a corrupt level's hull cell reaching out a million units gave a
// template face that the 128-unit grid cut into 67 million pieces before the cap on lights was
// ever checked: gigabytes. Cutting now stops at the cap.
TEST(SurfaceLightQ1, AFaceAMillionUnitsWideStopsAtTheCapWithAWarning) {
  expectLavaFloorStopsAtTheCap(524288);
}

TEST(SurfaceLightGrid, StopsCuttingAtTheCapLeavingTheRestWhole) {
  // 2^20 units square on the 128 grid: 67 million pieces uncapped.
  const auto pieces = subdivideOnGrid(square(-524288, 524288), 128.0);
  EXPECT_GT(pieces.size(), kMaxSurfaceLights);
  EXPECT_LT(pieces.size(), kMaxSurfaceLights + 64);
  double total = 0.0;
  for (const auto& p : pieces) total += area(p);
  EXPECT_NEAR(total, 1048576.0 * 1048576.0, 1e-6 * 1048576.0 * 1048576.0); // still the whole square
}

struct JitterCase {
  const char* delay;
  const char* samples;
  float deviance, faithfulScale;
};

TEST(Deviance, SamplesDefaultTo16AndOnlyLinearLightsKeepTheFullValuePerCopy) {
  const JitterCase cases[] = {
      {"0", "", 8.0f, 16.0f},                         // linear: 16 copies of the whole value
      {"0", "4", 8.0f, 4.0f}, {"2", "", 8.0f, 1.0f},  // inverse square: the value is split among the copies
      {"1", "4", 8.0f, 1.0f}, {"0", "1", 0.0f, 1.0f}, // one sample: no jitter at all
  };
  for (const JitterCase& c : cases) {
    test::BoxSceneBuilder b;
    std::vector<std::pair<std::string, std::string>> keys = {
        {"classname", "light"}, {"origin", "0 0 64"}, {"delay", c.delay}, {"_deviance", "8"}};
    if (*c.samples) keys.emplace_back("_samples", c.samples);
    b.entity(keys);
    Diagnostics diags;
    const SceneLights lights = collectLights(b.build(), {}, diags);
    ASSERT_EQ(lights.lights.size(), 1u);
    EXPECT_FLOAT_EQ(lights.lights[0].deviance, c.deviance) << c.delay << " " << c.samples;
    EXPECT_FLOAT_EQ(lights.lights[0].faithfulScale, c.faithfulScale) << c.delay << " " << c.samples;
    EXPECT_FLOAT_EQ(lights.lights[0].value, 300.0f);
  }
}

TEST(Deviance, FaithfulLightIsTheSumOfTheJitteredCopies) {
  // A linear light 64 units above a floor, jittered 16 units with 4 samples: the compiler adds
  // 4 copies of 300 - distance at points uniform in the cube. The expectation, by midpoint
  // quadrature over the cube, against the tracer's Monte Carlo mean.
  test::BoxSceneBuilder b;
  b.material("white", 255, 255, 255);
  b.box({-2048, -2048, -16}, {2048, 2048, 0}, "white");
  b.entity({{"classname", "light"}, {"origin", "0 0 64"}, {"_deviance", "16"}, {"_samples", "4"}});
  const Scene scene = b.build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const glm::vec3 p(40, 0, 0), n(0, 0, 1);

  GpuLight single;
  single.formula = uint32_t(LightFormula::Linear);
  double expected = 0.0;
  constexpr int kSteps = 24;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j)
      for (int k = 0; k < kSteps; ++k) {
        const glm::vec3 u((i + 0.5f) / kSteps, (j + 0.5f) / kSteps, (k + 0.5f) / kSteps);
        const glm::vec3 d = glm::vec3(0, 0, 64) + 16.0f * (2.0f * u - 1.0f) - p;
        expected += faithful::pointLightValue(single, n, glm::normalize(d), glm::length(d));
      }
  expected = 4.0 * expected / (kSteps * kSteps * kSteps);

  const int samples = 4000;
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    Rng rng = pixelRng(7, 3, uint32_t(i), 2);
    sum += faithfulLight(rs, {.p = p, .n = n, .lights = LightSet::All}, rng).x;
  }
  EXPECT_NEAR(sum / samples, expected, 0.01 * expected);
  // Far from what one unjittered copy gives: the copies add up.
  EXPECT_GT(expected, 3.0 * (300.0 - glm::length(glm::vec3(0, 0, 64) - p)));
}

} // namespace
} // namespace bt
