// The GL tracer on the liquid maps (maps/liquids/; tests/render/liquids_test.cpp holds the CPU
// tracer to the engine's blend): `_wateralpha 0.5` water over a yellow floor, in the albedo AOV
// and the beauty of both lighting modes, against the engine's rule and the CPU reference; and
// overlapping liquids as qbsp's CSG leaves them (lighting/liquid_csg.h), against the CPU's.
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "quake/bspfile_q2.h"
#include "renderer/gl/gl_lighting.h"
#include "scene/color.h"
#include "tests/gl/cpu_and_gl.h"
#include "tests/gl/test_scenes.h"
#include "tests/render/box_scene.h"
#include "tests/render/liquid_ranges.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>

namespace bt::gl {
namespace {

using test::engineBlend;
using test::expectNear;

constexpr int kWidth = 96;
constexpr int kHeight = 64;
const glm::vec3 kWaterSrgb = glm::vec3(40, 90, 200) / 255.0f; // generate.py's *water_blue

test::CpuAndGl renderLiquids(const std::string& name, LightingMode mode, int spp) {
  const Scene scene = importScene((test::mapsDir() / "liquids" / name).string(), ImportOptions{});
  return test::renderCpuAndGl(scene, mode, kWidth, kHeight, spp);
}

// The CPU's settings for one sample a pixel (seed 7): the same rays and random numbers as the GL
// beauty drawn with BeautySettings{.spp = 1, .seed = 7}.
RenderSettings oneSampleSettings(LightingMode mode) {
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 1;
  settings.seed = 7;
  settings.integrator.mode = mode;
  return settings;
}

// The parity tests' tolerance for a GL pixel against the CPU's: within 1 % (float differences
// in the lighting).
bool nearCpu(const glm::vec3& gpu, const glm::vec3& cpu) {
  return glm::length(gpu - cpu) <= 0.01f * glm::length(cpu) + 1e-3f;
}

// Pixels whose ray and its four neighbours' meet the same face as the centre's, a face that
// `dry` does not have at that pixel (the water): jitter stays on the water.
std::vector<size_t> waterPixels(const RenderImage& pool, const RenderImage& dry) {
  std::vector<size_t> pixels;
  for (int y = 1; y + 1 < kHeight; ++y)
    for (int x = 1; x + 1 < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      const uint32_t f = pool.face[i];
      if (f != 0 && f != dry.face[i] && pool.face[i - 1] == f && pool.face[i + 1] == f && pool.face[i - kWidth] == f &&
          pool.face[i + kWidth] == f)
        pixels.push_back(i);
    }
  return pixels;
}

// One sample a pixel, so that each pixel is one ray in both maps: the GL image's water is the
// engine's blend of the water and the GL image of the pool without it, in beauty and albedo,
// and both equal the CPU's.
TEST(GlLiquids, FaithfulWaterIsTheEnginesBlend) {
  const test::CpuAndGl pool = renderLiquids("pool.map", LightingMode::Faithful, 1);
  const test::CpuAndGl dry = renderLiquids("pool_dry.map", LightingMode::Faithful, 1);
  const std::vector<size_t> water = waterPixels(pool.gpu, dry.gpu);
  ASSERT_GT(water.size(), size_t(kWidth * kHeight / 20)) << "the camera should look at the pool";
  for (size_t i : water) {
    const bool ok = expectNear(pool.gpu.beauty[i], engineBlend(0.5f, kWaterSrgb, dry.gpu.beauty[i]), 0.01f, i, "GL beauty") &&
        expectNear(pool.gpu.albedo[i], engineBlend(0.5f, kWaterSrgb, dry.gpu.albedo[i]), 0.01f, i, "GL albedo") &&
        expectNear(pool.gpu.beauty[i], pool.cpu.beauty[i], 0.01f, i, "GL against CPU beauty") &&
        expectNear(pool.gpu.albedo[i], pool.cpu.albedo[i], 0.01f, i, "GL against CPU albedo");
    if (!ok) break; // one pixel tells
  }
}

// Physical mode's stochastic blend draws the same random numbers in both tracers: 97 % of the
// pixels within 1 % of the CPU's, the means within 3 % (gl_engine_rules_test's tolerance).
TEST(GlLiquids, PhysicalWaterAgreesWithTheCpu) {
  const test::CpuAndGl pool = renderLiquids("pool.map", LightingMode::Physical, 4);
  size_t close = 0;
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  for (size_t i = 0; i < pool.cpu.beauty.size(); ++i) {
    gpuSum += glm::dvec3(pool.gpu.beauty[i]);
    cpuSum += glm::dvec3(pool.cpu.beauty[i]);
    close += nearCpu(pool.gpu.beauty[i], pool.cpu.beauty[i]);
  }
  EXPECT_GE(close, pool.cpu.beauty.size() * 97 / 100) << close << " of " << pool.cpu.beauty.size() << " pixels agree";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], 0.03 * cpuSum[c] + 1e-6) << "channel " << c;
  EXPECT_GT(cpuSum.x + cpuSum.y + cpuSum.z, 0.0) << "a black image proves nothing";
}

