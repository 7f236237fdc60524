// The GL backend against the CPU reference (renderer/cpu) on real levels: the same scene,
// lights and camera through renderCpu and renderWithGl.
//   AOVs: equal up to float tolerance (a few silhouette pixels may see the other face).
//   Beauty: both tracers draw the same random numbers per pixel and sample (sampling.h's PCG
//   streams, and physical mode's Sobol sequences), so most pixels agree to float precision; paths that float rounding sends another
//   way (a shadow ray grazing an edge) make the rest differ. Stated tolerance, at equal spp:
//   the image means within 1 % (faithful) / 3 % (physical), and at least 97 % of pixels
//   within 1 % (+ 1e-3 absolute) of the CPU's value.
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/cpu/integrator.h"
#include "lighting/light_grid.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_level.h"
#include "renderer/gl/gl_render.h"
#include "importers/import.h"
#include "tests/gl/test_scenes.h"
#include "tests/render/box_scene.h"
#include "tests/render/normal_map_room.h"
#include "tests/test_data.h"

#include "lighting/compiled_lightmaps.h"
#include "lighting/lightmap_bake.h"
#include "renderer/view_lightmaps.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>

namespace bt::gl {
namespace {

constexpr int kWidth = 80;
constexpr int kHeight = 48;

struct Level {
  Scene scene;
  RenderScene render;
  CameraPose pose;
};

// A LibreQuake map with its textures (loose PNG folders, see shared/maps/librequake/PROVENANCE.txt).
std::unique_ptr<Level> loadLibreQuake(const std::filesystem::path& shared, const std::string& map) {
  ImportOptions options;
  for (const auto& dir : std::filesystem::directory_iterator(shared / "maps/librequake/texture-wads"))
    if (dir.is_directory()) options.textures.textureDirs.push_back(dir.path().string());
  auto level = std::make_unique<Level>();
  level->scene = importScene((shared / "maps/librequake/lq1/maps/src" / map).string(), options);
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, {}, diagnostics);
  level->pose = defaultCameraPose(level->scene);
  return level;
}

RenderImage renderBoth(const RenderScene& rs, const CameraPose& pose, const RenderSettings& settings, RenderImage& cpu,
                       GlRenderParts parts = GlRenderParts::BeautyAndAovs) {
  cpu = renderCpu(rs, Camera(pose, settings.width, settings.height), settings);
  std::string whyNot;
  auto gl = renderWithGl(rs, pose, settings, test::textureModeUnderTest(), {}, whyNot, parts);
  if (!gl) ADD_FAILURE() << "no GL context: " << whyNot;
  return gl ? gl->image : RenderImage{};
}

// The AOVs of both tracers for one level and camera: faces, depths and normals equal up to
// float rounding, albedo up to the bilinear filter's sensitivity to it. At least `minHits` of the
// pixels must see the level, so that an empty view cannot pass.
void expectAovsAgree(const RenderImage& gpu, const RenderImage& cpu, double minHits) {
  ASSERT_EQ(gpu.face.size(), cpu.face.size());
  size_t mismatched = 0, coplanarTies = 0, hits = 0;
  for (size_t i = 0; i < cpu.face.size(); ++i) {
    if (gpu.face[i] != cpu.face[i]) {
      // Overlapping brushes put coplanar faces at the same t; the contract breaks such ties by
      // face index, but the t of each is rounded differently by the two tracers' arithmetic
      // (the GL tracer clips by every plane, the CPU's TraceScene takes axial planes from the
      // box), so either face may win. Geometrically the pixel is the same.
      const bool tie = gpu.face[i] != 0 && cpu.face[i] != 0 && std::abs(gpu.depth[i] - cpu.depth[i]) <= 1e-4f * cpu.depth[i] &&
          glm::length(gpu.normal[i] - cpu.normal[i]) < 1e-6f;
      ++(tie ? coplanarTies : mismatched);
      continue;
    }
    if (cpu.face[i] == 0) continue;
    ++hits;
    EXPECT_NEAR(gpu.depth[i], cpu.depth[i], 1e-4f * cpu.depth[i]) << "pixel " << i;
    EXPECT_LT(glm::length(gpu.normal[i] - cpu.normal[i]), 1e-6f) << "pixel " << i;
    // The hit points differ by the rounding of t (the CPU's TraceScene computes it from the
    // box slabs); bilinear filtering between high-contrast texels turns that into up to ~1e-3.
    EXPECT_LT(glm::length(gpu.albedo[i] - cpu.albedo[i]), 2e-3f) << "pixel " << i;
  }
  EXPECT_LE(mismatched, cpu.face.size() / 200) << mismatched << " pixels see another face";
  EXPECT_LE(coplanarTies, cpu.face.size() / 10) << coplanarTies << " pixels see another coplanar face";
  EXPECT_GE(double(hits), minHits * double(cpu.face.size())) << hits << " pixels see the level";
}

TEST(GlCpuParity, AovsEqualTheCpuReferenceOnASharedMap) {
  BT_REQUIRE_SHARED(shared);
  const auto level = loadLibreQuake(shared, "misc/slope.map");
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 1;
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level->render, level->pose, settings, cpu, GlRenderParts::AovsOnly);
  expectAovsAgree(gpu, cpu, 0.5);
}

