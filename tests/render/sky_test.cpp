// Quake's two-layer sky as QuakeSpasm draws it at time 0 (Quake/gl_sky.c), on maps/sky/
// (generate.py there): every sky pixel of the albedo AOV against the engine's formula, computed
// here from the texture's texels, and the beauty of both lighting modes against it.
#include "importers/bsp/q3_textures.h"
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "lighting/sky.h"
#include "renderer/cpu/cpu_renderer.h"
#include "scene/color.h"
#include "shaders/light_constants.glsl"
#include "tests/render/box_scene.h"
#include "tests/render/test_level.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <optional>
#include <tuple>
#include <unistd.h>

namespace bt {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 64;

using test::Level;

// `dome`: the worldspawn's `_sunlight2` when above 0 (the level has none).
std::unique_ptr<Level> loadSkyLevel(bool lights = true, double dome = 0.0) {
  auto level = std::make_unique<Level>();
  level->scene = importScene((test::mapsDir() / "sky" / "sky_layers.map").string(), ImportOptions{});
  // The light is a point entity after every brush entity: dropping it renumbers no brush's entity.
  if (!lights) std::erase_if(level->scene.entities, [](const Entity& e) { return e.classname() == "light"; });
  if (dome > 0.0) level->scene.entities.at(0).keys.emplace_back("_sunlight2", std::to_string(dome));
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, {}, diagnostics);
  return level;
}

const Material& skyMaterial(const Scene& scene) {
  const auto m = scene.findMaterial("sky_test");
  EXPECT_TRUE(m.has_value());
  return scene.materials[*m];
}

// The engine's rule, written out again: Sky_GetTexCoord (the direction from the eye, z times 3,
// scaled to 6*63, over 128) gives both layers' coordinates at time 0; Sky_LoadTexture makes the
// right half the solid layer and the left half the alpha layer, its index 0 clear (black in this
// level's palette, and no other index is); the alpha layer is drawn over the solid one (GL_DECAL).
// Each layer is filtered bilinearly with repeat over its own 128x128 texels.
glm::dvec3 engineSky(const Image& image, glm::dvec3 dir) {
  dir.z *= 3.0;
  const double scale = 6.0 * 63.0 / glm::length(dir);
  const double s = dir.x * scale / 128.0, t = dir.y * scale / 128.0;
  const int side = image.height; // 128: each layer is square
  auto layer = [&](int firstColumn, glm::dvec3& rgb, double& alpha) {
    const double x = (s - std::floor(s)) * side - 0.5, y = (t - std::floor(t)) * side - 0.5;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    rgb = glm::dvec3(0.0), alpha = 0.0;
    for (int k = 0; k < 4; ++k) {
      const int tx = ((x0 + (k & 1)) % side + side) % side, ty = ((y0 + (k >> 1)) % side + side) % side;
      const double w = ((k & 1) ? x - x0 : 1.0 - (x - x0)) * ((k >> 1) ? y - y0 : 1.0 - (y - y0));
      const uint8_t* p = image.texel(firstColumn + tx, ty);
      const bool clear = firstColumn == 0 && p[0] == 0 && p[1] == 0 && p[2] == 0;
      rgb += w * glm::dvec3(p[0], p[1], p[2]) / 255.0;
      alpha += clear ? 0.0 : w;
    }
  };
  glm::dvec3 back, front;
  double backAlpha, frontAlpha;
  layer(side, back, backAlpha);
  layer(0, front, frontAlpha);
  const glm::dvec3 shown = front + back * (1.0 - frontAlpha); // clear texels are black: front is premultiplied
  return glm::dvec3(srgbToLinear(float(shown.x)), srgbToLinear(float(shown.y)), srgbToLinear(float(shown.z)));
}

bool isSky(const Level& level, uint32_t faceIndexPlusOne) {
  return faceIndexPlusOne != 0 && level.scene.faces[faceIndexPlusOne - 1].texture == "sky_test";
}