// pools.map's water, slime and lava in physical mode: the GL image agrees with the CPU's, and its
// liquids land in the documented ranges (tests/render/liquid_ranges.h).
TEST(GlLiquids, PhysicalLiquidsLookLikeThemselves) {
  const Scene scene = importScene((test::mapsDir() / "liquids" / "pools.map").string(), ImportOptions{});
  const test::CpuAndGl pools = test::renderCpuAndGl(scene, LightingMode::Physical, kWidth, kHeight, 16);
  size_t close = 0;
  for (size_t i = 0; i < pools.cpu.beauty.size(); ++i) close += nearCpu(pools.gpu.beauty[i], pools.cpu.beauty[i]);
  EXPECT_GE(close, pools.cpu.beauty.size() * 97 / 100) << close << " of " << pools.cpu.beauty.size() << " pixels agree";
  test::expectLiquidsInRange(scene, pools.gpu, "GL");
}

// maps/q3blend/: Quake 3's additive, filter and alpha-blended panels before a wall
// (tests/render/q3_blends_test.cpp holds the CPU tracer to the engine's rules). One sample a
// pixel: every pixel of each panel is the engine's blend over the GL image of the wall without
// the panels, in beauty and albedo, and equals the CPU's.
TEST(GlLiquids, Quake3BlendsAreTheEnginesBlend) {
  const auto load = [](const char* name) { return importScene((test::mapsDir() / "q3blend/maps" / name).string(), ImportOptions{}); };
  const Scene scene = load("blends.map");
  const test::CpuAndGl seen = test::renderCpuAndGl(scene, LightingMode::Faithful, kWidth, kHeight, 1);
  const test::CpuAndGl wall = test::renderCpuAndGl(load("blends_behind.map"), LightingMode::Faithful, kWidth, kHeight, 1);
  const glm::vec3 add = glm::vec3(40, 30, 60) / 255.0f, filter = glm::vec3(180, 220, 120) / 255.0f, blend = glm::vec3(50, 200, 90) / 255.0f;
  const auto rule = [&](const std::string& texture, const glm::vec3& b) {
    if (texture == "blend/add") return srgbToLinear(add + linearToSrgb(b));
    if (texture == "blend/filter") return srgbToLinear(filter * linearToSrgb(b));
    return engineBlend(128.0f / 255.0f, blend, b);
  };
  std::map<std::string, size_t> compared;
  for (size_t i : waterPixels(seen.gpu, wall.gpu)) {
    const std::string& texture = scene.faces[seen.gpu.face[i] - 1].texture;
    const bool ok = expectNear(seen.gpu.beauty[i], rule(texture, wall.gpu.beauty[i]), 0.01f, i, texture.c_str()) &&
        expectNear(seen.gpu.albedo[i], rule(texture, wall.gpu.albedo[i]), 0.01f, i, texture.c_str()) &&
        expectNear(seen.gpu.beauty[i], seen.cpu.beauty[i], 0.01f, i, "GL against CPU beauty") &&
        expectNear(seen.gpu.albedo[i], seen.cpu.albedo[i], 0.01f, i, "GL against CPU albedo");
    if (!ok) break; // one pixel tells
    ++compared[texture];
  }
  for (const char* texture : {"blend/add", "blend/filter", "blend/blend"}) EXPECT_GT(compared[texture], size_t(100)) << texture;
}