// The same on every map of the repository's maps/: the default map and one per dialect (each
// dialect's texture projection, their missing textures drawn as checkers), each from its own
// camera (info_intermission or the player start), at a small size. One context and
// one AOV program serve them all; no path tracer is built (GlRenderParts::AovsOnly).
TEST(GlCpuParity, AovsEqualTheCpuReferenceOnEveryMapInMaps) {
  std::vector<std::filesystem::path> maps;
  for (const auto& dir : {test::mapsDir(), test::mapsDir() / "dialects"})
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.path().extension() == ".map") maps.push_back(entry.path());
  std::sort(maps.begin(), maps.end());
  ASSERT_GE(maps.size(), 9u) << "start.map and the eight dialect maps";

  GlContext& context = test::sharedGlContext();
  auto programs = std::make_shared<TracerPrograms>(context, test::textureModeUnderTest());
  RenderSettings settings;
  settings.width = 64;
  settings.height = 36;
  settings.spp = 1;
  for (const auto& map : maps) {
    SCOPED_TRACE(map.filename().string());
    Level level;
    level.scene = importScene(map.string(), ImportOptions{});
    Diagnostics diagnostics;
    level.render = buildRenderScene(level.scene, {}, diagnostics);
    level.pose = defaultCameraPose(level.scene);
    const RenderImage cpu = renderCpu(level.render, Camera(level.pose, settings.width, settings.height), settings);
    const int errorsBefore = context.debugErrorCount();
    const RenderImage gpu = renderWithGl(context, level.render, level.pose, settings, programs, {}, GlRenderParts::AovsOnly).image;
    EXPECT_EQ(context.debugErrorCount(), errorsBefore);
    EXPECT_TRUE(gpu.beauty.empty());
    // The dialect maps are an open room seen from its corner: a quarter of the view is the void.
    expectAovsAgree(gpu, cpu, 0.2);
  }
}

// More texture sizes than the arrays path has arrays (test_scenes.h makeManyTextureSizesWall):
// the arrays path, llvmpipe's only one, draws the CPU's albedo.
TEST(GlCpuParity, AovsWithMoreTextureSizesThanArraysEqualTheCpu) {
  const Scene scene = test::makeManyTextureSizesWall();
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  const CameraPose pose{{-150.0f, 0.0f, 0.0f}, 0.0f, 0.0f, 0.0f, "test"};
  RenderSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.spp = 1;
  const RenderImage cpu = renderCpu(rs, Camera(pose, settings.width, settings.height), settings);
  GlContext& context = test::sharedGlContext();
  const GlRenderResult gl = renderWithGl(context, rs, pose, settings, TextureMode::Arrays, {}, GlRenderParts::AovsOnly);
  ASSERT_EQ(gl.textures, TextureMode::Arrays);
  expectAovsAgree(gl.image, cpu, 0.5);
}

void expectBeautyAgrees(const RenderImage& gpu, const RenderImage& cpu, double meanTolerance) {
  ASSERT_EQ(gpu.beauty.size(), cpu.beauty.size());
  EXPECT_EQ(gpu.samples, cpu.samples);
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  size_t close = 0;
  for (size_t i = 0; i < cpu.beauty.size(); ++i) {
    gpuSum += glm::dvec3(gpu.beauty[i]);
    cpuSum += glm::dvec3(cpu.beauty[i]);
    const float d = glm::length(gpu.beauty[i] - cpu.beauty[i]);
    close += d <= 0.01f * glm::length(cpu.beauty[i]) + 1e-3f;
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], meanTolerance * cpuSum[c] + 1e-6) << "channel " << c;
  EXPECT_GE(close, cpu.beauty.size() * 97 / 100) << close << " of " << cpu.beauty.size() << " pixels agree";
  EXPECT_GT(cpuSum.x + cpuSum.y + cpuSum.z, 0.0) << "a black image proves nothing";
}

// kWidth x kHeight at 4 spp; physical mode with 2 bounces.
RenderSettings beautySettings(LightingMode mode, uint32_t seed) {
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 4;
  settings.seed = seed;
  settings.integrator.mode = mode;
  if (mode == LightingMode::Physical) settings.integrator.bounces = 2;
  return settings;
}

TEST(GlCpuParity, FaithfulBeautyAgreesWithTheCpuReference) {
  BT_REQUIRE_SHARED(shared);
  const auto level = loadLibreQuake(shared, "misc/slope.map");
  const RenderSettings settings = beautySettings(LightingMode::Faithful, 3);
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level->render, level->pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
}