RenderImage renderSky(const Level& level, LightingMode mode, int spp) {
  return test::renderFromDefaultCamera(level, mode, spp, kWidth, kHeight);
}

// The level's sky is the sky texture's two layers, as two materials: the right half (back,
// opaque) and the left half (front) with palette index 0 (black here) clear and black. The
// texture itself stays as the WAD holds it (its faces are drawn as the sky, not with it).
TEST(Sky, QuakeSkyTextureHasTwoLayers) {
  const auto level = loadSkyLevel();
  const Image& texture = skyMaterial(level->scene).baseColor;
  ASSERT_TRUE(level->scene.sky.has_value());
  EXPECT_EQ(level->scene.sky->kind, Sky::Kind::QuakeLayers);
  EXPECT_EQ(level->scene.sky->name, "sky_test");
  ASSERT_EQ(texture.width, 256);
  const Image& back = level->scene.materials[level->scene.sky->firstMaterial].baseColor;
  const Image& front = level->scene.materials[level->scene.sky->firstMaterial + 1].baseColor;
  ASSERT_EQ(back.width, 128);
  ASSERT_EQ(front.width, 128);
  size_t clearFront = 0, wrong = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      const uint8_t* left = texture.texel(x, y);
      const bool clear = left[0] == 0 && left[1] == 0 && left[2] == 0;
      clearFront += clear;
      wrong += !std::equal(back.texel(x, y), back.texel(x, y) + 4, texture.texel(x + 128, y));
      wrong += clear ? front.texel(x, y)[3] != 0 || front.texel(x, y)[0] != 0 : !std::equal(front.texel(x, y), front.texel(x, y) + 4, left);
      wrong += texture.texel(x, y)[3] != 255 || texture.texel(x + 128, y)[3] != 255;
    }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(clearFront, 128u * 128u / 2);
}

// Every sky pixel of the albedo AOV is the engine's sky along a direction less than half a
// texel of the baked sky from the pixel's ray (lighting/sky.h: the tracers read the nearest texel
// of a cube map of 512 texels a face, at whose centre the engine's rule was evaluated, stored as
// half floats: 2e-3 holds their rounding), and the level's camera sees both layers and most of
// the sky's range of heights. At the pixel's own direction, the mean error (the length of the
// linear rgb difference) stays small.
TEST(Sky, AlbedoOfSkyPixelsIsTheEnginesTwoLayerSky) {
  const auto level = loadSkyLevel();
  const Image& texture = skyMaterial(level->scene).baseColor;
  const RenderImage image = renderSky(*level, LightingMode::Faithful, 1);
  const Camera camera(defaultCameraPose(level->scene), kWidth, kHeight);
  const int size = level->render.sky.size;
  ASSERT_EQ(size, 512);
  const double halfTexel = std::sqrt(2.0) / size; // half a texel's diagonal on a face at distance 1
  size_t sky = 0, front = 0, back = 0, wrong = 0;
  double meanError = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const size_t i = size_t(y) * kWidth + x;
      if (!isSky(*level, image.face[i])) continue;
      ++sky;
      const glm::vec3 dir = glm::normalize(camera.ray(x + 0.5f, y + 0.5f).direction);
      const glm::vec3 centre = glm::normalize(skyMapTexelDirection(skyMapTexel(dir, size), size));
      EXPECT_LE(std::acos(std::min(1.0f, glm::dot(dir, centre))), halfTexel + 1e-5) << "pixel " << x << "," << y;
      const glm::dvec3 expected = engineSky(texture, glm::dvec3(centre));
      const glm::dvec3 got(image.albedo[i]);
      const double error = std::max({std::abs(got.x - expected.x), std::abs(got.y - expected.y), std::abs(got.z - expected.z)});
      meanError += glm::length(got - engineSky(texture, glm::dvec3(dir)));
      if (error > 2e-3 && wrong++ < 5)
        ADD_FAILURE() << "pixel " << x << "," << y << ": albedo " << got.x << " " << got.y << " " << got.z << ", the engine's sky "
                      << expected.x << " " << expected.y << " " << expected.z;
      front += expected.x > 2.0 * expected.z; // red or yellow: the front layer
      back += expected.z > 2.0 * expected.x;  // blue: the back layer shows through
    }
  EXPECT_EQ(wrong, 0u) << "of " << sky << " sky pixels";
  // 0.018 measured: towards the horizon the engine's rule compresses several of a layer's texels
  // into one texel of the bake, whose centre's value a nearby direction reads.
  EXPECT_LT(meanError / double(std::max<size_t>(sky, 1)), 0.025) << "the mean error at the pixels' own directions";
  EXPECT_GT(sky, size_t(kWidth * kHeight) / 3) << "the camera should look at the sky";
  EXPECT_GT(front, sky / 10);
  EXPECT_GT(back, sky / 4);
}

