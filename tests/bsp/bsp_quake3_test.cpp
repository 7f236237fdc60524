// Quake 3 (IBSP 46) levels from Debian's openarena-085-data, read straight out of the .pk3.
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/coplanar_index.h"
#include "importers/bsp/pk3.h"
#include "importers/bsp/q3_textures.h"
#include "importers/import.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <unistd.h>

namespace {

const std::filesystem::path kGameDir = "/usr/share/games/openarena/baseoa";
const std::filesystem::path kLevels = kGameDir / "pak6-patch085.pk3";

#define REQUIRE_OPENARENA()                                                                                                                \
  if (!std::filesystem::exists(kLevels))                                                                                                   \
  GTEST_SKIP() << kLevels                                                                                                                  \
               << " not found: install Debian's openarena-085-data (scripts/install-deps.sh "                                              \
                  "--with-test-data)"

bool openArenaInstalled() {
  return std::filesystem::exists(kLevels);
}

std::vector<std::string> levelNames() {
  std::vector<std::string> out;
  for (const std::string& name : bt::bsp::Pk3Archive(kLevels).names())
    if (name.rfind("maps/", 0) == 0 && name.size() > 4 && name.substr(name.size() - 4) == ".bsp") out.push_back(name);
  return out;
}

bool isToolTexture(std::string_view name) {
  return name == "noshader" || name.find("common/") != std::string_view::npos || name.find("system/") != std::string_view::npos;
}

double area(const std::vector<glm::dvec3>& w) {
  glm::dvec3 sum{0.0};
  for (size_t k = 1; k + 1 < w.size(); ++k) sum += glm::cross(w[k] - w[0], w[k + 1] - w[0]);
  return glm::length(sum) * 0.5;
}

TEST(Quake3, AllTwelveOpenArenaLevelsImportTexturedFromThePk3) {
  REQUIRE_OPENARENA();
  const auto names = levelNames();
  ASSERT_EQ(names.size(), 12u);
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const bt::Scene scene = bt::importScene(kLevels.string() + ":" + name, bt::ImportOptions{});
    EXPECT_EQ(scene.format, "ibsp46");
    ASSERT_NE(scene.worldspawn(), nullptr);
    EXPECT_GT(scene.worldspawn()->brushCount, 100u);
    // Walls are textured: of the surface area not painted with tool shaders (clip, caulk,
    // portals), at most 1% uses a placeholder.
    double shown = 0.0, placeholder = 0.0;
    for (const bt::Face& face : scene.faces) {
      if (isToolTexture(face.texture)) continue;
      const double a = area(face.winding);
      shown += a;
      if (scene.materials[face.material].missing()) placeholder += a;
    }
    EXPECT_GT(shown, 0.0);
    EXPECT_LE(placeholder, 0.01 * shown) << placeholder << " of " << shown;
    for (const bt::Brush& brush : scene.brushes)
      for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
        for (const auto& p : scene.faces[f].winding)
          for (uint32_t g = brush.firstFace; g < brush.firstFace + brush.faceCount; ++g)
            ASSERT_LE(scene.faces[g].plane.distanceTo(p), 0.02) << "brush not convex";
  }
}

// Every OpenArena level with a sky face gets its sky from the sky shader (loadQuake3Sky): a far
// box of six images from env/ in pak0.pk3 where its skyParms names one that is there, else the
// shader image's mean colour.
TEST(Quake3, OpenArenaLevelsTakeTheirSkyFromTheSkyShader) {
  REQUIRE_OPENARENA();
  size_t withSky = 0, farBoxes = 0;
  for (const std::string& name : levelNames()) {
    SCOPED_TRACE(name);
    const bt::Scene scene = bt::importScene(kLevels.string() + ":" + name, bt::ImportOptions{});
    const bool skyFace =
        std::any_of(scene.faces.begin(), scene.faces.end(), [](const bt::Face& f) { return f.surface && (f.surface->flags & 0x4); });
    if (!skyFace) continue;
    ++withSky;
    ASSERT_TRUE(scene.sky.has_value());
    EXPECT_EQ(scene.sky->kind, bt::Sky::Kind::BoxClamped);
    ASSERT_LE(scene.sky->firstMaterial + 6, scene.materials.size());
    const std::string& rt = scene.materials[scene.sky->firstMaterial].name;
    if (rt.rfind("env/", 0) != 0) continue;
    ++farBoxes;
    EXPECT_NE(rt.find("_rt."), std::string::npos) << rt;
    for (int i = 0; i < 6; ++i) EXPECT_GT(scene.materials[scene.sky->firstMaterial + i].baseColor.width, 1) << i;
  }
  EXPECT_GT(withSky, 0u);
  EXPECT_GT(farBoxes, 0u);
}