// Physical mode: the additive panel's light and the filter's tint draw the same numbers as the CPU.
TEST(GlLiquids, Quake3BlendsPhysicalAgreeWithTheCpu) {
  const Scene scene = importScene((test::mapsDir() / "q3blend/maps/blends.map").string(), ImportOptions{});
  const test::CpuAndGl seen = test::renderCpuAndGl(scene, LightingMode::Physical, kWidth, kHeight, 4);
  size_t close = 0;
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  for (size_t i = 0; i < seen.cpu.beauty.size(); ++i) {
    gpuSum += glm::dvec3(seen.gpu.beauty[i]);
    cpuSum += glm::dvec3(seen.cpu.beauty[i]);
    close += nearCpu(seen.gpu.beauty[i], seen.cpu.beauty[i]);
  }
  EXPECT_GE(close, seen.cpu.beauty.size() * 97 / 100) << close << " of " << seen.cpu.beauty.size() << " pixels agree";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], 0.03 * cpuSum[c] + 1e-6) << "channel " << c;
}

// csg_water.map (three overlapping water brushes, merged: no face inside the water) and
// csg_lava.map (a water box inside lava: its faces kept, from both sides), whose CPU images
// tests/render/liquids_test.cpp holds to qbsp's rule, through the GL tracer's programs with the
// rule compiled in (BT_LIQUID_CSG).
struct CsgLevel {
  Scene scene;
  RenderScene render;
};
std::unique_ptr<CsgLevel> loadCsgLevel(const char* name) {
  auto level = std::make_unique<CsgLevel>();
  level->scene = importScene((test::mapsDir() / "liquids" / name).string(), ImportOptions{});
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, {}, diagnostics);
  return level;
}
constexpr const char* kCsgMaps[] = {"csg_water.map", "csg_lava.map"};

// Every pixel of the AOVs, one ray through each pixel centre: the same face (the face qbsp
// keeps in place of a removed one included), the same normal (facing the ray where the water
// is seen from inside the lava) and the albedo of the same blend of liquids.
TEST(GlLiquids, OverlappingLiquidsAovsAreTheCpusEveryPixel) {
  for (const char* name : kCsgMaps) {
    SCOPED_TRACE(name);
    const auto level = loadCsgLevel(name);
    ASSERT_FALSE(level->render.liquidCsg.empty()) << "the liquids should overlap";
    const CameraPose pose = defaultCameraPose(level->scene);
    const RenderImage cpu = renderAovsCpu(level->render, Camera(pose, kWidth, kHeight), kWidth, kHeight, 2);
    GlTracer tracer(test::sharedGlContext(), level->scene, level->render.tracer, test::textureModeUnderTest(), lightingFor(level->render));
    ASSERT_TRUE(tracer.faithfulFeatures().liquidCsg);
    const AovImages gpu = tracer.renderAovs(cameraFrom(pose, kWidth, kHeight), kWidth, kHeight);
    size_t liquid = 0;
    for (size_t i = 0; i < cpu.albedo.size(); ++i) {
      liquid += cpu.face[i] != 0 && (level->render.faceFlags[cpu.face[i] - 1] & kFaceLiquid) != 0;
      EXPECT_EQ(gpu.face[i], cpu.face[i]) << "face at pixel " << i;
      EXPECT_EQ(gpu.normal[i], cpu.normal[i]) << "normal at pixel " << i;
      if (gpu.face[i] != cpu.face[i] || gpu.normal[i] != cpu.normal[i] ||
          !expectNear(glm::vec3(gpu.albedo[i]), cpu.albedo[i], 1e-3f, i, "GL against CPU albedo"))
        break; // one pixel tells
    }
    EXPECT_GT(liquid, size_t(kWidth * kHeight / 20)) << "the camera should look at the liquids";
  }
}