// The beauty of a sky pixel is the sky, unlit, in both modes (physical mode: the `sky`
// radiance is the image's linear colour; no sky-dome light here). Compared in the mean over sky
// pixels, since beauty samples are jittered in the pixel.
TEST(Sky, BeautyOfSkyPixelsIsTheSameImageInBothModes) {
  const auto level = loadSkyLevel();
  for (LightingMode mode : {LightingMode::Faithful, LightingMode::Physical}) {
    const RenderImage image = renderSky(*level, mode, 16);
    glm::dvec3 beauty(0.0), albedo(0.0);
    for (size_t i = 0; i < image.face.size(); ++i)
      if (isSky(*level, image.face[i])) beauty += glm::dvec3(image.beauty[i]), albedo += glm::dvec3(image.albedo[i]);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(beauty[c], albedo[c], 0.01 * albedo[c]) << "channel " << c << ", mode " << int(mode);
  }
}

// Physical mode, the level's light off: the sky lights the floor with the light the compiler
// gives it, the dome (`_sunlight2`), and not with its picture, which lights nothing in the game
// (lighting/README.md, "Physical mode"). Without a dome the floor under the open ceiling is black;
// with `_sunlight2 100` each floor pixel is albedo x the dome's radiance x the cosine-weighted
// share of its directions that leave the room through the ceiling (the walls are black without
// light, and --bounces 0 stops a path at the first of them).
TEST(Sky, BounceRaysSeeTheDomeNotTheSkyImage) {
  constexpr int kSide = 16;
  const CameraPose pose{glm::vec3(0.0f, 0.0f, 128.0f), 90.0f, 0.0f, 0.0f, "test"}; // straight down
  const Camera camera(pose, kSide, kSide);
  RenderSettings settings;
  settings.width = settings.height = kSide;
  settings.spp = 256;
  settings.threads = 2;
  settings.integrator.mode = LightingMode::Physical;
  settings.integrator.bounces = 0;
  const auto floorSum = [&](const Level& level) {
    const RenderImage image = renderCpu(level.render, camera, settings);
    glm::dvec3 sum(0.0);
    for (int y = 4; y < 12; ++y)
      for (int x = 4; x < 12; ++x) sum += glm::dvec3(image.beauty[size_t(y) * kSide + x]);
    return sum;
  };

  const glm::dvec3 dark = floorSum(*loadSkyLevel(/*lights=*/false));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(dark[c], 0.0) << "channel " << c << ": no dome, yet the sky lit the floor";

  constexpr double kDome = 100.0;
  const std::unique_ptr<Level> domed = loadSkyLevel(/*lights=*/false, kDome);
  const double albedo = srgbToLinear(128.0f / 255.0f); // the floor's grey (generate.py)
  // The dome's radiance (lighting/README.md, "Physical mode"): value x _range x k / 128.
  const double dome = kDome * domed->render.world.range * BT_PHYSICAL_DISPLAY_MATCH / BT_PHYSICAL_LIGHT_UNIT;
  double expected = 0.0;
  constexpr int kStrata = 64;
  for (int y = 4; y < 12; ++y)
    for (int x = 4; x < 12; ++x) {
      const Ray ray = camera.ray(x + 0.5f, y + 0.5f);
      const glm::dvec3 p = glm::dvec3(ray.origin) - glm::dvec3(ray.direction) * (double(ray.origin.z) / ray.direction.z);
      int through = 0;
      for (int i = 0; i < kStrata; ++i)
        for (int j = 0; j < kStrata; ++j) { // Malley's method: a stratified disc lifted onto the hemisphere
          const double r = std::sqrt((i + 0.5) / kStrata), phi = 2.0 * 3.14159265358979 * (j + 0.5) / kStrata;
          const glm::dvec3 w(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - r * r)));
          const glm::dvec3 q = p + w * (256.0 / w.z); // where it meets the ceiling's plane
          through += std::abs(q.x) < 256.0 && std::abs(q.y) < 256.0;
        }
      expected += albedo * dome * through / double(kStrata * kStrata);
    }
  const glm::dvec3 lit = floorSum(*domed);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(lit[c], expected, 0.02 * expected) << "channel " << c;
  EXPECT_GT(expected, 0.0);
}

