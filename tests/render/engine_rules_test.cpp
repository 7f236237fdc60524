// What the engine hides and what it cuts, on the maps of maps/engine_rules/ (generate.py there):
// each level against the level as the engine shows it, through the CPU tracer's AOVs and beauty
// from the player start, as `brushtrace render` draws them. tests/gl holds the GL tracer to
// these same images.
#include "importers/bsp/q3_textures.h"
#include "importers/import.h"
#include "importers/textures/png_indices.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/game_rules.h"
#include "lighting/render_scene.h"
#include "tests/render/box_scene.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace bt {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 96;

struct Level {
  Scene scene;
  RenderScene render;
};

std::unique_ptr<Level> load(const std::string& name, bool showHidden = false) {
  auto level = std::make_unique<Level>();
  level->scene = importScene((test::mapsDir() / "engine_rules" / name).string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderSceneOptions options;
  options.showHidden = showHidden;
  level->render = buildRenderScene(level->scene, options, diagnostics);
  return level;
}

RenderImage render(const Level& level) {
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.spp = 1;
  settings.threads = 2;
  return renderCpu(level.render, Camera(defaultCameraPose(level.scene), kWidth, kHeight), settings);
}

size_t pixelsSeeingEntity(const Level& level, const RenderImage& image, std::string_view classname) {
  size_t n = 0;
  for (uint32_t f : image.face)
    if (f != 0 && level.scene.entities[level.scene.brushes[level.scene.faces[f - 1].brush].entity].classname() == classname) ++n;
  return n;
}

// A trigger textured like a wall, a func_episodegate and a `*waterskip` brush stand between the
// player and the light: the game draws none of them and the compiler lights the level without
// them (the trigger's `_shadow 1` notwithstanding), so every pixel equals the level without them.
TEST(EngineRules, WhatTheGameHidesIsNeitherSeenNorCastsShadows) {
  const auto hidden = load("hidden.map");
  const auto reference = load("hidden_reference.map");
  const RenderImage a = render(*hidden), b = render(*reference);
  size_t lit = 0;
  for (size_t i = 0; i < a.face.size(); ++i) {
    ASSERT_EQ(a.face[i], b.face[i]) << "pixel " << i % kWidth << "," << i / kWidth;
    ASSERT_EQ(a.albedo[i], b.albedo[i]) << "pixel " << i;
    ASSERT_EQ(a.beauty[i], b.beauty[i]) << "pixel " << i;
    lit += a.beauty[i].r > 0.05f;
  }
  EXPECT_GT(lit, a.face.size() / 4) << "the light must reach the floor behind the hidden brushes";
}

// --show-hidden draws them: the same view then sees each of them.
TEST(EngineRules, ShowHiddenDrawsThem) {
  const auto level = load("hidden.map", true);
  const RenderImage image = render(*level);
  EXPECT_GT(pixelsSeeingEntity(*level, image, "trigger_multiple"), image.face.size() / 10);
  EXPECT_GT(pixelsSeeingEntity(*level, image, "func_episodegate"), 20u);
  size_t skip = 0;
  for (uint32_t f : image.face) skip += f != 0 && level->scene.faces[f - 1].texture == "*waterskip";
  EXPECT_GT(skip, 5u);
}

// The fence texture of generate.py: opaque bars 8 texels wide every 32, both ways; palette index
// 255 between them. `margin` texels around each bar's edge count as neither (bilinear filtering).
enum class Texel { Opaque, Clear, Edge };
Texel fenceTexel(double s, double t, double margin = 1.0) {
  auto classify = [&](double x) {
    const double m = x - 32.0 * std::floor(x / 32.0);
    if (m > margin && m < 8.0 - margin) return Texel::Opaque;
    if (m > 8.0 + margin && m < 32.0 - margin) return Texel::Clear;
    return Texel::Edge;
  };
  const Texel a = classify(s), b = classify(t);
  if (a == Texel::Opaque || b == Texel::Opaque) return Texel::Opaque;
  return a == Texel::Clear && b == Texel::Clear ? Texel::Clear : Texel::Edge;
}

// The fence's face towards the player (normal -x) and what it shows at a point of its plane.
const Face& fenceFace(const Scene& scene) {
  for (const Face& f : scene.faces)
    if (f.texture == "{fence" && f.plane.normal.x < -0.5) return f;
  throw std::runtime_error("fence.map has no fence");
}

// Through the holes of an 8-bit PNG fence the room beyond shows as if there were no fence; its
// bars show the fence.
TEST(EngineRules, PngFenceHolesShowWhatIsBehindIt) {
  const auto fence = load("fence.map");
  const auto open = load("fence_open.map");
  const CameraPose pose = defaultCameraPose(fence->scene);
  const Camera camera(pose, kWidth, kHeight);
  const RenderImage a = renderAovsCpu(fence->render, camera, kWidth, kHeight, 2);
  const RenderImage b = renderAovsCpu(open->render, camera, kWidth, kHeight, 2);
  const Face& face = fenceFace(fence->scene);
  const uint32_t fenceIndex = uint32_t(&face - fence->scene.faces.data()) + 1;
  size_t bars = 0, holes = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const Ray ray = camera.ray(x + 0.5f, y + 0.5f);
      const size_t i = size_t(y) * kWidth + x;
      const double t = face.plane.distanceTo(dvec3(ray.origin)) / -glm::dot(face.plane.normal, dvec3(ray.direction));
      const dvec3 p = dvec3(ray.origin) + t * dvec3(ray.direction);
      if (!(t > 0.0) || std::abs(p.y) > 127.0 || p.z < 1.0 || p.z > 191.0) continue;
      switch (fenceTexel(face.frame.s(p), face.frame.t(p))) {
      case Texel::Opaque:
        ++bars;
        EXPECT_EQ(a.face[i], fenceIndex) << "bar at pixel " << x << "," << y;
        break;
      case Texel::Clear:
        ++holes;
        EXPECT_EQ(a.face[i], b.face[i]) << "hole at pixel " << x << "," << y;
        EXPECT_EQ(a.albedo[i], b.albedo[i]) << "hole at pixel " << x << "," << y;
        break;
      case Texel::Edge: break;
      }
    }
  EXPECT_GT(bars, 1000u);
  EXPECT_GT(holes, 3000u);
}

