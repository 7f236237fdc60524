// The engine rules on every shared level: LibreQuake's show no trigger and no opaque fence, and
// the Quake 2, Half-Life and Quake 3 levels (../shared, Debian's OpenArena) open at a camera
// inside the level that looks at something drawn.
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/cpu/integrator.h"
#include "lighting/render_scene.h"
#include "tests/test_data.h"

#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace bt {
namespace {

namespace fs = std::filesystem;

RenderScene prepare(const Scene& scene) {
  Diagnostics diagnostics;
  RenderSceneOptions options;
  options.bounceLights = false;
  return buildRenderScene(scene, options, diagnostics);
}

bool isTrigger(const Scene& scene, const Face& face) {
  return scene.entities[scene.brushes[face.brush].entity].classname().starts_with("trigger_");
}

std::vector<std::string> libreQuakeMaps() {
  std::vector<std::string> maps;
  if (auto shared = test::sharedDir())
    for (const auto& entry : fs::recursive_directory_iterator(*shared / "maps/librequake/lq1/maps/src"))
      if (entry.path().extension() == ".map") maps.push_back(entry.path().string());
  std::sort(maps.begin(), maps.end());
  return maps;
}

class LibreQuakeLevel : public testing::TestWithParam<std::string> {};

// Every face of a trigger is hidden and every `{` face with a texture is alpha-tested with holes
// in its texture; from the level's camera, no pixel shows a trigger and every fence in view
// shows what is behind it somewhere.
TEST_P(LibreQuakeLevel, ShowsNoTriggerAndNoOpaqueFence) {
  BT_REQUIRE_SHARED(shared);
  ImportOptions options;
  for (const auto& dir : fs::directory_iterator(shared / "maps/librequake/texture-wads"))
    if (dir.is_directory()) options.textures.textureDirs.push_back(dir.path().string());
  const Scene scene = importScene(GetParam(), options);
  const RenderScene rs = prepare(scene);
  size_t triggers = 0, fences = 0;
  for (size_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (isTrigger(scene, face)) {
      ++triggers;
      EXPECT_TRUE(rs.faceFlags[f] & kFaceHidden) << face.texture << " line " << face.line;
    }
    if (!face.texture.starts_with("{") || scene.materials[face.material].missing()) continue;
    ++fences;
    EXPECT_TRUE(rs.faceFlags[f] & kFaceMasked) << face.texture << " line " << face.line;
    const Image& image = scene.materials[face.material].baseColor;
    size_t clear = 0;
    for (size_t i = 3; i < image.rgba.size(); i += 4) clear += image.rgba[i] == 0;
    EXPECT_GT(clear, 0u) << face.texture << " has no see-through texel";
  }
  const RenderImage image = renderAovsCpu(rs, Camera(defaultCameraPose(scene), 160, 90), 160, 90, 2);
  for (uint32_t f : image.face) ASSERT_FALSE(f != 0 && isTrigger(scene, scene.faces[f - 1])) << "a trigger is drawn";
  RecordProperty("triggerFaces", int(triggers));
  RecordProperty("fenceFaces", int(fences));
}

INSTANTIATE_TEST_SUITE_P(Shared, LibreQuakeLevel, testing::ValuesIn(libreQuakeMaps()), [](const auto& info) {
  std::string name = fs::path(info.param).stem().string();
  std::replace(name.begin(), name.end(), '-', '_'); // gtest names: letters, digits, _
  return name;
});
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(LibreQuakeLevel);

// The default camera is inside the level's bounds, in no solid brush, and its view's centre
// sees a drawn face. Above the bounds by up to a player's eye height counts as inside: many
// compiler test maps are a floor with the player start on it and nothing overhead.
void expectCameraInside(const Scene& scene) {
  const RenderScene rs = prepare(scene);
  const CameraPose pose = defaultCameraPose(scene);
  SCOPED_TRACE(scene.sourcePath + " camera " + formatCameraPose(pose) + " from " + pose.source);
  const dvec3 p(pose.origin);
  constexpr double kEyeAboveTheTop = 64.0;
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(p[a], scene.bounds.min[a]);
    EXPECT_LT(p[a], scene.bounds.max[a] + (a == 2 ? kEyeAboveTheTop : 0.0));
  }
  const std::vector<BrushContents> contents = brushContents(scene);
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    if (contents[b] != BrushContents::Solid) continue;
    bool inside = true;
    for (uint32_t f = scene.brushes[b].firstFace; inside && f < scene.brushes[b].firstFace + scene.brushes[b].faceCount; ++f)
      inside = scene.faces[f].plane.distanceTo(p) < 0.0;
    EXPECT_FALSE(inside) << "inside the solid brush of line " << scene.brushes[b].line;
  }
  const Camera camera(pose, 64, 64);
  const SurfaceHit hit = traceVisible(rs, camera.ray(32.0f, 32.0f));
  EXPECT_TRUE(hit.found) << "the view's centre sees nothing";
}

TEST(DefaultCamera, EverySharedQuake2AndHalfLifeLevelOpensInside) {
  BT_REQUIRE_SHARED(shared);
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(shared / "oracle/lit-games/manifest.json"));
  ImportOptions options;
  options.textures.load = false;
  size_t levels = 0;
  for (const auto& entry : manifest) {
    // One brush whose only drawn face looks down, out of the level: no point of it sees a face.
    if (entry["bsp"].get<std::string>().find("q2_light_divzero") != std::string::npos) continue;
    const Scene scene = importScene((shared / "oracle/lit-games" / entry["bsp"].get<std::string>()).string(), options);
    expectCameraInside(scene);
    ++levels;
  }
  EXPECT_GE(levels, 83u);
}

TEST(DefaultCamera, SharedQuake3LevelsOpenInside) {
  BT_REQUIRE_SHARED(shared);
  ImportOptions options;
  options.textures.load = false;
  for (const char* map : {"unvanquished-plat23/maps/plat23.map", "unvanquished-chasm/maps/chasm.map"})
    expectCameraInside(importScene((shared / "maps" / map).string(), options));
}

TEST(DefaultCamera, OpenArenaLevelsOpenInside) {
  const fs::path game = "/usr/share/games/openarena/baseoa";
  if (!fs::exists(game / "pak1-maps.pk3"))
    GTEST_SKIP() << game << " has no levels: install Debian's openarena-085-data (scripts/install-deps.sh --with-test-data)";
  ImportOptions options;
  options.textures.load = false;
  for (const char* level : {"pak1-maps.pk3:maps/oa_dm1.bsp", "pak1-maps.pk3:maps/oa_ctf2.bsp", "pak6-patch085.pk3:maps/am_underworks.bsp"})
    expectCameraInside(importScene((game / level).string(), options));
}

} // namespace
} // namespace bt