// The baked sky's addressing (lighting/sky.h, the same arithmetic as shaders/sky.glsl): the
// direction through a texel's centre reads that texel on every face, corners included; each face
// holds its axis's directions; a zero direction reads a texel rather than a NaN's.
TEST(Sky, SkyMapTexelCentresReadTheirOwnTexels) {
  constexpr int kSize = 256;
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int face = 0; face < 6; ++face)
    for (int j = 0; j < kSize; j += 17)
      for (int i : {0, 1, 100, kSize - 2, kSize - 1, j}) {
        const glm::ivec3 texel(i, j, face);
        const glm::vec3 dir = skyMapTexelDirection(texel, kSize);
        EXPECT_EQ(skyMapTexel(dir * 3.0f, kSize), texel) << "face " << face << " texel " << i << "," << j;
        EXPECT_GT(glm::dot(dir, axes[face]), 0.99f * glm::length(dir) / std::sqrt(3.0f)) << "face " << face;
      }
  const glm::ivec3 zero = skyMapTexel(glm::vec3(0.0f), kSize);
  EXPECT_TRUE(zero.x >= 0 && zero.x < kSize && zero.y >= 0 && zero.y < kSize && zero.z >= 0 && zero.z < 6);
}

// A level without sky images bakes nothing: its sky faces show their own texture, and the GL
// tracer binds a one-texel sky it never reads.
TEST(Sky, LevelWithoutSkyImagesBakesNoSky) {
  test::BoxSceneBuilder b;
  b.material("sky_plain", 90, 30, 150);
  b.room({-256, -256, -256}, {256, 256, 256}, "sky_plain");
  const Scene scene = b.build();
  ASSERT_FALSE(scene.sky.has_value());
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  EXPECT_EQ(rs.sky.size, 0);
  EXPECT_TRUE(rs.sky.texels.empty());
}

// The sky box level (maps/sky/id1/: its six images in the game folder's gfx/env/).
std::unique_ptr<Level> loadSkyBoxLevel() {
  auto level = std::make_unique<Level>();
  level->scene = importScene((test::mapsDir() / "sky" / "id1" / "maps" / "sky_box.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, {}, diagnostics);
  return level;
}

// The engine's sky box, written out from what a player sees: each image stands on its side of
// the box upright and unmirrored, as seen from inside facing that side (the walls with +z up; up
// and dn as seen facing +x, then looking up or down). `left` and `up` are the world directions
// of the image's left and top. (QuakeSpasm Sky_DrawSkyBox: rt on +x, lf on -x, bk on +y, ft on
// -y.) The images are one colour each with a white top left quarter (generate.py).
struct BoxSide {
  glm::vec3 forward, left, up;
  glm::dvec3 colour;
};
const BoxSide kBoxSides[6] = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {200, 0, 0}},    // rt
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 200, 0}},   // bk
    {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, 200}},  // lf
    {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}, {200, 200, 0}}, // ft
    {{0, 0, 1}, {0, 1, 0}, {-1, 0, 0}, {0, 200, 200}}, // up
    {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}, {200, 0, 200}}, // dn
};