// The light stands behind the fence, alone: a point of the floor on the player's side is lit
// exactly where its segment to the light crosses the fence through a hole, as `light` casts the
// shadows of `{` brushes. A pixel's one sample lies anywhere in it, so only pixels whose four
// corners see the same part of the fence's shadow count.
TEST(EngineRules, PngFenceShadowsFollowItsMask) {
  const auto fence = load("fence.map");
  const RenderImage image = render(*fence);
  const Face& face = fenceFace(fence->scene);
  const Camera camera(defaultCameraPose(fence->scene), kWidth, kHeight);
  const dvec3 light(150.0, 0.0, 96.0);
  // What the fence does to the light at the floor point (z = 0) seen at image point (x, y).
  auto shadowAt = [&](float x, float y) {
    const Ray ray = camera.ray(x, y);
    if (!(ray.direction.z < 0.0f)) return Texel::Edge;
    const dvec3 p = dvec3(ray.origin) + (-double(ray.origin.z) / double(ray.direction.z)) * dvec3(ray.direction);
    if (p.x > -4.0 || p.x < -250.0 || std::abs(p.y) > 122.0) return Texel::Edge; // the floor on the player's side
    const dvec3 q = p + (-p.x / (light.x - p.x)) * (light - p);
    return fenceTexel(face.frame.s(q), face.frame.t(q));
  };
  size_t lit = 0, shadowed = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const Texel texel = shadowAt(float(x), float(y));
      if (texel == Texel::Edge || shadowAt(x + 1.0f, float(y)) != texel || shadowAt(float(x), y + 1.0f) != texel ||
          shadowAt(x + 1.0f, y + 1.0f) != texel)
        continue;
      const size_t i = size_t(y) * kWidth + x;
      const bool isLit = image.beauty[i].r > 0.0f;
      ++(texel == Texel::Clear ? lit : shadowed);
      EXPECT_EQ(isLit, texel == Texel::Clear) << "floor pixel " << x << "," << y
                                              << (isLit ? " behind a bar is lit" : " behind a hole is dark");
    }
  EXPECT_GT(lit, 300u);
  EXPECT_GT(shadowed, 100u);
}