// An exact tie on an edge: camera rays through the top edge of the second water brush of
// csg_water.map, where its side inside the first brush (a face qbsp removes) meets its top. The
// tracers give a tie to the later face of the brush, so with the top moved before that side
// the tie goes to the removed side, and the face qbsp keeps at that point is drawn in its place
// (LiquidCsg::keptFaceAt): the later of the two coplanar tops, this brush's. The default views of
// the liquid maps never meet such a tie, so without this view the GL tracer's edge search
// (visible.glsl csgKeptCandidate) would go untested.
TEST(GlLiquids, AnEdgeTieOnARemovedFaceDrawsTheFaceQbspKeeps) {
  CsgLevel level;
  level.scene = importScene((test::mapsDir() / "liquids" / "csg_water.map").string(), ImportOptions{});
  const auto find = [&](glm::dvec3 normal, double dist) {
    for (uint32_t f = 0; f < level.scene.faces.size(); ++f) {
      const Face& face = level.scene.faces[f];
      if (face.texture == "*water_blue" && glm::length(face.plane.normal - normal) < 1e-9 && std::abs(face.plane.dist - dist) < 1e-9)
        return f;
    }
    ADD_FAILURE() << "no such water face";
    return uint32_t(0);
  };
  const uint32_t side = find({-1, 0, 0}, -32), top = [&] {
    for (uint32_t f = level.scene.brushes[level.scene.faces[side].brush].firstFace;; ++f)
      if (level.scene.faces[f].plane.normal.z > 0.5) return f;
  }();
  ASSERT_LT(side, top);
  std::swap(level.scene.faces[side], level.scene.faces[top]); // the top now comes first
  Diagnostics diagnostics;
  level.render = buildRenderScene(level.scene, {}, diagnostics);
  CameraPose pose; // 45 degrees down along +x: the centre ray meets the edge at (32, 0, -8)
  pose.origin = glm::vec3(16, 0, 8);
  pose.pitch = 45.0f;
  constexpr int kSize = 33; // an odd size, so that a pixel's ray is the camera's axis
  const RenderImage cpu = renderAovsCpu(level.render, Camera(pose, kSize, kSize), kSize, kSize, 2);
  const size_t centre = kSize / 2 * kSize + kSize / 2;
  ASSERT_EQ(cpu.face[centre], side + 1) << "the CPU draws the kept top (now at the side's index) at the edge";
  GlTracer tracer(test::sharedGlContext(), level.scene, level.render.tracer, test::textureModeUnderTest(), lightingFor(level.render));
  const AovImages gpu = tracer.renderAovs(cameraFrom(pose, kSize, kSize), kSize, kSize);
  for (size_t i = 0; i < cpu.face.size(); ++i) {
    EXPECT_EQ(gpu.face[i], cpu.face[i]) << "face at pixel " << i;
    EXPECT_EQ(gpu.normal[i], cpu.normal[i]) << "normal at pixel " << i;
  }
}