// The colour the engine shows along dir; nullopt within a texel of a quarter's edge, where
// the filter blends the white quarter into the side's colour.
std::optional<glm::dvec3> engineSkyBox(const glm::vec3& dir) {
  const BoxSide* side = &kBoxSides[0];
  for (const BoxSide& s : kBoxSides)
    if (glm::dot(dir, s.forward) > glm::dot(dir, side->forward)) side = &s;
  const float depth = glm::dot(dir, side->forward);
  const float left = glm::dot(dir, side->left) / depth, up = glm::dot(dir, side->up) / depth; // -1..1 across the side
  if (std::abs(left) < 0.3f || std::abs(up) < 0.3f) return std::nullopt;
  const glm::dvec3 shown = left > 0.0f && up > 0.0f ? glm::dvec3(255.0) : side->colour;
  return glm::dvec3(srgbToLinear(float(shown.x / 255.0)), srgbToLinear(float(shown.y / 255.0)), srgbToLinear(float(shown.z / 255.0)));
}

TEST(Sky, SkyBoxIsReadFromTheGameFolder) {
  const auto level = loadSkyBoxLevel();
  ASSERT_TRUE(level->scene.sky.has_value());
  EXPECT_EQ(level->scene.sky->kind, Sky::Kind::Box);
  EXPECT_EQ(level->scene.sky->name, "testsky");
  EXPECT_EQ(level->scene.materials[level->scene.sky->firstMaterial].name, "gfx/env/testskyrt.tga");
}

// A sky box whose images the game folder lacks: one warning naming every file tried, and the sky
// stays Quake's two layers.
TEST(Sky, MissingSkyBoxWarnsOnceAndKeepsTheLayers) {
  const std::filesystem::path install = std::filesystem::path(::testing::TempDir()) / "bt_sky_missing";
  std::filesystem::create_directories(install / "id1" / "maps");
  std::ifstream in(test::mapsDir() / "sky" / "id1" / "maps" / "sky_box.map");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("\"testsky\""), 9, "\"nosuch\"");
  text.replace(text.find("../../sky_layers.wad"), 20, (test::mapsDir() / "sky" / "sky_layers.wad").string());
  std::ofstream(install / "id1" / "maps" / "missing.map") << text;
  const Scene scene = importScene((install / "id1" / "maps" / "missing.map").string(), ImportOptions{});
  ASSERT_TRUE(scene.sky.has_value());
  EXPECT_EQ(scene.sky->kind, Sky::Kind::QuakeLayers);
  size_t warnings = 0;
  for (const Diagnostic& d : scene.diagnostics) {
    if (d.message.find("sky box") == std::string::npos) continue;
    ++warnings;
    for (const char* suffix : {"rt", "bk", "lf", "ft", "up", "dn"})
      for (const char* extension : {".tga", ".pcx"})
        EXPECT_NE(d.message.find(std::string("gfx/env/nosuch") + suffix + extension), std::string::npos) << d.message;
  }
  EXPECT_EQ(warnings, 1u);
  std::filesystem::remove_all(install);
}