TEST(EngineRules, GameHidesTheEntitiesItsCodeNeverDraws) {
  auto entity = [](std::vector<std::pair<std::string, std::string>> keys) {
    Entity e;
    e.keys = std::move(keys);
    return e;
  };
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "trigger_teleport"}}), Game::Quake));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "func_episodegate"}}), Game::Quake));
  EXPECT_FALSE(gameHidesEntity(entity({{"classname", "func_bossgate"}}), Game::Quake));
  EXPECT_FALSE(gameHidesEntity(entity({{"classname", "func_illusionary"}}), Game::Quake));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "func_areaportal"}}), Game::Quake2));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "func_wall"}, {"spawnflags", "1"}}), Game::Quake2));
  EXPECT_FALSE(gameHidesEntity(entity({{"classname", "func_wall"}, {"spawnflags", "5"}}), Game::Quake2));
  EXPECT_FALSE(gameHidesEntity(entity({{"classname", "func_wall"}, {"spawnflags", "1"}}), Game::Quake));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "func_object"}, {"spawnflags", "2"}}), Game::Quake2));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "func_ladder"}}), Game::HalfLife));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "func_wall"}, {"rendermode", "2"}, {"renderamt", "0"}}), Game::HalfLife));
  EXPECT_FALSE(gameHidesEntity(entity({{"classname", "func_wall"}, {"rendermode", "2"}, {"renderamt", "120"}}), Game::HalfLife));
  EXPECT_FALSE(gameHidesEntity(entity({{"classname", "func_door"}}), Game::Quake3));
  EXPECT_TRUE(gameHidesEntity(entity({{"classname", "trigger_push"}}), Game::Quake3));
}