// Faithful mode as the game shows it: both tracers read the same baked luxels
// (lighting/lightmap_bake.h) and filter them with the same arithmetic, so every pixel agrees
// up to float rounding (a shader may fuse the filters' multiply-adds: 0.2 % seen on llvmpipe, 5e-5 in the H100's darkest pixels), not
// only on average; a face left unbaked is lit at its point by both.
TEST(GlCpuParity, BakedLuxelsShowTheSameInBothTracers) {
  BT_REQUIRE_SHARED(shared);
  auto level = loadLibreQuake(shared, "misc/slope.map");
  const RenderSettings settings = beautySettings(LightingMode::Faithful, 3);
  const Camera camera(level->pose, settings.width, settings.height);
  bakeFaithfulLightmaps(level->render, &camera, settings.width, settings.height, {});
  ASSERT_FALSE(level->render.lightmaps.empty());
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level->render, level->pose, settings, cpu);
  ASSERT_EQ(gpu.beauty.size(), cpu.beauty.size());
  size_t lit = 0;
  for (size_t i = 0; i < cpu.beauty.size(); ++i) {
    EXPECT_LE(glm::length(gpu.beauty[i] - cpu.beauty[i]), 2e-3f * glm::length(cpu.beauty[i]) + 2e-4f) << "pixel " << i;
    lit += cpu.beauty[i] != glm::vec3(0.0f);
  }
  EXPECT_GT(lit, cpu.beauty.size() / 2) << "a black image proves nothing";
}

// The default camera, but on hl_basic, whose player start looks at walls its one light leaves
// black: there the view up at its lit ceiling.
CameraPose litView(const Scene& scene) {
  CameraPose pose = defaultCameraPose(scene);
  if (scene.format != "bsp30") return pose;
  pose.origin = {-102.4f, 83.2f, 144.0f};
  pose.pitch = -90.0f, pose.yaw = 0.0f;
  return pose;
}

// --lighting compiled: both tracers draw a .bsp's own lightmaps from the same fragments
// (lighting/compiled_lightmaps.h), through each engine's display scale: a Quake level with a
// .lit (overbright), a Quake 2 one (no overbright) and a Half-Life one (GoldSrc's light gamma
// table, which the GL tracer reads from the lightmap buffer), every pixel up to float rounding. (Not
// q2_light_sun: without its .wal the compiler saw no sky face, so its sun lit nothing and Quake 2,
// which draws a face by its texinfo flags, shows that sky as a black wall.)
TEST(GlCpuParity, CompiledLightmapsShowTheSameInBothTracers) {
  BT_REQUIRE_SHARED(shared);
  for (const char* file : {"lit/maps_ericw-tools_testmaps_q1_light_hlform.bsp", "lit-games/maps_ericw-tools_testmaps_q2_dirt.bsp",
                           "lit-games/maps_ericw-tools_testmaps_hl_basic.bsp"}) {
    SCOPED_TRACE(file);
    const Scene scene = importScene((shared / "oracle" / file).string(), ImportOptions{});
    Diagnostics diagnostics;
    RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    ASSERT_EQ(showCompiledLightmaps(scene, rs, ""), "");
    const RenderSettings settings = beautySettings(LightingMode::Faithful, 1);
    RenderImage cpu;
    const RenderImage gpu = renderBoth(rs, litView(scene), settings, cpu);
    ASSERT_EQ(gpu.beauty.size(), cpu.beauty.size());
    size_t lit = 0;
    for (size_t i = 0; i < cpu.beauty.size(); ++i) {
      EXPECT_LE(glm::length(gpu.beauty[i] - cpu.beauty[i]), 2e-3f * glm::length(cpu.beauty[i]) + 2e-4f) << "pixel " << i;
      lit += cpu.beauty[i] != glm::vec3(0.0f);
    }
    EXPECT_GT(lit, cpu.beauty.size() / 4) << "a black image proves nothing";
  }
}

// Faithful light at each pixel (--luxels off) on a Quake 2 level: both tracers show it as ref_gl
// does, texture × stored / 255 (WorldLighting::overbrightOne, which the GL tracer reads from the
// World block), not Quake's / 128, which drew it twice as bright on the GPU.
TEST(GlCpuParity, Quake2PerPixelLightShowsAsTheCpuShowsIt) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "oracle/lit-games/maps_ericw-tools_testmaps_q2_dirt.bsp").string(), ImportOptions{});
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  ASSERT_EQ(rs.world.overbrightOne, 255.0f);
  ASSERT_TRUE(rs.lightmaps.empty()) << "the light at each pixel, not baked luxels";
  RenderImage cpu;
  const RenderImage gpu = renderBoth(rs, defaultCameraPose(scene), beautySettings(LightingMode::Faithful, 5), cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
}