// Looking along each axis, every sky pixel shows the side of the box the engine puts there, the
// right way up and round.
void expectEnginesSkyBox(const Level& level) {
  const std::pair<float, float> views[] = {{0, 0}, {0, 90}, {0, 180}, {0, 270}, {-90, 0}, {90, 0}}; // pitch, yaw
  for (const auto& [pitch, yaw] : views) {
    const CameraPose pose{glm::vec3(0.0f), pitch, yaw, 0.0f, "test"};
    RenderSettings settings;
    settings.width = kWidth;
    settings.height = kHeight;
    settings.spp = 1;
    settings.threads = 2;
    const Camera camera(pose, kWidth, kHeight);
    const RenderImage image = renderCpu(level.render, camera, settings);
    size_t checked = 0, wrong = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = size_t(y) * kWidth + x;
        if (!isSky(level, image.face[i])) continue;
        const auto expected = engineSkyBox(glm::normalize(camera.ray(x + 0.5f, y + 0.5f).direction));
        if (!expected) continue;
        ++checked;
        const glm::dvec3 got(image.albedo[i]);
        if (glm::length(got - *expected) > 1e-3 && wrong++ < 3)
          ADD_FAILURE() << "pitch " << pitch << " yaw " << yaw << ", pixel " << x << "," << y << ": " << got.x << " " << got.y << " "
                        << got.z << ", the engine's " << expected->x << " " << expected->y << " " << expected->z;
      }
    EXPECT_EQ(wrong, 0u) << "pitch " << pitch << " yaw " << yaw;
    EXPECT_GT(checked, size_t(kWidth * kHeight) / 4) << "pitch " << pitch << " yaw " << yaw;
  }
}

TEST(Sky, AlbedoOfSkyPixelsIsTheEnginesSkyBox) {
  expectEnginesSkyBox(*loadSkyBoxLevel());
}

// The same level in a Half-Life and a Quake 2 game folder, which name the box by their own keys
// and keep its images in their own folders (README's table: `skyname` and gfx/env/, `sky` and
// env/): the same box, seen the same way.
TEST(Sky, HalfLifeAndQuake2SkyBoxesAreReadFromTheirFolders) {
  const std::filesystem::path source = test::mapsDir() / "sky";
  const std::string_view suffixes[6] = {"rt", "bk", "lf", "ft", "up", "dn"};
  for (const auto& [baseDir, key, envDir] : {std::tuple<std::string, std::string, std::string>{"valve", "skyname", "gfx/env"},
                                             std::tuple<std::string, std::string, std::string>{"baseq2", "sky", "env"}}) {
    const std::filesystem::path install = std::filesystem::temp_directory_path() / ("bt_sky_" + baseDir + std::to_string(::getpid()));
    std::filesystem::create_directories(install / baseDir / "maps");
    std::filesystem::create_directories(install / baseDir / envDir);
    for (std::string_view suffix : suffixes) {
      const std::string file = "testsky" + std::string(suffix) + ".tga";
      std::filesystem::copy_file(source / "id1/gfx/env" / file, install / baseDir / envDir / file);
    }
    std::filesystem::copy_file(source / "sky_layers.wad", install / "sky_layers.wad"); // the map's "../../sky_layers.wad"
    std::ifstream in(source / "id1/maps/sky_box.map");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text.replace(text.find("\"sky\" \"testsky\""), 15, "\"" + key + "\" \"testsky\"");
    const std::filesystem::path map = install / baseDir / "maps" / "sky_box.map";
    std::ofstream(map) << text;
    auto level = std::make_unique<Level>();
    level->scene = importScene(map.string(), ImportOptions{});
    std::error_code ec;
    std::filesystem::remove_all(install, ec);
    ASSERT_TRUE(level->scene.sky.has_value()) << baseDir;
    EXPECT_EQ(level->scene.sky->kind, Sky::Kind::Box) << baseDir;
    EXPECT_EQ(level->scene.materials[level->scene.sky->firstMaterial].name, envDir + "/testskyrt.tga") << baseDir;
    Diagnostics diagnostics;
    level->render = buildRenderScene(level->scene, {}, diagnostics);
    SCOPED_TRACE(baseDir);
    expectEnginesSkyBox(*level);
  }
}

// ---- Quake 3: skyParms -----------------------------------------------------------------------

