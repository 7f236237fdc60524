// Entity models as the user sees them (importers/models): a Quake .mdl written here into a
// temporary game folder, placed by a point entity's `model` key in a room of
// maps/engine_rules/, through `importScene` and the CPU tracer: where it is, what its pixels
// show, that faithful mode casts no shadow from it and physical mode does, and that without the
// game's files nothing is added and one note says so. tests/gl holds the GL tracer to these
// pixels on an OpenArena item.
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "renderer/camera.h"
#include "renderer/cpu/cpu_renderer.h"
#include "scene/color.h"
#include "tests/game/game_fixtures.h"
#include "tests/support/alias_model_writer.h"
#include "tests/test_data.h"

#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace bt {
namespace {

namespace fs = std::filesystem;

constexpr uint8_t kSkinIndex = 100; // the test palette's (100, 155, 77)

void writeFile(const fs::path& path, const std::vector<uint8_t>& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// hidden_reference.map's room lit from (0 0 160), with two models: a wall facing the player
// start (x = 60, y -32..32, z 16..80) and, turned by "angle" 90, a roof over the floor's middle
// (x, y -32..32 at z = 112).
std::string roomWithModels() {
  std::ifstream in(test::mapsDir() / "engine_rules" / "hidden_reference.map");
  std::stringstream text;
  text << in.rdbuf();
  std::string map = text.str();
  const std::string light = "\"origin\" \"150 0 96\"";
  map.replace(map.find(light), light.size(), "\"origin\" \"0 0 160\"");
  map += "{\n\"classname\" \"misc_model\"\n\"model\" \"progs/wall.mdl\"\n\"origin\" \"60 -32 16\"\n}\n";
  map += "{\n\"classname\" \"misc_model\"\n\"model\" \"progs/roof.mdl\"\n\"origin\" \"32 -32 112\"\n\"angle\" \"90\"\n}\n";
  return map;
}

// A game folder <tmp>/q/id1 with the palette and both models, the map in its maps/; the same map
// in <tmp>/plain, outside any game.
struct Folders {
  fs::path root = fs::temp_directory_path() / ("bt_entity_models_" + std::to_string(::getpid()));
  fs::path inGame = root / "q/id1/maps/room.map";
  fs::path plain = root / "plain/room.map";
  Folders() {
    writeFile(root / "q/id1/gfx/palette.lmp", test::testPalette());
    test::TestMdl wall = test::squareMdl(64, kSkinIndex);
    for (glm::vec3& p : wall.positions) p = glm::vec3(0.0f, p.x, p.y); // the square stood up, facing -x
    writeFile(root / "q/id1/progs/wall.mdl", test::writeMdl(wall));
    writeFile(root / "q/id1/progs/roof.mdl", test::writeMdl(test::squareMdl(64, kSkinIndex)));
    const std::string map = roomWithModels();
    writeFile(inGame, std::vector<uint8_t>(map.begin(), map.end()));
    writeFile(plain, std::vector<uint8_t>(map.begin(), map.end()));
  }
  ~Folders() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
};

Scene import(const fs::path& map) {
  ImportOptions options;
  options.textures.textureDirs = {(test::mapsDir() / "engine_rules" / "textures").string()};
  return importScene(map.string(), options);
}

std::vector<const Mesh*> models(const Scene& scene) {
  std::vector<const Mesh*> found;
  for (const Mesh& m : scene.meshes)
    if (m.kind == MeshKind::Model) found.push_back(&m);
  return found;
}

RenderImage render(const Scene& scene, const CameraPose& pose, LightingMode mode, int spp) {
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.spp = spp;
  settings.seed = 3;
  settings.threads = 2;
  settings.integrator.mode = mode;
  settings.integrator.bounces = 2;
  return renderCpu(rs, Camera(pose, settings.width, settings.height), settings);
}

TEST(EntityModels, AModelKeyPlacesTheModelAtItsEntityTurnedByItsAngle) {
  const Folders folders;
  const Scene scene = import(folders.inGame);
  const std::vector<const Mesh*> placed = models(scene);
  ASSERT_EQ(placed.size(), 2u);
  EXPECT_EQ(scene.entities[placed[0]->entity].value("model"), "progs/wall.mdl");
  EXPECT_EQ(placed[0]->faceCount, 4u) << "two triangles, each two faces";
  EXPECT_EQ(placed[0]->bounds.min, dvec3(60, -32, 16));
  EXPECT_EQ(placed[0]->bounds.max, dvec3(60, 32, 80));
  // The roof's +x turned to +y: (0..64, 0..64) becomes (-64..0, 0..64), then moved.
  EXPECT_NEAR(placed[1]->bounds.min.x, -32, 1e-4);
  EXPECT_NEAR(placed[1]->bounds.max.x, 32, 1e-4);
  EXPECT_NEAR(placed[1]->bounds.min.y, -32, 1e-4);
  EXPECT_NEAR(placed[1]->bounds.max.y, 32, 1e-4);
  EXPECT_EQ(placed[1]->bounds.min.z, 112);
  const Material& skin = scene.materials[scene.faces[placed[0]->firstFace].material];
  EXPECT_EQ(skin.name, "progs/wall.mdl");
  EXPECT_EQ(skin.width, 8);
  EXPECT_TRUE(std::any_of(scene.inputFiles.begin(), scene.inputFiles.end(), [](const std::string& f) {
    return f.ends_with("progs/wall.mdl");
  })) << "view reloads when the model is saved";
}

// From the player start the wall model fills the middle of the view: every pixel there shows the
// skin's colour (the palette's index 100), not the room's wall behind it.
TEST(EntityModels, ThePixelsWhereTheModelIsShowItsSkin) {
  const Folders folders;
  const Scene scene = import(folders.inGame);
  const RenderImage image = render(scene, defaultCameraPose(scene), LightingMode::Faithful, 1);
  const glm::vec3 skin(srgbToLinear(100 / 255.0f), srgbToLinear(155 / 255.0f), srgbToLinear(77 / 255.0f));
  size_t onModel = 0;
  for (size_t i = 0; i < image.face.size(); ++i) {
    if (image.face[i] == 0) continue;
    const uint32_t face = image.face[i] - 1;
    const bool model = scene.faces[face].brush == kNoBrush;
    onModel += model;
    if (model) EXPECT_LT(glm::length(image.albedo[i] - skin), 1e-4f) << "pixel " << i;
  }
  EXPECT_GT(onModel, image.face.size() / 40) << "the camera should see the model";
  const size_t centre = size_t(image.height / 2) * size_t(image.width) + size_t(image.width / 2);
  ASSERT_NE(image.face[centre], 0u);
  EXPECT_EQ(scene.faces[image.face[centre] - 1].brush, kNoBrush) << "the middle of the view is the model";
}

// The floor under the roof model, seen from below its edge: faithful mode lights it as if the
// model were not there (ericw-tools' light casts no shadow from entities' models), physical mode
// shadows it.
TEST(EntityModels, FaithfulModeCastsNoShadowFromModelsPhysicalModeDoes) {
  const Folders folders;
  const Scene with = import(folders.inGame), without = import(folders.plain);
  ASSERT_FALSE(models(with).empty());
  ASSERT_TRUE(models(without).empty());
  CameraPose floor;
  floor.origin = glm::vec3(-150.0f, 0.0f, 24.0f);
  floor.pitch = glm::degrees(std::atan(24.0f / 150.0f)); // the middle pixel looks at (0 0 0)
  auto middle = [](const RenderImage& image) {
    glm::vec3 sum(0.0f);
    for (int y = 20; y < 28; ++y)
      for (int x = 28; x < 36; ++x) sum += image.beauty[size_t(y * image.width + x)];
    return (sum.r + sum.g + sum.b) / 64.0f;
  };
  const float faithfulWith = middle(render(with, floor, LightingMode::Faithful, 4));
  const float faithfulWithout = middle(render(without, floor, LightingMode::Faithful, 4));
  EXPECT_GT(faithfulWithout, 0.05f) << "the floor should be lit";
  EXPECT_NEAR(faithfulWith, faithfulWithout, 0.02f * faithfulWithout);
  const float physicalWith = middle(render(with, floor, LightingMode::Physical, 16));
  const float physicalWithout = middle(render(without, floor, LightingMode::Physical, 16));
  EXPECT_GT(physicalWithout, 0.0f);
  EXPECT_LT(physicalWith, 0.5f * physicalWithout) << "the roof's shadow";
}

TEST(EntityModels, WithoutTheGameFilesNothingIsAddedAndOneNoteSaysSo) {
  const Folders folders;
  const Scene scene = import(folders.plain);
  EXPECT_TRUE(models(scene).empty());
  size_t notes = 0;
  for (const Diagnostic& d : scene.diagnostics)
    if (d.message.find("entity model") != std::string::npos) {
      ++notes;
      EXPECT_EQ(d.severity, Severity::Note);
      EXPECT_NE(d.message.find("2 entity models not drawn"), std::string::npos) << d.message;
      EXPECT_NE(d.message.find("progs/wall.mdl"), std::string::npos) << d.message;
    }
  EXPECT_EQ(notes, 1u);
}

// Quake's item boxes are .bsp models: item_health with spawnflags 2 (H_MEGA) is items.qc's
// maps/b_bh100.bsp, here LibreQuake's as ericw-tools compiled it (../shared/oracle), its world
// model's faces placed at the entity. Its `skip` faces are hidden as in any level.
TEST(EntityModels, QuakeItemBoxesAreBspModelsChosenBySpawnflags) {
  BT_REQUIRE_SHARED(shared);
  const fs::path box = shared / "oracle" / "maps_librequake_lq1_maps_src_brushmodels_b_bh100.bsp";
  if (!fs::is_regular_file(box)) GTEST_SKIP() << box << " not found";
  const Folders folders;
  fs::copy_file(box, folders.root / "q/id1/maps/b_bh100.bsp");
  std::string map = roomWithModels();
  map = map.substr(0, map.find("{\n\"classname\" \"misc_model\""));
  map += "{\n\"classname\" \"item_health\"\n\"spawnflags\" \"2\"\n\"origin\" \"60 -16 16\"\n}\n";
  writeFile(folders.root / "q/id1/maps/items.map", std::vector<uint8_t>(map.begin(), map.end()));
  const Scene scene = import(folders.root / "q/id1/maps/items.map");
  const std::vector<const Mesh*> placed = models(scene);
  ASSERT_FALSE(placed.empty());
  Bounds bounds;
  for (const Mesh* m : placed) {
    EXPECT_EQ(scene.entities[m->entity].classname(), "item_health");
    EXPECT_TRUE(scene.materials[scene.faces[m->firstFace].material].name.starts_with("maps/b_bh100.bsp:"));
    bounds.grow(m->bounds);
  }
  EXPECT_LT(glm::length(bounds.min - dvec3(60, -16, 16)), 1e-3);
  EXPECT_LT(glm::length(bounds.max - dvec3(92, 16, 48)), 1e-3);
  const RenderImage image = render(scene, defaultCameraPose(scene), LightingMode::Faithful, 1);
  const size_t centre = size_t(image.height / 2) * size_t(image.width) + size_t(image.width / 2);
  ASSERT_NE(image.face[centre], 0u);
  const Face& seen = scene.faces[image.face[centre] - 1];
  EXPECT_EQ(seen.brush, kNoBrush) << "the middle of the view is the box";
  EXPECT_NE(seen.texture, "skip");
}

// q3map2's misc_model keys: modelscale_vec scales each axis, else modelscale all three; the
// Quake 3 "angles" (pitch yaw roll) turn it. Each entity here has the roof model (0..64 square).
TEST(EntityModels, MiscModelScaleAndAnglesKeys) {
  const Folders folders;
  std::string map = roomWithModels();
  map = map.substr(0, map.find("{\n\"classname\" \"misc_model\""));
  map += "{\n\"classname\" \"misc_model\"\n\"model\" \"progs/roof.mdl\"\n\"origin\" \"0 0 100\"\n"
         "\"modelscale_vec\" \"2 0.5 1\"\n\"modelscale\" \"3\"\n}\n";
  map += "{\n\"classname\" \"misc_model\"\n\"model\" \"progs/roof.mdl\"\n\"origin\" \"0 0 100\"\n\"modelscale\" \"0.5\"\n}\n";
  map += "{\n\"classname\" \"misc_model\"\n\"model\" \"progs/roof.mdl\"\n\"origin\" \"0 0 100\"\n\"angles\" \"0 0 90\"\n}\n";
  writeFile(folders.root / "q/id1/maps/scaled.map", std::vector<uint8_t>(map.begin(), map.end()));
  const Scene scene = import(folders.root / "q/id1/maps/scaled.map");
  const std::vector<const Mesh*> placed = models(scene);
  ASSERT_EQ(placed.size(), 3u);
  EXPECT_EQ(placed[0]->bounds.max, dvec3(128, 32, 100)) << "modelscale_vec wins over modelscale";
  EXPECT_EQ(placed[1]->bounds.max, dvec3(32, 32, 100));
  // Rolled 90 degrees about its forward (+x) axis: its +y (left) turns to +z.
  EXPECT_NEAR(placed[2]->bounds.max.z, 164, 1e-4);
  EXPECT_NEAR(placed[2]->bounds.max.y, 0, 1e-4);
}

// --no-textures: the models are placed, their skins are placeholders as every texture is.
TEST(EntityModels, WithoutTexturesTheModelsKeepTheirPlaceButNotTheirSkins) {
  const Folders folders;
  ImportOptions options;
  options.textures.load = false;
  const Scene scene = importScene(folders.inGame.string(), options);
  const std::vector<const Mesh*> placed = models(scene);
  ASSERT_EQ(placed.size(), 2u);
  for (const Mesh* m : placed) EXPECT_TRUE(scene.materials[scene.faces[m->firstFace].material].missing());
}

TEST(EntityModels, ACorruptModelIsAWarningNamingItAndTheLevelStillImports) {
  const Folders folders;
  std::vector<uint8_t> cut = test::writeMdl(test::squareMdl(64, kSkinIndex));
  cut.resize(cut.size() - 5);
  writeFile(folders.root / "q/id1/progs/roof.mdl", cut);
  const Scene scene = import(folders.inGame);
  EXPECT_EQ(models(scene).size(), 1u);
  bool warned = false;
  for (const Diagnostic& d : scene.diagnostics)
    warned |=
        d.severity == Severity::Warning && d.file.find("roof.mdl") != std::string::npos && d.message.find("truncated") != std::string::npos;
  EXPECT_TRUE(warned);
}

} // namespace
} // namespace bt