// Faithful light at each pixel (--luxels off) on a Half-Life level: both tracers take the stored
// value through GoldSrc's light gamma table (WorldLighting::luxelDisplay in the World block, the
// table from the lightmap buffer, which holds it even with no luxel baked).
TEST(GlCpuParity, HalfLifePerPixelLightShowsAsTheCpuShowsIt) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "oracle/lit-games/maps_ericw-tools_testmaps_hl_basic.bsp").string(), ImportOptions{});
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  ASSERT_EQ(rs.world.luxelDisplay, BT_LUXEL_DISPLAY_GOLDSRC);
  ASSERT_TRUE(rs.lightmaps.empty()) << "the light at each pixel, not baked luxels";
  RenderImage cpu;
  const RenderImage gpu = renderBoth(rs, litView(scene), beautySettings(LightingMode::Faithful, 5), cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
}

// q3map2's light from Quake 3 shaders at each pixel (--luxels off; lighting/q3map2_shader_light.h):
// surface lights, a sky shader's sun with worldspawn _ambient, a q3map_skylight dome, seen from
// above the floor by both tracers alike.
TEST(GlCpuParity, Q3map2ShaderLightPerPixelShowsAsTheCpuShowsIt) {
  for (const char* map : {"surface_light.map", "sun.map", "skylight.map"}) {
    SCOPED_TRACE(map);
    const Scene scene = importScene((test::mapsDir() / "q3map2" / "shader_light" / "maps" / map).string(), ImportOptions{});
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    CameraPose pose;
    pose.origin = {0.0f, 0.0f, 100.0f};
    pose.pitch = 90.0f; // looking down, below the panels
    RenderImage cpu;
    const RenderImage gpu = renderBoth(rs, pose, beautySettings(LightingMode::Faithful, 5), cpu);
    expectBeautyAgrees(gpu, cpu, 0.01);
  }
}

TEST(GlCpuParity, PhysicalBeautyAgreesWithTheCpuReference) {
  BT_REQUIRE_SHARED(shared);
  const auto level = loadLibreQuake(shared, "misc/slope.map");
  const RenderSettings settings = beautySettings(LightingMode::Physical, 5);
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level->render, level->pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.03);
}

// Physical mode's firefly clamp (IntegratorSettings::clampIndirect) on both tracers, in a room
// whose light is 8 units from a wall. At 512 units (not the default: so that it changes the light
// of every path that bounces, not of the few that find the spot beside the light) both dim the
// same lights at the same surfaces; the CPU's clamped image must be darker than its unclamped
// one by more than the tolerance, so that a GL tracer that ignored the clamp would fail.
TEST(GlCpuParity, FireflyClampAgreesWithTheCpuReference) {
  const Scene scene = test::lightNearWallRoom();
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  const CameraPose pose{{110.0f, 100.0f, 100.0f}, 30.0f, -150.0f, 0.0f, "test"};
  RenderSettings settings = beautySettings(LightingMode::Physical, 21);
  settings.integrator.clampIndirect = 512.0f;
  RenderImage cpu;
  const RenderImage gpu = renderBoth(rs, pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.03);

  RenderSettings unclamped = settings;
  unclamped.integrator.clampIndirect = 0.0f;
  const RenderImage bright = renderCpu(rs, Camera(pose, settings.width, settings.height), unclamped);
  double clampedSum = 0.0, unclampedSum = 0.0;
  for (size_t i = 0; i < cpu.beauty.size(); ++i) clampedSum += cpu.beauty[i].x, unclampedSum += bright.beauty[i].x;
  EXPECT_LT(clampedSum, 0.9 * unclampedSum) << "the clamp should take a tenth of the light or more here";
}