// A Quake 3 game folder in a temporary directory: scripts/sky.shader with `shaderText`, and the
// far box env/test/test_{rt,...}.tga, each side 2x2 of its kBoxSides colour with a white top left
// texel (so the box's orientation shows as in the Quake test above).
struct Quake3Game {
  std::filesystem::path dir;
  explicit Quake3Game(const std::string& shaderText, bool withBox = true) {
    dir = std::filesystem::temp_directory_path() / ("bt_q3sky_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir / "scripts");
    std::filesystem::create_directories(dir / "env/test");
    std::ofstream(dir / "scripts/sky.shader") << shaderText;
    const char* suffixes[6] = {"rt", "bk", "lf", "ft", "up", "dn"};
    for (int i = 0; withBox && i < 6; ++i) {
      const glm::dvec3& c = kBoxSides[i].colour;
      // An uncompressed true-colour TGA, rows from the top (descriptor 0x20), texels in BGR.
      std::vector<unsigned char> tga = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 24, 0x20};
      for (int t = 0; t < 4; ++t) {
        const bool white = t == 0;
        tga.insert(tga.end(),
                   {white ? uint8_t(255) : uint8_t(c.z), white ? uint8_t(255) : uint8_t(c.y), white ? uint8_t(255) : uint8_t(c.x)});
      }
      std::ofstream(dir / "env/test" / (std::string("test_") + suffixes[i] + ".tga"), std::ios::binary)
          .write(reinterpret_cast<const char*>(tga.data()), std::streamsize(tga.size()));
    }
  }
  ~Quake3Game() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

// A Quake 3 room whose every face is the sky shader textures/skies/test (SURF_SKY, as q3map2
// writes the shader's surfaceparm sky), its sky read from `game` as the .bsp importer reads it.
std::unique_ptr<Level> quake3SkyRoom(const Quake3Game& game) {
  test::BoxSceneBuilder b;
  b.material("textures/skies/test", 90, 30, 150);
  b.room({-256, -256, -256}, {256, 256, 256}, "textures/skies/test");
  auto level = std::make_unique<Level>();
  level->scene = b.build();
  level->scene.game = "quake3";
  level->scene.format = "ibsp46";
  for (Face& face : level->scene.faces) face.surface = SurfaceAttributes{0, 0x4, 0.0}; // SURF_SKY
  bsp::GameFiles files;
  files.addGameDir(game.dir);
  const bsp::Quake3Shaders shaders = bsp::readQuake3Shaders(files, level->scene.diagnostics);
  bsp::resolveQuake3Materials(level->scene.materials, shaders, files, level->scene.diagnostics);
  // The stage names no image file: the material keeps its image, stripes of two colours a
  // texel wide whose mean, (60, 60, 80), no face shows where the texture is mapped on it.
  Image& stripes = level->scene.materials[0].baseColor;
  for (size_t i = 0; i < stripes.rgba.size() / 4; ++i)
    if (i % 2) std::copy_n(std::array<uint8_t, 3>{30, 90, 10}.begin(), 3, stripes.rgba.begin() + ptrdiff_t(i * 4));
  bsp::loadQuake3Sky(level->scene, files, shaders);
  Diagnostics diagnostics;
  level->render = buildRenderScene(level->scene, {}, diagnostics);
  return level;
}

// Every sky pixel of the six axis views against `expected` (nullopt: not checked).
template <class Expected> void expectSkyPixels(const Level& level, const Expected& expected) {
  const std::pair<float, float> views[] = {{0, 0}, {0, 90}, {0, 180}, {0, 270}, {-90, 0}, {90, 0}}; // pitch, yaw
  for (const auto& [pitch, yaw] : views) {
    const Camera camera(CameraPose{glm::vec3(0.0f), pitch, yaw, 0.0f, "test"}, kWidth, kHeight);
    RenderSettings settings;
    settings.width = kWidth;
    settings.height = kHeight;
    settings.spp = 1;
    settings.threads = 2;
    const RenderImage image = renderCpu(level.render, camera, settings);
    size_t checked = 0, wrong = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = size_t(y) * kWidth + x;
        const std::optional<glm::dvec3> want = expected(glm::normalize(camera.ray(x + 0.5f, y + 0.5f).direction));
        if (!want) continue;
        ++checked;
        const glm::dvec3 got(image.albedo[i]);
        if (glm::length(got - *want) > 1e-3 && wrong++ < 3)
          ADD_FAILURE() << "pitch " << pitch << " yaw " << yaw << ", pixel " << x << "," << y << ": " << got.x << " " << got.y << " "
                        << got.z << ", ioquake3's " << want->x << " " << want->y << " " << want->z;
      }
    EXPECT_EQ(wrong, 0u) << "pitch " << pitch << " yaw " << yaw;
    EXPECT_GT(checked, size_t(kWidth * kHeight) / 16) << "pitch " << pitch << " yaw " << yaw;
  }
}