// The palette indices of LibreQuake-style PNGs; anything else, a truncated file included, is no
// such PNG (nullopt), never a crash.
TEST(EngineRules, PngPaletteIndicesAreReadAsStored) {
  const std::filesystem::path fence = test::mapsDir() / "engine_rules/textures/{fence.png";
  const auto indices = readPngPaletteIndices(fence);
  ASSERT_TRUE(indices);
  ASSERT_EQ(indices->size(), 64u * 64u);
  EXPECT_EQ((*indices)[0], 1);                                                  // (0, 0): on a bar
  EXPECT_EQ((*indices)[8 * 64 + 8], 255);                                       // (8, 8): a hole
  EXPECT_FALSE(readPngPaletteIndices(test::mapsDir() / "textures/bricks.png")); // RGB
  std::ifstream in(fence, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const std::filesystem::path cut = std::filesystem::temp_directory_path() / "bt_engine_rules_cut.png";
  for (size_t size : {size_t(0), size_t(8), size_t(40), bytes.size() / 2, bytes.size() - 13}) {
    std::ofstream(cut, std::ios::binary).write(bytes.data(), std::streamsize(size));
    EXPECT_FALSE(readPngPaletteIndices(cut)) << size << " bytes";
  }
  std::filesystem::remove(cut);
  EXPECT_FALSE(readPngPaletteIndices(test::mapsDir() / "engine_rules/textures/no such file.png"));
}

TEST(EngineRules, Quake3ShadersAlphaTestOnlyWhereTheySay) {
  const auto tests = bsp::parseShaderAlphaTests(R"(
textures/a/grate
{
  surfaceparm alphashadow
  {
    map textures/a/grate.tga
    alphaFunc GE128
    depthWrite
  }
  { map $lightmap blendFunc filter }
}
textures/a/leaves { cull none { map textures/a/leaves.tga
  alphafunc gt0 } }
textures/a/glass { { map textures/a/glass.tga blendFunc blend } }
textures/a/inverse { { map x.tga
  alphaFunc LT128 } }
)");
  EXPECT_EQ(tests.at("textures/a/grate"), AlphaTest::Ge128);
  EXPECT_EQ(tests.at("textures/a/leaves"), AlphaTest::Gt0);
  EXPECT_EQ(tests.at("textures/a/glass"), AlphaTest::None);
  EXPECT_EQ(tests.at("textures/a/inverse"), AlphaTest::Lt128);
}

Scene roomFor(const std::string& format, std::vector<std::vector<std::pair<std::string, std::string>>> entities) {
  test::BoxSceneBuilder b;
  b.material("white", 255, 255, 255);
  b.room({-256, -256, 0}, {256, 256, 256}, "white");
  for (auto& keys : entities) b.entity(std::move(keys));
  Scene scene = b.build();
  scene.format = format;
  return scene;
}

// Each game's eye: its spawn offset and view height, its intermission first.
TEST(DefaultCamera, EachGamePutsTheEyeWhereItsCodeDoes) {
  CameraPose pose = defaultCameraPose(roomFor("quake2",
                                              {{{"classname", "info_player_deathmatch"}, {"origin", "0 0 24"}},
                                               {{"classname", "info_player_start"}, {"origin", "10 0 24"}, {"targetname", "x"}},
                                               {{"classname", "info_player_start"}, {"origin", "20 0 24"}, {"angles", "5 90 0"}}}));
  EXPECT_EQ(pose.source, "info_player_start");
  EXPECT_EQ(pose.origin, glm::vec3(20, 0, 55)); // the start without a targetname, + 9 + 22
  EXPECT_FLOAT_EQ(pose.pitch, 5.0f);
  EXPECT_FLOAT_EQ(pose.yaw, 90.0f);
  pose = defaultCameraPose(roomFor("ibsp46", {{{"classname", "info_player_deathmatch"}, {"origin", "0 0 24"}}}));
  EXPECT_EQ(pose.origin, glm::vec3(0, 0, 59)); // + 9 + 26
  pose = defaultCameraPose(roomFor("bsp30", {{{"classname", "info_player_deathmatch"}, {"origin", "0 0 36"}}}));
  EXPECT_EQ(pose.origin, glm::vec3(0, 0, 65)); // + 1 + 28
  // Quake 3's intermission looks at its target.
  pose = defaultCameraPose(roomFor("quake3",
                                   {{{"classname", "info_player_deathmatch"}, {"origin", "0 0 24"}},
                                    {{"classname", "info_player_intermission"}, {"origin", "0 0 100"}, {"target", "t"}},
                                    {{"classname", "target_position"}, {"origin", "-100 0 0"}, {"targetname", "t"}}}));
  EXPECT_EQ(pose.source, "info_player_intermission");
  EXPECT_EQ(pose.origin, glm::vec3(0, 0, 100));
  EXPECT_NEAR(std::abs(pose.yaw), 180.0f, 1e-4f);
  EXPECT_NEAR(pose.pitch, 45.0f, 1e-4f); // looking down at it
}

// A level with no spawn point opens inside it, where the walls close in, not outside.
TEST(DefaultCamera, ALevelWithoutSpawnPointsOpensInside) {
  const CameraPose pose = defaultCameraPose(roomFor("quake2", {}));
  EXPECT_EQ(pose.source, "inside the level");
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(pose.origin[a], a == 2 ? 0.0f : -256.0f);
    EXPECT_LT(pose.origin[a], 256.0f);
  }
}

} // namespace
} // namespace bt