// Physical mode's emitters on both tracers: maps/start.map's glowing lamp is an area emitter,
// sampled by NEE and met by bounce rays (MIS on both), beside its sun, spots and point lights.
TEST(GlCpuParity, PhysicalBeautyWithEmittersAgreesWithTheCpuReference) {
  Level level;
  level.scene = importScene((test::mapsDir() / "start.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  level.render = buildRenderScene(level.scene, {}, diagnostics);
  level.pose = defaultCameraPose(level.scene);
  ASSERT_FALSE(level.render.emitters.empty()) << "start.map must keep an emitting face for this test";
  const RenderSettings settings = beautySettings(LightingMode::Physical, 9);
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level.render, level.pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.03);
}

// A lit liquid takes light from both sides on both tracers: a pool under _litwater whose only
// light is under its surface. A tracer that lit the water one-sided would draw it black.
TEST(GlCpuParity, LitWaterLitFromBelowAgreesWithTheCpu) {
  test::BoxSceneBuilder b;
  b.material("wall", 160, 160, 160);
  b.material("*water", 60, 120, 200);
  b.room({-256, -256, 0}, {256, 256, 256}, "wall");
  b.box({-256, -256, 0}, {256, 256, 64}, "*water");
  b.worldKey("_litwater", "1");
  b.entity({{"classname", "light"}, {"origin", "0 0 32"}, {"light", "300"}});
  const Scene scene = b.build();
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  const CameraPose pose{{-200.0f, -200.0f, 200.0f}, 35.0f, 45.0f, 0.0f, "test"};
  RenderSettings settings;
  settings.width = 64;
  settings.height = 40;
  settings.spp = 4;
  settings.seed = 11;
  settings.integrator.mode = LightingMode::Faithful;
  RenderImage cpu;
  const RenderImage gpu = renderBoth(rs, pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
}

// Physical mode's minlight on both tracers: a room lit by nothing but `light 100` and an orange
// `_minlight_color`, whose walls show the floor as the game's display shows it, channel by
// channel in the texture's gamma space (lighting/README.md, "Physical mode"). Nothing else
// lights it, so no path differs: every pixel agrees in colour.
TEST(GlCpuParity, PhysicalMinlightShowsTheSameFloorAsTheCpu) {
  test::BoxSceneBuilder b;
  b.material("brown", 200, 140, 80);
  b.material("grey", 90, 90, 90);
  b.room({-256, -256, 0}, {256, 256, 256}, "brown");
  b.box({-64, -64, 0}, {64, 64, 96}, "grey");
  b.worldKey("light", "100");
  b.worldKey("_minlight_color", "255 160 64");
  const Scene scene = b.build();
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  const CameraPose pose{{-200.0f, -200.0f, 200.0f}, 35.0f, 45.0f, 0.0f, "test"};
  const RenderSettings settings = beautySettings(LightingMode::Physical, 3);
  RenderImage cpu;
  const RenderImage gpu = renderBoth(rs, pose, settings, cpu);
  ASSERT_EQ(gpu.beauty.size(), cpu.beauty.size());
  size_t lit = 0;
  for (size_t i = 0; i < cpu.beauty.size(); ++i) {
    lit += cpu.beauty[i].z > 0.0f;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(gpu.beauty[i][c], cpu.beauty[i][c], 1e-3f * cpu.beauty[i][c] + 1e-6f) << "pixel " << i << " channel " << c;
  }
  EXPECT_EQ(lit, cpu.beauty.size()) << "every pixel sees a wall at the minlight";
}

// Light selection on both tracers, in a room with 120 lights of every kind: faithful mode
// reads the light grid's lists, physical mode shadow-tests one point light picked per hit.
// Both draw the same random numbers, so they pick the same lights and most pixels agree to
// float precision, as on the shared map. A GL tracer that read other lists, or picked with
// other weights or another stream order, would light most pixels with another light.
TEST(GlCpuParity, ManyLightsPickTheSameLightsAsTheCpu) {
  const Scene scene = test::manyLightsRoom(120, true, 17);
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  ASSERT_GT(rs.lightGrid.cells.size(), 1u);
  const CameraPose pose{{-450.0f, -450.0f, 200.0f}, 25.0f, 45.0f, 0.0f, "test"};
  for (const LightingMode mode : {LightingMode::Faithful, LightingMode::Physical}) {
    SCOPED_TRACE(mode == LightingMode::Faithful ? "faithful" : "physical");
    RenderSettings settings;
    settings.width = 64;
    settings.height = 40;
    settings.spp = 4;
    settings.seed = 9;
    settings.integrator.mode = mode;
    settings.integrator.bounces = 1;
    RenderImage cpu;
    const RenderImage gpu = renderBoth(rs, pose, settings, cpu);
    expectBeautyAgrees(gpu, cpu, mode == LightingMode::Faithful ? 0.01 : 0.03);
  }
}

// Faithful dirt on both tracers: ericw-tools' dirttest2 (worldspawn _dirt 1, a light with
// _dirt_off_radius / _dirt_on_radius), with the fixed ray pattern and with _dirtmode 1's random
// rays (drawn in the same order from the same stream on both), from the player start.
TEST(GlCpuParity, FaithfulDirtAgreesWithTheCpuReference) {
  BT_REQUIRE_SHARED(shared);
  for (const char* mode : {"0", "1"}) {
    SCOPED_TRACE(std::string("_dirtmode ") + mode);
    Level level;
    level.scene = importScene((shared / "maps/ericw-tools/testmaps/deprecated/dirttest2.map").string(), ImportOptions{});
    ASSERT_FALSE(level.scene.entities.empty());
    level.scene.entities[0].keys.emplace_back("_dirtmode", mode);
    Diagnostics diagnostics;
    level.render = buildRenderScene(level.scene, {}, diagnostics);
    ASSERT_TRUE(level.render.world.dirtSettings.enabled);
    ASSERT_EQ(level.render.world.dirtSettings.mode, mode[0] - '0');
    level.pose = defaultCameraPose(level.scene);
    // 2 spp: each hit traces 48 occlusion rays before its lights, and llvmpipe is CI's GPU.
    RenderSettings settings = beautySettings(LightingMode::Faithful, 11);
    settings.spp = 2;
    RenderImage cpu;
    const RenderImage gpu = renderBoth(level.render, level.pose, settings, cpu);
    expectBeautyAgrees(gpu, cpu, 0.01);
  }
}

// ericw-tools' suntest, evaluated at each pixel on both tracers: a green light on lighting
// channel 2 lights only the func_wall on channels 1 and 2 (`_object_channel_mask 3`), through
// the world (channel 1), and the func_wall shadows both channels; seen from above the wall.
TEST(GlCpuParity, LightingChannelsAgreeWithTheCpuReference) {
  BT_REQUIRE_SHARED(shared);
  Level level;
  level.scene = importScene((shared / "maps/ericw-tools/testmaps/deprecated/suntest.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  level.render = buildRenderScene(level.scene, {}, diagnostics);
  ASSERT_FALSE(level.render.faceChannels.empty());
  level.pose = CameraPose{{48.0f, 400.0f, -200.0f}, 30.0f, 90.0f, 0.0f, "test"};
  RenderSettings settings = beautySettings(LightingMode::Faithful, 5);
  settings.spp = 2;
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level.render, level.pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
  size_t green = 0;
  for (const glm::vec3& c : cpu.beauty) green += c.g > 2.0f * c.r + 0.01f;
  EXPECT_GT(green, cpu.beauty.size() / 100) << "the green light lights the func_wall in view";
}

// ericw-tools' q2_light_negative at each pixel on both tracers: the negative light comes off after
// the minlight floor (BT_FAITHFUL_NEGATIVE), so the room is black where it reaches, not at minlight.
TEST(GlCpuParity, NegativeLightsAgreeWithTheCpuReference) {
  BT_REQUIRE_SHARED(shared);
  Level level;
  level.scene = importScene((shared / "maps/ericw-tools/testmaps/q2_light_negative.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  level.render = buildRenderScene(level.scene, {}, diagnostics);
  level.pose = defaultCameraPose(level.scene);
  const RenderSettings settings = beautySettings(LightingMode::Faithful, 17);
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level.render, level.pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
  size_t black = 0;
  for (const glm::vec3& c : cpu.beauty) black += c == glm::vec3(0.0f);
  EXPECT_GT(black, cpu.beauty.size() / 10) << "the negative light darkens the view below the minlight";
}

// Faithful _bounce on both tracers: ericw-tools' deprecated/nobounce.map (worldspawn _bounce 1),
// whose rooms are lit by a spotlight on a pillar and, everywhere else, by the bounce lights the
// CPU made (lighting/bounce.h) and the GL tracer sums like its other lights.
TEST(GlCpuParity, FaithfulBounceAgreesWithTheCpuReference) {
  BT_REQUIRE_SHARED(shared);
  Level level;
  level.scene = importScene((shared / "maps/ericw-tools/testmaps/deprecated/nobounce.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  level.render = buildRenderScene(level.scene, {}, diagnostics);
  const auto bounceLights = std::count_if(level.render.lights.begin(), level.render.lights.end(),
                                          [](const GpuLight& l) { return l.formula == uint32_t(LightFormula::Bounce); });
  ASSERT_EQ(bounceLights, 2) << "one for each pillar face a spotlight lights";
  level.pose = defaultCameraPose(level.scene);
  const RenderSettings settings = beautySettings(LightingMode::Faithful, 13);
  RenderImage cpu;
  const RenderImage gpu = renderBoth(level.render, level.pose, settings, cpu);
  expectBeautyAgrees(gpu, cpu, 0.01);
}

// More bounce lights than kBounceShadowRays in a cell: both tracers draw among them by their
// share at the hit (lighting/faithful_light.h LightSet::GridSampledBounce, pathtrace.comp faithfulBounceRay) with the
// same numbers, so they draw the same lights. The many-lights room with `_bounce 1` (about 250
// bounce lights a cell), plain and with dirt (which dims each drawn light). The draw's noise moves
// most pixels of the CPU's own image by more than the agreement asked here, checked first: a GL
// tracer that shadow-tested every bounce light, or drew others, would not agree.
TEST(GlCpuParity, ManyBounceLightsDrawTheSameAsTheCpu) {
  for (const bool dirt : {false, true}) {
    SCOPED_TRACE(dirt ? "_dirt 1" : "no dirt");
    Scene scene = test::manyLightsRoom(24, false, 7);
    scene.entities[0].keys.emplace_back("_bounce", "1");
    if (dirt) scene.entities[0].keys.emplace_back("_dirt", "1");
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    const CameraPose pose{{400.0f, -400.0f, 200.0f}, 20.0f, 135.0f, 0.0f, "test"};
    ASSERT_GT(trailingBounceLights(rs.lights, rs.lightGrid.cellLights(pose.origin)), kBounceShadowRays);
    // The GL tracer builds its faithful program with the draw (and dirt) for this level alone; the
    // room's darklight takes the negative lights' part.
    EXPECT_EQ(faithfulFeatures(rs.world.dirtSettings, rs.lights),
              (FaithfulFeatures{.dirt = dirt, .bounceDraw = true, .sky = true, .negative = true}));
    RenderSettings settings;
    settings.width = 64;
    settings.height = 40;
    settings.spp = dirt ? 1 : 4;
    settings.seed = 21;
    settings.integrator.mode = LightingMode::Faithful;
    RenderImage cpu;
    const RenderImage gpu = renderBoth(rs, pose, settings, cpu);
    expectBeautyAgrees(gpu, cpu, 0.01);

    RenderSettings exhaustive = settings;
    exhaustive.integrator.lightSelection = false;
    const RenderImage everyLight = renderCpu(rs, Camera(pose, settings.width, settings.height), exhaustive);
    size_t moved = 0;
    for (size_t i = 0; i < cpu.beauty.size(); ++i)
      moved += glm::length(cpu.beauty[i] - everyLight.beauty[i]) > 0.01f * glm::length(everyLight.beauty[i]) + 1e-3f;
    EXPECT_GT(moved, cpu.beauty.size() / 10) << "the draw must change the image beyond the agreement";
  }
}

// The bounce draw is compiled only into the faithful programs of levels that can need it: more
// bounce lights than the draw's rays. With 16 or fewer no cell lists more, and every light keeps
// its own ray on both tracers.
TEST(FaithfulFeatures, TheBounceDrawOnlyWhereALevelHasMoreBounceLightsThanRays) {
  std::vector<GpuLight> lights(3); // point lights of the default formula
  DirtSettings dirt;
  EXPECT_EQ(faithfulFeatures(dirt, lights), (FaithfulFeatures{false, false}));
  GpuLight bounce;
  bounce.formula = uint32_t(LightFormula::Bounce);
  lights.insert(lights.end(), kBounceShadowRays, bounce);
  EXPECT_EQ(faithfulFeatures(dirt, lights), (FaithfulFeatures{false, false}));
  lights.push_back(bounce);
  EXPECT_EQ(faithfulFeatures(dirt, lights), (FaithfulFeatures{false, true}));
  dirt.enabled = true;
  EXPECT_EQ(faithfulFeatures(dirt, lights), (FaithfulFeatures{true, true}));
}

// The sky code where a level has a sun or a dome, the jitter where a point light has _deviance
// (a sun's penumbra is the sky code's own).
TEST(FaithfulFeatures, TheSkyAndTheJitterOnlyWhereALightNeedsThem) {
  std::vector<GpuLight> lights(3);
  const DirtSettings dirt;
  EXPECT_EQ(faithfulFeatures(dirt, lights), FaithfulFeatures{});
  lights[1].deviance = 8.0f;
  EXPECT_EQ(faithfulFeatures(dirt, lights), (FaithfulFeatures{.jitter = true}));
  lights[1].deviance = 0.0f;
  for (const LightType sky : {LightType::Sun, LightType::Dome}) {
    lights[2].type = uint32_t(sky);
    lights[2].deviance = 0.1f;
    EXPECT_EQ(faithfulFeatures(dirt, lights), (FaithfulFeatures{.sky = true}));
  }
}

// The front ends start a level's program from its LightKinds and LevelParts, told as soon as the
// importer has its entities and faces (ImportOptions::entitiesRead), before its textures,
// _surface and _bounce lights exist (gl::LevelPreparation); the tracer renders with those
// features and what the finished level needs together. If the early ones differed from the
// finished level's, or missed something it needs, the level would compile a second program
// before its first image. Every map of ours and every shared .map (ericw-tools' test maps use
// every light key: suns, domes, _deviance, dirt, _bounce, _surface; and Quake 2's glass and
// water drawn as walls, overlapping liquids) must agree.
TEST(FaithfulFeatures, TheEarlyKindsAndPartsOfEveryMapAreTheFinishedLevelsAndCoverWhatItNeeds) {
  BT_REQUIRE_SHARED(shared);
  std::vector<std::filesystem::path> maps;
  for (const auto& dir : {test::mapsDir(), shared / "maps"})
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir))
      if (entry.path().extension() == ".map") maps.push_back(entry.path());
  std::sort(maps.begin(), maps.end());
  FaithfulFeatures seen;
  size_t checked = 0;
  for (const auto& path : maps) {
    SCOPED_TRACE(path.string());
    std::optional<LightKinds> early;
    std::optional<LevelParts> earlyParts;
    ImportOptions options;
    options.textures.load = false; // the kinds of light do not depend on the textures
    options.entitiesRead = [&](const Scene& read) {
      EXPECT_FALSE(early) << "told twice";
      Diagnostics ignored;
      early = lightKinds(read, collectLights(read, {}, ignored), true);
      earlyParts = levelParts(read, {});
    };
    Scene scene;
    try {
      scene = importScene(path.string(), options);
    } catch (const ImportError&) {
      continue; // the corpus has maps that are meant not to import
    }
    Diagnostics diagnostics;
    const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
    ASSERT_TRUE(early && earlyParts);
    EXPECT_EQ(*early, rs.lightKinds);
    EXPECT_EQ(*earlyParts, levelParts(rs));
    const FaithfulFeatures started = faithfulFeatures(*early, *earlyParts);
    EXPECT_EQ(started | faithfulFeatures(rs.world.dirtSettings, rs.lights), started);
    seen = seen | started;
    ++checked;
  }
  EXPECT_GT(checked, maps.size() * 9 / 10);
  // Not passed for want of a case: the maps use every part.
  EXPECT_EQ(seen, (FaithfulFeatures{true, true, true, true, true, true, true, true, true}));
}

// The level's kinds of light come before its preparation ends, and are those the prepared level
// records; an import that fails reaches both waits with its message, and nothing hangs.
TEST(LevelPreparation, GivesTheLightKindsFirstAndTheImportsErrors) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path map = shared / "maps" / "ericw-tools" / "testmaps" / "q1_sunlight.map";
  ASSERT_TRUE(std::filesystem::exists(map));
  Scene scene;
  RenderScene render;
  bool readEarly = false;
  LevelPreparation preparation(scene, render, [&](const EntitiesRead& entitiesRead) {
    ImportOptions options;
    options.entitiesRead = [&](const Scene& read) {
      readEarly = read.materials.empty() || read.materials.front().baseColor.empty(); // before the textures
      entitiesRead(read);
    };
    return importScene(map.string(), options);
  });
  const LightKinds kinds = preparation.lightKinds();
  EXPECT_TRUE(kinds.sky);
  preparation.wait();
  EXPECT_TRUE(readEarly) << "the lights were collected after the textures were loaded";
  EXPECT_EQ(render.scene, &scene);
  EXPECT_EQ(render.lightKinds, kinds);
  EXPECT_FALSE(render.lights.empty());
  EXPECT_LE(preparation.started, preparation.lightsCollected);
  EXPECT_LE(preparation.lightsCollected, preparation.prepared);

  const std::filesystem::path bad = std::filesystem::temp_directory_path() / "brushtrace-preparation-bad.map";
  {
    std::ofstream out(bad);
    out << "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 1 0 0 ) ( 0 1 zero ) tex 0 0 0 1 1\n}\n}\n";
  }
  Scene badScene;
  RenderScene badRender;
  LevelPreparation failing(badScene, badRender, [&](const EntitiesRead&) { return importScene(bad.string(), {}); });
  try {
    failing.lightKinds();
    ADD_FAILURE() << "lightKinds() returned for a map that does not import";
  } catch (const ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("brushtrace-preparation-bad.map:4:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(failing.wait(), ImportError);
  std::filesystem::remove(bad);
}

// Normal maps in physical mode (renderer/cpu shadingNormal, pathtrace.comp physicalSurface): a
// wall with a map of bumps, its texels all different and smaller than the base colour's, lit from
// the side; unmirrored Lambert, and mirrored with a roughness map (GGX on the shading normal).
// The map moves most pixels of the CPU's own image far beyond the agreement asked here (checked
// first), so a GL tracer that ignored it, read it in another frame or filtered it otherwise
// would not agree.
TEST(GlCpuParity, NormalMappedWallAgreesWithTheCpuReference) {
  for (const bool mirroredAndGlossy : {false, true}) {
    SCOPED_TRACE(mirroredAndGlossy ? "mirrored, glossy" : "lambert");
    const glm::vec3 light{96.0f, -120.0f, 128.0f};
    const test::NormalMapRoom flat({{}, mirroredAndGlossy, light, mirroredAndGlossy});
    const test::NormalMapRoom bumps({test::bumpsNormalMap(12, 12), mirroredAndGlossy, light, mirroredAndGlossy});
    const RenderSettings settings = beautySettings(LightingMode::Physical, 13);
    RenderImage cpu;
    const RenderImage gpu = renderBoth(bumps.render(), bumps.pose(), settings, cpu);
    expectBeautyAgrees(gpu, cpu, 0.03);
    // The normal AOV stays the face's own normal on both tracers.
    size_t wall = 0;
    for (size_t i = 0; i < gpu.face.size() && i < cpu.face.size(); ++i)
      if (cpu.face[i] == bumps.wallFace() + 1 && gpu.face[i] == cpu.face[i]) {
        ++wall;
        EXPECT_LT(glm::length(gpu.normal[i] - glm::vec3(-1.0f, 0.0f, 0.0f)), 1e-6f) << "pixel " << i;
      }
    EXPECT_GT(wall, cpu.face.size() / 2);

    const RenderImage withoutMap = renderCpu(flat.render(), Camera(flat.pose(), settings.width, settings.height), settings);
    size_t moved = 0;
    for (size_t i = 0; i < cpu.beauty.size(); ++i)
      moved += glm::length(cpu.beauty[i] - withoutMap.beauty[i]) > 0.05f * glm::length(withoutMap.beauty[i]) + 1e-3f;
    EXPECT_GT(moved, cpu.beauty.size() / 2) << "the map must change the image beyond the agreement";
  }
}

} // namespace
} // namespace bt::gl
