// Liquids as the engines draw them, on the maps of maps/liquids/ (generate.py there): the
// worldspawn alpha keys as QuakeSpasm reads them, and the CPU tracer's water, seen from above,
// against the engine's blend of the water over the pool without it; overlapping liquids as
// qbsp's CSG leaves them (lighting/liquid_csg.h). tests/gl holds the GL tracer to the pool's
// images, and to these of the overlapping liquids (gl_liquids_test.cpp).
#include "importers/import.h"
#include "lighting/liquids.h"
#include "lighting/render_scene.h"
#include "renderer/camera.h"
#include "renderer/cpu/cpu_renderer.h"
#include "scene/color.h"
#include "tests/render/liquid_ranges.h"
#include "tests/render/test_level.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

namespace bt {
namespace {

using test::engineBlend;
using test::expectNear;

constexpr int kWidth = 96;
constexpr int kHeight = 64;
const glm::vec3 kWaterSrgb = glm::vec3(40, 90, 200) / 255.0f; // generate.py's *water_blue

using test::Level;

std::unique_ptr<Level> load(const std::string& name) {
  return test::loadLevel(test::mapsDir() / "liquids" / name);
}

RenderImage render(const Level& level, LightingMode mode, int spp) {
  return test::renderFromDefaultCamera(level, mode, spp, kWidth, kHeight);
}

// Pixels whose own ray and its four neighbours' all meet the water: jitter stays on the water.
std::vector<size_t> waterPixels(const Level& level, const RenderImage& image) {
  auto water = [&](int x, int y) {
    const uint32_t f = image.face[size_t(y) * kWidth + x];
    return f != 0 && level.scene.faces[f - 1].texture == "*water_blue";
  };
  std::vector<size_t> pixels;
  for (int y = 1; y + 1 < kHeight; ++y)
    for (int x = 1; x + 1 < kWidth; ++x)
      if (water(x, y) && water(x - 1, y) && water(x + 1, y) && water(x, y - 1) && water(x, y + 1)) pixels.push_back(size_t(y) * kWidth + x);
  return pixels;
}

TEST(Liquids, WorldspawnAlphasAsQuakeSpasmReadsThem) {
  Scene scene;
  scene.entities.push_back(Entity{});
  scene.entities[0].keys = {
      {"classname", "worldspawn"}, {"_wateralpha", "0.4"}, {"lavaalpha", "0.7"}, {"_telealpha", "0"}, {"_slimealpha", "3"}};
  const LiquidAlphas alphas = liquidAlphas(scene);
  EXPECT_FLOAT_EQ(alphas.of(LiquidKind::Water), 0.4f);
  EXPECT_FLOAT_EQ(alphas.of(LiquidKind::Lava), 0.7f);         // its own key, without the underscore
  EXPECT_FLOAT_EQ(alphas.of(LiquidKind::Tele), 0.4f);         // 0: as water (GL_WaterAlphaForSurface)
  EXPECT_FLOAT_EQ(alphas.of(LiquidKind::Slime), 1.0f);        // clamped as the cvar is
  EXPECT_FLOAT_EQ(LiquidAlphas{}.of(LiquidKind::Tele), 1.0f); // no key: opaque, as the engine
  EXPECT_EQ(liquidKind("*LAVA1", nullptr), LiquidKind::Lava);
  EXPECT_EQ(liquidKind("*slime0", nullptr), LiquidKind::Slime);
  EXPECT_EQ(liquidKind("*teleport", nullptr), LiquidKind::Tele);
  EXPECT_EQ(liquidKind("*04water1", nullptr), LiquidKind::Water);
}

// pool.map's `_wateralpha 0.5` water over a yellow floor, unlit as Quake draws liquids: every
// pixel on the water is the engine's blend of the water's colour and pool_dry.map's pixel, in
// beauty and in the albedo AOV; opaque water (no key) is the water's colour alone.
TEST(Liquids, FaithfulWaterIsTheEnginesBlend) {
  const auto pool = load("pool.map"), dry = load("pool_dry.map"), opaque = load("pool_opaque.map");
  const RenderImage seen = render(*pool, LightingMode::Faithful, 1);
  const RenderImage behind = render(*dry, LightingMode::Faithful, 1);
  const RenderImage solid = render(*opaque, LightingMode::Faithful, 1);
  const std::vector<size_t> water = waterPixels(*pool, seen);
  ASSERT_GT(water.size(), size_t(kWidth * kHeight / 20)) << "the camera should look at the pool";
  for (size_t i : water) {
    const bool ok = expectNear(seen.beauty[i], engineBlend(0.5f, kWaterSrgb, behind.beauty[i]), 0.01f, i, "beauty") &&
        expectNear(seen.albedo[i], engineBlend(0.5f, kWaterSrgb, behind.albedo[i]), 0.01f, i, "albedo") &&
        expectNear(solid.beauty[i], srgbToLinear(kWaterSrgb), 0.01f, i, "opaque water");
    if (!ok) break; // one pixel tells
  }
}

RenderImage albedo(const Level& level) {
  return renderAovsCpu(level.render, Camera(defaultCameraPose(level.scene), kWidth, kHeight), kWidth, kHeight, 2);
}

// csg_water.map builds pool.map's water of three overlapping brushes (one inside the other two).
// qbsp merges liquids of one kind into one volume and compiles no face inside it, so through the
// translucent water every pixel shows what pool.map's single brush shows: a face inside the
// water would darken the floor behind it.
TEST(Liquids, OverlappingWaterIsOneVolumeAsQbspMergesIt) {
  const auto merged = load("csg_water.map"), single = load("pool.map");
  const RenderImage seen = albedo(*merged), want = albedo(*single);
  size_t onWater = 0;
  for (uint32_t f : seen.face) onWater += f && merged->scene.faces[f - 1].texture == "*water_blue";
  for (size_t i = 0; i < seen.albedo.size(); ++i) {
    const bool sameNormal = seen.normal[i] == want.normal[i] || glm::dot(seen.normal[i], want.normal[i]) > 0.9999f;
    EXPECT_TRUE(sameNormal) << "normal at pixel " << i;
    if (!expectNear(seen.albedo[i], want.albedo[i], 1e-3f, i, "albedo") || !sameNormal) break;
  }
  EXPECT_GT(onWater, size_t(kWidth * kHeight / 20)) << "the camera should look at the water";
}

// csg_lava.map: a water box inside translucent lava. qbsp keeps the faces of liquids of another
// kind inside a liquid and compiles each from both sides (q1_water_slime_zfighting in the
// oracle), so a ray through the lava that crosses the box meets the water twice, entering and
// leaving: lava over water over water over pool_dry.map's floor; beside the box, lava over the
// floor. Pixels whose ray grazes the box (within half a unit) are left out.
TEST(Liquids, WaterInsideLavaKeepsItsFacesFromBothSides) {
  const auto level = load("csg_lava.map"), dry = load("pool_dry.map");
  const RenderImage seen = albedo(*level), behind = albedo(*dry);
  const Camera camera(defaultCameraPose(level->scene), kWidth, kHeight);
  const glm::vec3 lavaSrgb = glm::vec3(230, 90, 20) / 255.0f; // generate.py's *lava_glow
  // Whether the camera ray meets the water box (generate.py's, grown by `margin`).
  const auto crosses = [&](const Ray& ray, float margin) {
    const glm::vec3 lo = glm::vec3(32, -32, -48) - margin, hi = glm::vec3(96, 32, -24) + margin;
    const glm::vec3 a = (lo - ray.origin) / ray.direction, b = (hi - ray.origin) / ray.direction;
    const glm::vec3 near = glm::min(a, b), far = glm::max(a, b);
    return std::max({near.x, near.y, near.z}) <= std::min({far.x, far.y, far.z});
  };
  size_t through = 0, beside = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      if (!seen.face[i] || level->scene.faces[seen.face[i] - 1].texture != "*lava_glow") continue;
      const Ray ray = camera.ray(float(x) + 0.5f, float(y) + 0.5f);
      const bool in = crosses(ray, -0.5f);
      if (in != crosses(ray, 0.5f)) continue;
      const glm::vec3 floor = behind.albedo[i];
      const glm::vec3 want = engineBlend(0.5f, lavaSrgb, in ? engineBlend(0.5f, kWaterSrgb, engineBlend(0.5f, kWaterSrgb, floor)) : floor);
      ++(in ? through : beside);
      if (!expectNear(seen.albedo[i], want, 0.01f, i, in ? "lava over the water box" : "lava beside the water box")) return;
    }
  EXPECT_GT(through, size_t(kWidth * kHeight / 50)) << "the camera should look through the lava at the water box";
  EXPECT_GT(beside, size_t(kWidth * kHeight / 50));
}

// Physical mode draws the water of pool.map (`wateralpha 0.5`) with probability
// srgbToLinear(0.5) = 0.214 (the share of its own colour the engine's gamma-space blend shows
// over darkness: physicalOpacityOfAlpha) and what lies behind it otherwise, tinted by the
// water's colour: the mean over the water is 0.214 x the opaque water's + 0.786 x tint x the dry
// pool's, within the noise of 32 samples and the light that now also crosses the surface (5 %).
TEST(Liquids, PhysicalWaterIsTheTintedBlendOnAverage) {
  const auto pool = load("pool.map"), dry = load("pool_dry.map"), opaque = load("pool_opaque.map");
  const uint32_t waterMaterial = *opaque->scene.findMaterial("*water_blue");
  EXPECT_FLOAT_EQ(opaque->render.materials[waterMaterial].physicalOpacity, kPhysicalWaterOpacity); // no key: physical default
  const double share = srgbToLinear(0.5f);
  EXPECT_NEAR(share, 0.214, 1e-3);
  EXPECT_FLOAT_EQ(pool->render.materials[waterMaterial].physicalOpacity, float(share)); // the level's alpha, linearised
  opaque->render.materials[waterMaterial].physicalOpacity = 1.0f;                       // the water's own shading
  const glm::dvec3 tint(liquidTint(pool->render.materials[waterMaterial]));
  EXPECT_NEAR(tint.z, 1.0, 1e-6);
  EXPECT_LT(tint.x, 0.1);
  const RenderImage seen = render(*pool, LightingMode::Physical, 32);
  const RenderImage behind = render(*dry, LightingMode::Physical, 32);
  const RenderImage solid = render(*opaque, LightingMode::Physical, 32);
  const std::vector<size_t> water = waterPixels(*pool, seen);
  ASSERT_FALSE(water.empty());
  glm::dvec3 got(0.0), want(0.0);
  for (size_t i : water) {
    got += glm::dvec3(seen.beauty[i]);
    want += share * glm::dvec3(solid.beauty[i]) + (1.0 - share) * tint * glm::dvec3(behind.beauty[i]);
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 0.05 * want[c]) << "channel " << c;
  EXPECT_GT(want.x + want.y + want.z, 0.0) << "a black pool proves nothing";
}

// pools.map in physical mode: each liquid's mean displayed colour lands in its documented range
// (lighting/README.md, "Liquids"): water blue and neither black nor washed out, slime green
// and not a flat neon, lava orange and bright. 16 samples, 2 bounces.
TEST(Liquids, PhysicalLiquidsLookLikeThemselves) {
  const auto pools = load("pools.map");
  test::expectLiquidsInRange(pools->scene, render(*pools, LightingMode::Physical, 16), "CPU");
}

// lava_dark.map has no light at all: only the lava's emission can light the wall beside it.
TEST(Liquids, LavaLightsAWallInTheDark) {
  const auto level = load("lava_dark.map");
  ASSERT_FALSE(level->render.emitters.empty()) << "lava should be an emitter";
  const RenderImage image = render(*level, LightingMode::Physical, 16);
  glm::dvec3 wall(0.0);
  size_t count = 0;
  for (size_t i = 0; i < image.face.size(); ++i)
    if (image.face[i] != 0 && level->scene.faces[image.face[i] - 1].texture == "poolwall") wall += glm::dvec3(image.beauty[i]), ++count;
  ASSERT_GT(count, size_t(50)) << "the wall should be in view";
  wall /= double(count);
  // Without the lava the wall is black (0): no other light.
  EXPECT_GT(wall.x, 0.005) << "the lava's light should reach the wall: mean " << wall.x << " " << wall.y << " " << wall.z;
  EXPECT_GT(wall.x, wall.z) << "in the lava's colour";
}

// ../shared's LibreQuake levels that have liquids: from 8 units above the centre of the largest
// liquid surface, looking down, a physical render has no NaN or infinite pixel and the liquid is not black (its mean displayed
// colour, auto-exposed, above 0.02 in some channel).
std::vector<std::string> libreQuakeMaps() {
  std::vector<std::string> maps;
  if (auto shared = test::sharedDir())
    for (const auto& entry : std::filesystem::recursive_directory_iterator(*shared / "maps/librequake/lq1/maps/src"))
      if (entry.path().extension() == ".map") maps.push_back(entry.path().string());
  std::sort(maps.begin(), maps.end());
  return maps;
}

// The largest drawn liquid face that looks up and that a ray straight down from 8 units above
// its centre sees (not one under a floor), with that point; nullopt when there is none.
std::optional<std::pair<uint32_t, glm::vec3>> visibleLiquidSurface(const RenderScene& rs) {
  std::vector<std::pair<double, uint32_t>> byArea;
  for (uint32_t f = 0; f < rs.faceFlags.size(); ++f) {
    const Face& face = rs.scene->faces[f];
    if (!(rs.faceFlags[f] & kFaceLiquid) || (rs.faceFlags[f] & kFaceHidden) || face.plane.normal.z < 0.9) continue;
    dvec3 area(0.0);
    for (size_t k = 1; k + 1 < face.winding.size(); ++k)
      area += glm::cross(face.winding[k] - face.winding[0], face.winding[k + 1] - face.winding[0]);
    byArea.emplace_back(-glm::length(area), f);
  }
  std::sort(byArea.begin(), byArea.end());
  for (const auto& [negArea, f] : byArea) {
    dvec3 centre(0.0);
    for (const dvec3& p : rs.scene->faces[f].winding) centre += p / double(rs.scene->faces[f].winding.size());
    const glm::vec3 eye(centre + dvec3(0.0, 0.0, 8.0));
    const SurfaceHit hit = traceVisible(rs, Ray{eye, 0.0f, glm::vec3(0.0f, 0.0f, -1.0f)});
    if (hit.found && hit.face == f) return std::make_pair(f, eye);
  }
  return std::nullopt;
}

class LibreQuakeLiquids : public testing::TestWithParam<std::string> {};

TEST_P(LibreQuakeLiquids, PhysicalLiquidsAreNeitherNanNorBlack) {
  BT_REQUIRE_SHARED(shared);
  ImportOptions options;
  for (const auto& dir : std::filesystem::directory_iterator(shared / "maps/librequake/texture-wads"))
    if (dir.is_directory()) options.textures.textureDirs.push_back(dir.path().string());
  Level level;
  level.scene = importScene(GetParam(), options);
  Diagnostics diagnostics;
  RenderSceneOptions sceneOptions;
  sceneOptions.bounceLights = false;
  level.render = buildRenderScene(level.scene, sceneOptions, diagnostics);
  const auto liquid = visibleLiquidSurface(level.render);
  if (!liquid) GTEST_SKIP() << "no liquid surface in view from above";
  const Face& face = level.scene.faces[liquid->first];
  CameraPose pose;
  pose.origin = liquid->second;
  pose.pitch = 90.0f; // straight down at it, close enough that it fills the view
  RenderSettings settings;
  settings.width = 48;
  settings.height = 32;
  settings.spp = 4;
  settings.threads = 2;
  settings.integrator.mode = LightingMode::Physical;
  settings.integrator.bounces = 2;
  const RenderImage image = renderCpu(level.render, Camera(pose, 48, 32), settings);
  for (const glm::vec3& c : image.beauty) ASSERT_TRUE(std::isfinite(c.x + c.y + c.z)) << "a NaN or infinite pixel";
  size_t count = 0;
  const glm::vec3 mean = test::displayedMean(level.scene, image, face.texture, count);
  ASSERT_GT(count, size_t(48 * 32 / 4)) << face.texture << " should fill the view (line " << face.line << ")";
  EXPECT_GT(std::max({mean.x, mean.y, mean.z}), 0.02f) << face.texture << " is black: " << mean.x << " " << mean.y << " " << mean.z;
  RecordProperty("liquid", face.texture);
}

INSTANTIATE_TEST_SUITE_P(Shared, LibreQuakeLiquids, testing::ValuesIn(libreQuakeMaps()), [](const auto& info) {
  std::string name = std::filesystem::path(info.param).stem().string();
  std::replace(name.begin(), name.end(), '-', '_'); // gtest names: letters, digits, _
  return name;
});
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(LibreQuakeLiquids);

} // namespace
} // namespace bt