// ioquake3 draws the far box with the tables of Quake's (tr_sky.c MakeSkyVec, sky_texorder), each
// side clamped to its edge: a 2x2 image's texels fill the side's quarters, blended only within
// half the side's width of its centre lines.
TEST(Sky, Quake3FarBoxIsTheSkyShadersSkyParms) {
  const Quake3Game game("textures/skies/test\n{\n  surfaceparm sky\n  skyParms env/test/test 512 -\n  {\n    map $whiteimage\n  }\n}\n");
  const auto level = quake3SkyRoom(game);
  ASSERT_TRUE(level->scene.sky.has_value());
  EXPECT_EQ(level->scene.sky->kind, Sky::Kind::BoxClamped);
  EXPECT_EQ(level->scene.sky->name, "env/test/test");
  EXPECT_EQ(level->scene.materials[level->scene.sky->firstMaterial + 1].name, "env/test/test_bk.tga");
  expectSkyPixels(*level, [](const glm::vec3& dir) -> std::optional<glm::dvec3> {
    const BoxSide* side = &kBoxSides[0];
    for (const BoxSide& s : kBoxSides)
      if (glm::dot(dir, s.forward) > glm::dot(dir, side->forward)) side = &s;
    const float depth = glm::dot(dir, side->forward);
    const float left = glm::dot(dir, side->left) / depth, up = glm::dot(dir, side->up) / depth;
    if (std::abs(left) < 0.55f || std::abs(up) < 0.55f) return std::nullopt; // within the filter's blend
    const glm::dvec3 shown = left > 0.0f && up > 0.0f ? glm::dvec3(255.0) : side->colour;
    return glm::dvec3(srgbToLinear(float(shown.x / 255.0)), srgbToLinear(float(shown.y / 255.0)), srgbToLinear(float(shown.z / 255.0)));
  });
}

// Without a far box ("-"), or with one whose images are missing (one warning naming them), the
// sky is the mean colour of the shader's image in every direction.
TEST(Sky, Quake3SkyWithoutFarBoxIsTheShadersMeanColour) {
  for (const char* farbox : {"-", "env/nosuch/nosuch"}) {
    SCOPED_TRACE(farbox);
    const Quake3Game game(std::string("textures/skies/test\n{\n  skyParms ") + farbox + " 512 -\n}\n", /*withBox=*/false);
    const auto level = quake3SkyRoom(game);
    ASSERT_TRUE(level->scene.sky.has_value());
    size_t warnings = 0;
    for (const Diagnostic& d : level->scene.diagnostics)
      warnings += d.message.find("sky box 'env/nosuch/nosuch'") != std::string::npos &&
          d.message.find("env/nosuch/nosuch_dn.tga") != std::string::npos;
    EXPECT_EQ(warnings, farbox[0] == '-' ? 0u : 1u);
    const glm::dvec3 mean(srgbToLinear(60.0f / 255.0f), srgbToLinear(60.0f / 255.0f), srgbToLinear(80.0f / 255.0f));
    expectSkyPixels(*level, [&](const glm::vec3&) { return std::optional<glm::dvec3>(mean); });
  }
}

} // namespace
} // namespace bt
