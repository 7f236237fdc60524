// Entity models in both tracers: maps/models/oa_items.map (generate.py there) with OpenArena's
// item models (Debian's openarena-085-data, /usr/share/games/openarena), placed by the Quake 3
// classname table. The pixels where a model is show its texture, in the CPU tracer and, pixel
// for pixel, in the GL tracer. Skips, saying why, where OpenArena is not installed.
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"
#include "scene/color.h"
#include "tests/gl/test_scenes.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_precision.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>

namespace bt::gl {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 64;
const std::filesystem::path kOpenArena = "/usr/share/games/openarena";

Scene importItems() {
  ImportOptions options;
  options.textures.game.game = "quake3";
  options.textures.game.baseDir = kOpenArena.string();
  return importScene((test::mapsDir() / "models" / "oa_items.map").string(), options);
}

// From the spawn, a little above it and looking down at the items.
CameraPose itemsView() {
  CameraPose pose;
  pose.origin = glm::vec3(-64.0f, 4.0f, 56.0f);
  pose.pitch = 20.0f;
  return pose;
}

struct Renders {
  RenderImage cpu, gpu;
};

Renders renderAovs(const Scene& scene) {
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  Renders r;
  r.cpu = renderAovsCpu(rs, Camera(itemsView(), kWidth, kHeight), kWidth, kHeight, 2);
  RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  GlContext& context = test::sharedGlContext();
  static const auto programs = std::make_shared<TracerPrograms>(context, test::textureModeUnderTest());
  const int errorsBefore = context.debugErrorCount();
  r.gpu = renderWithGl(context, rs, itemsView(), settings, programs, {}, GlRenderParts::AovsOnly).image;
  EXPECT_EQ(context.debugErrorCount(), errorsBefore);
  return r;
}

bool onModel(const Scene& scene, uint32_t pixelFace) {
  if (pixelFace == 0) return false;
  for (const Mesh& m : scene.meshes)
    if (m.kind == MeshKind::Model && pixelFace - 1 >= m.firstFace && pixelFace - 1 < m.firstFace + m.faceCount) return true;
  return false;
}

#define REQUIRE_OPENARENA()                                                                                                                \
  if (!std::filesystem::is_directory(kOpenArena / "baseoa"))                                                                               \
  GTEST_SKIP() << kOpenArena << "/baseoa not installed (Debian openarena-085-data)"

TEST(GlEntityModels, OpenArenaItemsArePlacedWithTheirTextures) {
  REQUIRE_OPENARENA();
  const Scene scene = importItems();
  // Each item with its md3's shader (medium_cross.md3 names OpenArena's "mediumCross" shader,
  // rocketl.md3 its skin image), loaded from the pk3s.
  std::vector<std::string> placed;
  for (const Mesh& m : scene.meshes) {
    if (m.kind != MeshKind::Model) continue;
    const Material& material = scene.materials[scene.faces[m.firstFace].material];
    placed.push_back(std::string(scene.entities[m.entity].classname()) + " " + material.name);
    EXPECT_FALSE(material.missing()) << material.name << " should come from OpenArena's pk3";
  }
  EXPECT_NE(std::find(placed.begin(), placed.end(), "item_health mediumCross"), placed.end());
  EXPECT_NE(std::find(placed.begin(), placed.end(), "weapon_rocketlauncher models/weapons2/rocketl/skin"), placed.end());
}

// Each model material recoloured to a colour of its own: every pixel on a model shows exactly
// its material's colour, in both tracers, and the models cover a good part of the view.
TEST(GlEntityModels, EveryModelPixelShowsItsMaterialInBothTracers) {
  REQUIRE_OPENARENA();
  Scene scene = importItems();
  std::vector<bool> isModelMaterial(scene.materials.size(), false);
  for (const Mesh& m : scene.meshes)
    if (m.kind == MeshKind::Model) isModelMaterial[scene.faces[m.firstFace].material] = true;
  auto colourOf = [](size_t m) { return glm::u8vec3(uint8_t(40 + 50 * (m % 4)), uint8_t(200 - 30 * (m % 5)), uint8_t(90 + 20 * (m % 7))); };
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    if (!isModelMaterial[m]) continue;
    Image& image = scene.materials[m].baseColor;
    for (size_t i = 0; i + 3 < image.rgba.size(); i += 4) {
      const glm::u8vec3 c = colourOf(m);
      image.rgba[i] = c.r, image.rgba[i + 1] = c.g, image.rgba[i + 2] = c.b, image.rgba[i + 3] = 255;
    }
  }
  const Renders r = renderAovs(scene);
  size_t modelPixels = 0;
  for (size_t i = 0; i < r.cpu.face.size(); ++i)
    for (const RenderImage* image : {&r.cpu, &r.gpu}) {
      if (!onModel(scene, image->face[i])) continue;
      modelPixels += image == &r.cpu;
      const glm::u8vec3 c = colourOf(scene.faces[image->face[i] - 1].material);
      const glm::vec3 expected(srgbToLinear(c.r / 255.0f), srgbToLinear(c.g / 255.0f), srgbToLinear(c.b / 255.0f));
      EXPECT_LT(glm::length(image->albedo[i] - expected), 2e-3f) << (image == &r.cpu ? "CPU" : "GL") << " pixel " << i;
    }
  EXPECT_GT(modelPixels, r.cpu.face.size() / 40) << "the camera should see the items";
}

// With their own textures: the GL tracer sees the same model faces as the CPU tracer and the
// same albedo there, and the albedo is the texture's (it varies over the model: not one colour,
// not the floor's).
TEST(GlEntityModels, TexturedModelsMatchTheCpu) {
  REQUIRE_OPENARENA();
  const Scene scene = importItems();
  const Renders r = renderAovs(scene);
  size_t cpuModel = 0, gpuModel = 0, same = 0, close = 0;
  glm::vec3 lo(1e9f), hi(-1e9f);
  for (size_t i = 0; i < r.cpu.face.size(); ++i) {
    cpuModel += onModel(scene, r.cpu.face[i]);
    gpuModel += onModel(scene, r.gpu.face[i]);
    if (!onModel(scene, r.cpu.face[i])) continue;
    lo = glm::min(lo, r.cpu.albedo[i]);
    hi = glm::max(hi, r.cpu.albedo[i]);
    if (r.gpu.face[i] != r.cpu.face[i]) continue;
    ++same;
    close += glm::length(r.gpu.albedo[i] - r.cpu.albedo[i]) < 2e-3f;
  }
  EXPECT_GT(cpuModel, r.cpu.face.size() / 40);
  EXPECT_NEAR(double(gpuModel), double(cpuModel), cpuModel * 0.02 + 2);
  EXPECT_GE(same, cpuModel * 95 / 100) << same << " of " << cpuModel;
  EXPECT_GE(close, same * 99 / 100) << close << " of " << same;
  EXPECT_GT(glm::length(hi - lo), 0.05f) << "a texture, not one colour";
}

} // namespace
} // namespace bt::gl