// The frame solved for a brush side reproduces the texture coordinates of the draw triangles
// lying on it (up to whole texture repeats, which q3map2 subtracts per surface).
TEST(Quake3, SideFramesReproduceDrawVertexTextureCoordinates) {
  REQUIRE_OPENARENA();
  const std::string path = kLevels.string() + ":maps/ps37ctf2.bsp";
  const bt::Scene scene = bt::importScene(path, bt::ImportOptions{});
  const auto bytes = bt::bsp::Pk3Archive(kLevels).read("maps/ps37ctf2.bsp");
  ASSERT_TRUE(bytes);
  const bt::bsp::BspFile bsp = bt::bsp::readBspFile(*bytes, path);

  bt::bsp::CoplanarIndex sides;
  for (uint32_t f = 0; f < scene.faces.size(); ++f) sides.add(scene.faces[f].plane, scene.faces[f].winding, f);

  size_t checked = 0, wrong = 0;
  const auto& world = bsp.models[0];
  for (int32_t i = 0; i < world.faceCount; ++i) {
    const auto& s = bsp.surfaces[static_cast<size_t>(world.firstFace + i)];
    if (s.type != bt::bsp::SurfaceType::Planar) continue;
    for (int32_t k = 0; k + 2 < s.indexCount; k += 3) {
      std::array<const bt::bsp::DrawVertex*, 3> v;
      for (int c = 0; c < 3; ++c)
        v[c] = &bsp.drawVertices[static_cast<size_t>(s.firstVertex + bsp.drawIndices[static_cast<size_t>(s.firstIndex + k + c)])];
      std::vector<glm::dvec3> tri{glm::dvec3(v[0]->position), glm::dvec3(v[1]->position), glm::dvec3(v[2]->position)};
      const glm::dvec3 n = glm::normalize(glm::dvec3(s.lightmapVecs[2]));
      if (glm::dot(glm::cross(tri[1] - tri[0], tri[2] - tri[0]), n) < 0.0) std::swap(tri[1], tri[2]);
      if (area(tri) < 1.0) continue;
      const auto hit = sides.bestOverlap({n, glm::dot(n, tri[0])}, tri);
      if (!hit) continue; // a surface on no brush side (a model, a patch cap)
      const bt::Face& face = scene.faces[*hit];
      if (face.texture != bsp.shaders[static_cast<size_t>(s.shader)].name) continue;
      const bt::Material& m = scene.materials[face.material];
      ++checked;
      for (const auto* vertex : v) {
        const glm::dvec3 p(vertex->position);
        const double ds = face.frame.s(p) / m.width - vertex->st.x;
        const double dt = face.frame.t(p) / m.height - vertex->st.y;
        if (std::abs(ds - std::round(ds)) > 0.01 || std::abs(dt - std::round(dt)) > 0.01) {
          ++wrong;
          break;
        }
      }
    }
  }
  EXPECT_GT(checked, 500u);
  EXPECT_LE(wrong, checked / 50) << wrong << " of " << checked;
}

// skyParms' first argument, read at the shader's top level only; "-" is no far box, and a
// commented-out line is no skyParms.
TEST(Quake3, ShaderScriptsNameTheirSkyBox) {
  const auto boxes = bt::bsp::parseShaderSkyBoxes(R"(
textures/skies/Space
{
  surfaceparm sky
  // skyparms env/old/old - -
  SKYPARMS env/space1 512 -
  { map textures/skies/stars.tga }
}
textures/skies/clouds
{
  skyParms - 512 -
}
textures/base/wall
{
  { map textures/base/wall.tga }
}
)");
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_EQ(boxes.at("textures/skies/space"), "env/space1");
  EXPECT_EQ(boxes.at("textures/skies/clouds"), "");
}