// The beauty of both lighting modes in both forms of the path tracer, one sample a pixel (the
// same rays and random numbers as the CPU's): within 1 % of the CPU's at 99 % of the pixels (the
// parity tests' tolerance for float differences in the lighting) and at every pixel on a liquid.
TEST(GlLiquids, OverlappingLiquidsBeautyIsTheCpusInBothModesAndForms) {
  for (const char* name : kCsgMaps) {
    const auto level = loadCsgLevel(name);
    const CameraPose pose = defaultCameraPose(level->scene);
    GlTracer tracer(test::sharedGlContext(), level->scene, level->render.tracer, test::textureModeUnderTest(), lightingFor(level->render));
    const RenderImage faces = renderAovsCpu(level->render, Camera(pose, kWidth, kHeight), kWidth, kHeight, 2);
    for (const LightingMode mode : {LightingMode::Faithful, LightingMode::Physical}) {
      RenderSettings settings = oneSampleSettings(mode);
      settings.integrator.bounces = 2;
      const RenderImage cpu = renderCpu(level->render, Camera(pose, kWidth, kHeight), settings);
      for (const PathTracerForm form : {PathTracerForm::Megakernel, PathTracerForm::Wavefront}) {
        SCOPED_TRACE(std::string(name) + (mode == LightingMode::Physical ? " physical" : " faithful") +
                     (form == PathTracerForm::Wavefront ? " wavefront" : " megakernel"));
        const BeautySettings beauty{.width = kWidth,
                                    .height = kHeight,
                                    .spp = 1,
                                    .seed = 7,
                                    .physical = mode == LightingMode::Physical,
                                    .bounces = 2,
                                    .clampIndirect = settings.integrator.clampIndirect,
                                    .form = form};
        const BeautyImage gpu = tracer.renderBeauty(cameraFrom(pose, kWidth, kHeight), beauty);
        ASSERT_EQ(gpu.wavefrontSamples, form == PathTracerForm::Wavefront ? 1 : 0);
        size_t close = 0, liquidFar = 0;
        for (size_t i = 0; i < cpu.beauty.size(); ++i) {
          const bool near = nearCpu(gpu.beauty[i], cpu.beauty[i]);
          close += near;
          liquidFar += !near && faces.face[i] != 0 && (level->render.faceFlags[faces.face[i] - 1] & kFaceLiquid) != 0;
        }
        EXPECT_GE(close, cpu.beauty.size() * 99 / 100) << close << " of " << cpu.beauty.size() << " pixels agree";
        EXPECT_EQ(liquidFar, size_t(0)) << "pixels on a liquid off the CPU's";
      }
    }
  }
}

// A Quake 2 water drawn as a wall shadows from inside (RenderScene::blocksFromInside): from a
// camera inside the water, the floor under it is black and the floor beyond its side, by the
// light, lit; the faithful beauty in both forms of the path tracer, whose programs have the rule
// (BT_BLOCKS_FROM_INSIDE), is the CPU's, one sample a pixel.
TEST(GlLiquids, AQuake2WaterDrawnAsAWallShadowsFromInsideAsOnTheCpu) {
  const Scene scene = test::waterBesideALight("quake2", "e1u1/water", SurfaceAttributes{quake::q2::CONTENTS_WATER, 0, 0.0});
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  GlTracer tracer(test::sharedGlContext(), scene, rs.tracer, test::textureModeUnderTest(), lightingFor(rs));
  ASSERT_TRUE(tracer.faithfulFeatures().blocksFromInside);
  CameraPose pose; // straight down from inside the water, 40 units from its side: x -60 .. 140 in view
  pose.origin = glm::vec3(40, 0, 100);
  pose.pitch = 90.0f;
  const RenderSettings settings = oneSampleSettings(LightingMode::Faithful);
  const RenderImage cpu = renderCpu(rs, Camera(pose, kWidth, kHeight), settings);
  size_t lit = 0, black = 0;
  for (const glm::vec3& c : cpu.beauty) {
    lit += c.x > 1e-3f; // linear: the floor beside the water shows 0.06 .. 0.2 on screen
    black += c == glm::vec3(0.0f);
  }
  ASSERT_GT(lit, cpu.beauty.size() / 10) << "the floor beyond the water's side is lit";
  ASSERT_GT(black, cpu.beauty.size() / 2) << "the floor under the water is black";
  for (const PathTracerForm form : {PathTracerForm::Megakernel, PathTracerForm::Wavefront}) {
    SCOPED_TRACE(form == PathTracerForm::Wavefront ? "wavefront" : "megakernel");
    const BeautySettings beauty{.width = kWidth, .height = kHeight, .spp = 1, .seed = 7, .physical = false, .form = form};
    const BeautyImage gpu = tracer.renderBeauty(cameraFrom(pose, kWidth, kHeight), beauty);
    size_t close = 0;
    for (size_t i = 0; i < cpu.beauty.size(); ++i) close += nearCpu(gpu.beauty[i], cpu.beauty[i]);
    EXPECT_GE(close, cpu.beauty.size() * 99 / 100) << close << " of " << cpu.beauty.size() << " pixels agree";
  }
}

// Quake 2's glass as ref_gl draws it (lighting/game_rules.h engineGlassAlpha): its texture unlit,
// blended at 0.33 or 0.66 (per face: light_q2_translucent_shadow gives one texture both flags)
// over what lies behind. From two cameras that look through both panes (compiled_view_test.cpp's),
// the faithful beauty in both forms of the path tracer, whose programs have the glass
// (BT_QUAKE2_GLASS), is the CPU's, one sample a pixel: every pixel on glass within 0.1 %, and 99 %
// of all within the parity tests' 1 %.
TEST(GlLiquids, Quake2GlassIsTheCpusUnlitBlendInBothForms) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene =
      importScene((shared / "oracle/lit-games/maps_ericw-tools_testmaps_light_q2_translucent_shadow.bsp").string(), ImportOptions{});
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  ASSERT_FALSE(rs.glassAlpha.empty());
  GlTracer tracer(test::sharedGlContext(), scene, rs.tracer, test::textureModeUnderTest(), lightingFor(rs));
  ASSERT_TRUE(tracer.faithfulFeatures().glass);
  std::map<float, size_t> glassPixels; // by alpha
  for (const float yaw : {0.0f, 180.0f}) {
    const CameraPose pose{.origin = {yaw == 0.0f ? -200.0f : 150.0f, -500.0f, 80.0f}, .pitch = 10.0f, .yaw = yaw};
    const RenderSettings settings = oneSampleSettings(LightingMode::Faithful);
    const RenderImage cpu = renderCpu(rs, Camera(pose, kWidth, kHeight), settings);
    const RenderImage faces = renderAovsCpu(rs, Camera(pose, kWidth, kHeight), kWidth, kHeight, 2);
    for (const PathTracerForm form : {PathTracerForm::Megakernel, PathTracerForm::Wavefront}) {
      SCOPED_TRACE(fmt::format("yaw {} {}", yaw, form == PathTracerForm::Wavefront ? "wavefront" : "megakernel"));
      const BeautySettings beauty{.width = kWidth, .height = kHeight, .spp = 1, .seed = 7, .physical = false, .form = form};
      const BeautyImage gpu = tracer.renderBeauty(cameraFrom(pose, kWidth, kHeight), beauty);
      ASSERT_EQ(gpu.wavefrontSamples, form == PathTracerForm::Wavefront ? 1 : 0);
      size_t close = 0, glassFar = 0;
      for (size_t i = 0; i < cpu.beauty.size(); ++i) {
        const bool near = nearCpu(gpu.beauty[i], cpu.beauty[i]);
        close += near;
        const float alpha = faces.face[i] != 0 ? glassAlpha(rs, faces.face[i] - 1) : 1.0f;
        if (alpha == 1.0f) continue;
        // On the glass, nothing is lit here: only the colour conversions' rounding may differ
        // (llvmpipe: 9.4e-5 of the CPU's at worst), far below alpha 0.33 -> 0.34's 1e-2.
        glassFar += glm::length(gpu.beauty[i] - cpu.beauty[i]) > 1e-3f * glm::length(cpu.beauty[i]) + 1e-4f;
        if (form == PathTracerForm::Megakernel) ++glassPixels[alpha];
      }
      EXPECT_GE(close, cpu.beauty.size() * 99 / 100) << close << " of " << cpu.beauty.size() << " pixels agree";
      EXPECT_EQ(glassFar, size_t(0)) << "pixels on the glass off the CPU's";
    }
  }
  // Both panes in view, each over many pixels (the centre ray on them, as the CPU's AOVs trace).
  EXPECT_GT(glassPixels[0.33f], size_t(200));
  EXPECT_GT(glassPixels[0.66f], size_t(200));
}

} // namespace
} // namespace bt::gl