TEST(Quake3, ShaderScriptsNameTheirImage) {
  const auto images = bt::bsp::parseShaderImages(R"(
// comment { not a brace }
textures/a/first
{
    qer_editorimage textures/a/editor.tga
    { map $lightmap
      rgbGen identity }
    {
        map textures/a/base.jpg
        blendFunc filter
    }
}
textures/a/editoronly{ qer_editorimage "textures/a/only.tga" surfaceparm nodraw }
textures/a/anim
{
	{
		animMap 10 textures/a/f1.tga textures/a/f2.tga
	}
}
)");
  ASSERT_EQ(images.size(), 3u);
  EXPECT_EQ(images.at("textures/a/first"), "textures/a/base.jpg");
  EXPECT_EQ(images.at("textures/a/editoronly"), "textures/a/only.tga");
  EXPECT_EQ(images.at("textures/a/anim"), "textures/a/f1.tga");
}

// The viewer reloads when a shader script or an image it named is saved: resolveQuake3Materials
// lists the files it read, loose ones by path and those in a .pk3 by the archive.
TEST(Quake3, ResolvingMaterialsListsTheScriptsAndImagesItRead) {
  namespace fs = std::filesystem;
  const fs::path game = fs::temp_directory_path() / ("bt_q3files_" + std::to_string(::getpid()));
  fs::create_directories(game / "scripts");
  fs::create_directories(game / "textures/a");
  std::ofstream(game / "scripts/a.shader") << "textures/a/wall\n{\n  { map textures/a/stone.tga }\n}\n";
  // A 1x1 uncompressed true-colour TGA: 18-byte header, one BGR texel.
  const unsigned char tga[] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 24, 0, 10, 20, 30};
  std::ofstream(game / "textures/a/stone.tga", std::ios::binary).write(reinterpret_cast<const char*>(tga), sizeof tga);
  std::ofstream(game / "textures/a/other.tga", std::ios::binary).write(reinterpret_cast<const char*>(tga), sizeof tga);
  bt::bsp::GameFiles files;
  files.addGameDir(game);
  if (openArenaInstalled()) files.addArchive(kLevels);
  std::vector<bt::Material> materials(1);
  materials[0].name = "textures/a/wall";
  bt::Diagnostics diagnostics;
  std::vector<std::string> read;
  bt::bsp::resolveQuake3Materials(materials, files, diagnostics, &read);
  EXPECT_FALSE(materials[0].missing());
  EXPECT_NE(std::find(read.begin(), read.end(), (game / "scripts/a.shader").string()), read.end());
  EXPECT_NE(std::find(read.begin(), read.end(), (game / "textures/a/stone.tga").string()), read.end());
  EXPECT_EQ(std::find(read.begin(), read.end(), (game / "textures/a/other.tga").string()), read.end());
  if (openArenaInstalled()) {
    EXPECT_NE(std::find(read.begin(), read.end(), kLevels.string()), read.end()) << "the .pk3's own scripts";
  }
  std::error_code ec;
  fs::remove_all(game, ec);
}

TEST(Pk3, ArchivePathsSplitAtTheArchiveExtension) {
  const auto split = bt::bsp::splitArchivePath("dir/pak0.PK3:maps/q3dm1.bsp");
  ASSERT_TRUE(split);
  EXPECT_EQ(split->archive, "dir/pak0.PK3");
  EXPECT_EQ(split->entry, "maps/q3dm1.bsp");
  EXPECT_FALSE(bt::bsp::splitArchivePath("maps/e1m1.bsp"));
}

TEST(Pk3, GarbageArchiveAndMissingEntryAreImportErrors) {
  const auto dir = std::filesystem::temp_directory_path() / "brushtrace_bsp_pk3_test";
  std::filesystem::create_directories(dir);
  const auto garbage = dir / "garbage.pk3";
  std::ofstream(garbage, std::ios::binary) << "PK\x03\x04 this is not really a zip file";
  try {
    bt::importScene(garbage.string() + ":maps/x.bsp", bt::ImportOptions{});
    ADD_FAILURE() << "no ImportError";
  } catch (const bt::ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open archive"), std::string::npos) << e.what();
  }
  REQUIRE_OPENARENA();
  try {
    bt::importScene(kLevels.string() + ":maps/nosuchlevel.bsp", bt::ImportOptions{});
    ADD_FAILURE() << "no ImportError";
  } catch (const bt::ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("no such file in the archive"), std::string::npos) << e.what();
  }
}

} // namespace
