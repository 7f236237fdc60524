// loadMaterials: search order, name spellings, palettes, companion maps, missing textures.
#include "importers/textures/missing_textures.h"
#include "importers/textures/textures.h"
#include "tests/test_data.h"
#include "tests/textures/texture_fixtures.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

namespace bt {
namespace {

namespace fs = std::filesystem;
using test::makeScene;

const Material& material(const Scene& scene, std::string_view name) {
  const auto index = scene.findMaterial(name);
  EXPECT_TRUE(index) << name;
  return scene.materials.at(index.value_or(0));
}

// The warnings whose text mentions `needle`.
int warningsMentioning(const Scene& scene, std::string_view needle) {
  int n = 0;
  for (const Diagnostic& d : scene.diagnostics) n += d.severity == Severity::Warning && d.message.find(needle) != std::string::npos;
  return n;
}

std::vector<uint8_t> solid(int width, int height, int channels, std::initializer_list<uint8_t> value) {
  std::vector<uint8_t> pixels;
  for (int i = 0; i < width * height; ++i) pixels.insert(pixels.end(), value.begin(), value.end());
  EXPECT_EQ(static_cast<int>(value.size()), channels);
  return pixels;
}

bool endsWith(const std::string& s, std::string_view suffix) {
  return s.ends_with(suffix);
}

TEST(TextureNames, EngineAndLibreQuakeSpellingsAreAllTried) {
  const auto stems = textureFileStems("*water1");
  EXPECT_EQ(stems.front(), "*water1");
  for (const char* s : {"#water1", "star_water1", "star_water1_fbr"}) EXPECT_NE(std::find(stems.begin(), stems.end(), s), stems.end()) << s;
  const auto button = textureFileStems("+0button");
  EXPECT_NE(std::find(button.begin(), button.end(), "plus_0button"), button.end());
  const auto back = textureFileStems("star_lava");
  EXPECT_NE(std::find(back.begin(), back.end(), "*lava"), back.end());
  EXPECT_EQ(textureFileStems("e1u1/floor1_3").front(), "e1u1/floor1_3");
  const auto q3 = textureFileStems("textures/base_wall/concrete");
  EXPECT_NE(std::find(q3.begin(), q3.end(), "base_wall/concrete"), q3.end());
  EXPECT_TRUE(textureNamesEqual("*WATER1", "*water1"));
  EXPECT_FALSE(textureNamesEqual("water1", "water"));
}

TEST(LoadMaterials, MissingTexturesGetACheckerAndOneWarningNamingThemAll) {
  test::TempDir dir;
  Scene scene = makeScene(dir / "level.map", {}, {"rock1", "*slime0", "+0door"});
  scene.materials[2].width = 128; // a size the .bsp importer knew from the miptex header
  scene.materials[2].height = 32;
  loadMaterials(scene, TextureSearch{});
  ASSERT_EQ(test::countWarnings(scene), 1) << test::describe(scene.diagnostics);
  const std::string& message = scene.diagnostics[0].message;
  for (const char* name : {"rock1", "*slime0", "+0door"}) EXPECT_NE(message.find(name), std::string::npos) << message;
  EXPECT_EQ(scene.diagnostics[0].file, (dir / "level.map").string());
  for (const Material& m : scene.materials) {
    EXPECT_TRUE(m.missing());
    EXPECT_EQ(m.baseColor.width, m.width);
    EXPECT_EQ(m.baseColor.height, m.height);
    EXPECT_EQ(m.baseColor.rgba, checkerPlaceholder(m.width, m.height).rgba);
  }
  EXPECT_EQ(scene.materials[0].width, 64);
  EXPECT_EQ(scene.materials[2].baseColor.width, 128);
  EXPECT_EQ(scene.materials[2].baseColor.height, 32);
}

TEST(LoadMaterials, NoTextureLoadingLeavesPlaceholdersWithoutWarnings) {
  BT_REQUIRE_SHARED(shared);
  Scene scene = makeScene(shared / "maps/ericw-tools/testmaps/x.map", {{"wad", "deprecated/fence.wad"}}, {"{trigger"});
  TextureSearch search;
  search.load = false;
  loadMaterials(scene, search);
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
  EXPECT_TRUE(scene.materials[0].missing());
  EXPECT_FALSE(scene.materials[0].baseColor.empty());
}

// ericw-tools' test maps name their WADs relative to the map; one of them is not shipped.
TEST(LoadMaterials, WadKeyIsRelativeToTheMapAndMissingWadsAreWarnings) {
  BT_REQUIRE_SHARED(shared);
  const fs::path testmaps = shared / "maps/ericw-tools/testmaps";
  Scene scene = makeScene(testmaps / "q1_cube.map", {{"wad", "deprecated/free_wad.wad;deprecated/fence.wad"}}, {"{TRIGGER"});
  TextureSearch search;
  search.palette = (shared / "maps/palettes/quake.lmp").string();
  loadMaterials(scene, search);
  const Material& m = material(scene, "{trigger");
  EXPECT_EQ(m.source, TextureSource::Wad2);
  EXPECT_EQ(m.name, "{TRIGGER") << "the map's spelling is kept";
  EXPECT_TRUE(endsWith(m.sourcePath, "fence.wad")) << m.sourcePath;
  EXPECT_EQ(m.width, 64);
  EXPECT_EQ(test::countWarnings(scene), 1) << test::describe(scene.diagnostics);
  EXPECT_EQ(warningsMentioning(scene, "free_wad.wad"), 1) << test::describe(scene.diagnostics);
}

// No Quake palette anywhere: the built-in one draws WAD2 textures (no placeholder because no
// palette was passed), and one warning says so.
TEST(LoadMaterials, QuakeWadWithoutPaletteUsesTheBuiltInPaletteAndSaysSo) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  // A 32x16 texture in a WAD2 in a folder without any palette up the tree (the temp dir).
  test::writeFile(dir / "tex.wad",
                  test::makeWad("WAD2", {{"brick", 0x44, test::makeMiptex("brick", 32, 16, std::vector<uint8_t>(512, 4))}}));
  Scene scene = makeScene(dir / "level.map", {{"wad", "tex.wad"}}, {"brick", "gone"});
  loadMaterials(scene, TextureSearch{});
  const Material& brick = material(scene, "brick");
  ASSERT_FALSE(brick.missing());
  EXPECT_EQ(brick.width, 32);
  EXPECT_EQ(brick.height, 16);
  const std::vector<uint8_t> quake = test::readFile(shared / "maps/palettes/quake.lmp");
  EXPECT_EQ(brick.baseColor.rgba[0], quake[4 * 3]);
  EXPECT_EQ(brick.baseColor.rgba[1], quake[4 * 3 + 1]);
  ASSERT_EQ(test::countWarnings(scene), 2) << test::describe(scene.diagnostics);
  EXPECT_EQ(warningsMentioning(scene, "built-in Quake palette"), 1);
  for (const Diagnostic& d : scene.diagnostics)
    if (d.message.find("not found") != std::string::npos) {
      EXPECT_NE(d.message.find("gone"), std::string::npos);
      EXPECT_EQ(d.message.find("brick"), std::string::npos) << d.message;
    }
}

// A game dir: id1/gfx/palette.lmp, the map in id1/maps/, the WAD named with a Windows path that
// only resolves by its file name in the game dir.
TEST(LoadMaterials, FindsThePaletteInTheGameDirAndWadsByFileName) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  fs::create_directories(dir / "id1/gfx");
  fs::copy_file(shared / "maps/palettes/quake.lmp", dir / "id1/gfx/palette.lmp");
  fs::copy_file(shared / "maps/ericw-tools/testmaps/deprecated/fence.wad", dir / "id1/fence.wad");
  Scene scene = makeScene(dir / "id1/maps/level.map", {{"wad", "c:\\quake\\id1\\fence.wad"}}, {"{trigger"});
  loadMaterials(scene, TextureSearch{});
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
  EXPECT_EQ(material(scene, "{trigger").source, TextureSource::Wad2);
}

TEST(LoadMaterials, CommandLineWadsComeBeforeTheWadKey) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  const fs::path ours = dir / "ours.wad";
  test::writeFile(ours, test::makeWad("WAD2", {{"clip", 0x44, test::makeMiptex("clip", 16, 16, std::vector<uint8_t>(256, 9))}}));
  Scene scene =
      makeScene(shared / "maps/librequake/texture-wads/level.map", {{"wad", "lq_dev_legacy/lq_dev_legacy.wad"}}, {"clip", "skip"});
  TextureSearch search;
  search.wads = {ours.string()};
  search.palette = (shared / "maps/palettes/quake.lmp").string();
  loadMaterials(scene, search);
  EXPECT_EQ(material(scene, "clip").sourcePath, ours.string());
  EXPECT_EQ(material(scene, "clip").width, 16);
  EXPECT_TRUE(endsWith(material(scene, "skip").sourcePath, "lq_dev_legacy.wad"));
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
}

TEST(LoadMaterials, HalfLifeWadsResolveByFileNameBesideTheMap) {
  BT_REQUIRE_SHARED(shared);
  const fs::path deprecated = shared / "maps/ericw-tools/testmaps/deprecated";
  Scene scene = makeScene(deprecated / "hl_level.map", {{"wad", "\\sierra\\half-life\\valve\\hlwad.wad"}}, {"hltest", "!LiquidTest"});
  loadMaterials(scene, TextureSearch{});
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
  EXPECT_EQ(material(scene, "hltest").source, TextureSource::Wad3);
  EXPECT_EQ(material(scene, "!liquidtest").source, TextureSource::Wad3);
}

// LibreQuake's maps name WADs that its repository keeps as PNG folders (texture-wads/lq_tech/);
// the palette is lq1/gfx/palette.lmp, up the tree from the map.
TEST(LoadMaterials, LibreQuakeMapsFindTheirTexturesInTheUnpackedWadFolders) {
  BT_REQUIRE_SHARED(shared);
  const fs::path lq = shared / "maps/librequake";
  Scene scene = makeScene(lq / "lq1/maps/src/dm/lqdm8.map",
                          {{"wad",
                            "../../../../texture-wads/lq_tech.wad;../../../../texture-wads/lq_liquidsky.wad;"
                            "../../../../texture-wads/lq_utility.wad"}},
                          {"aqpipe13", "T_METALSHEETB", "*tele3", "+atlight1", "clip", "{char_0", "no_such_texture"});
  loadMaterials(scene, TextureSearch{});
  ASSERT_EQ(test::countWarnings(scene), 1) << test::describe(scene.diagnostics);
  EXPECT_NE(scene.diagnostics[0].message.find("no_such_texture"), std::string::npos);
  EXPECT_EQ(scene.diagnostics[0].message.find("aqpipe13"), std::string::npos);

  for (const char* name : {"aqpipe13", "t_metalsheetb", "*tele3", "+atlight1", "clip"}) {
    SCOPED_TRACE(name);
    const Material& m = material(scene, name);
    EXPECT_EQ(m.source, TextureSource::LooseImage);
    EXPECT_EQ(m.width, m.baseColor.width);
  }
  EXPECT_TRUE(endsWith(material(scene, "aqpipe13").sourcePath, "lq_tech/aqpipe13.png"));
  EXPECT_TRUE(endsWith(material(scene, "*tele3").sourcePath, "lq_liquidsky/star_tele3_fbr.png"));
  EXPECT_TRUE(endsWith(material(scene, "+atlight1").sourcePath, "lq_tech/plus_atlight1_fbr.png"));
  EXPECT_TRUE(endsWith(material(scene, "clip").sourcePath, "lq_utility/clip.png"));

  // "_fbr" images: texels of fullbright palette colours are emissive, with their own colour.
  const Material& light = material(scene, "+atlight1");
  ASSERT_FALSE(light.emissive.empty());
  int bright = 0;
  for (size_t i = 0; i < light.emissive.rgba.size(); i += 4) {
    const uint8_t* e = &light.emissive.rgba[i];
    if (!e[0] && !e[1] && !e[2]) continue;
    ++bright;
    EXPECT_TRUE(std::equal(e, e + 3, &light.baseColor.rgba[i])) << "texel " << i / 4;
  }
  EXPECT_GT(bright, 0);
  EXPECT_LT(bright, light.width * light.height);
  EXPECT_TRUE(material(scene, "aqpipe13").emissive.empty());
  // star_tele3_fbr.png is not drawn with Quake's palette at all: nothing to recover.
  EXPECT_TRUE(material(scene, "*tele3").emissive.empty());
}

// Every texture of these LibreQuake maps is in the PNG folders that shared/ carries (the maps
// whose WAD folders were not copied, lqdm5, e4m3 and old-start, are left out). The names come
// from the face lines: "( p ) ( p ) ( p ) NAME [ u ] [ v ] ..." (Valve 220).
TEST(LoadMaterials, EveryTextureOfLibreQuakeMapsIsFound) {
  BT_REQUIRE_SHARED(shared);
  const fs::path src = shared / "maps/librequake/lq1/maps/src";
  for (const char* map : {"dm/lqdm8.map", "dm/lqdm11.map", "dm/lqdm12.map", "dm/lqdm13.map", "e3/lq_e3m1.map", "misc/dev.map",
                          "misc/slope.map", "brushmodels/b_bh100.map"}) {
    SCOPED_TRACE(map);
    std::ifstream in(src / map);
    ASSERT_TRUE(in);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::set<std::string> names;
    std::string wadKey;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
      if (line.starts_with("\"wad\" \"")) wadKey = line.substr(7, line.rfind('"') - 7);
      const size_t axes = line.find(" [");
      const size_t points = line.rfind(") ", axes);
      if (line.starts_with("(") && axes != std::string::npos && points != std::string::npos)
        names.insert(line.substr(points + 2, axes - points - 2));
    }
    ASSERT_FALSE(wadKey.empty());
    ASSERT_GE(names.size(), 5u);

    Scene scene = makeScene(src / map, {{"wad", wadKey}}, std::vector<std::string>(names.begin(), names.end()));
    loadMaterials(scene, TextureSearch{});
    EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
    for (const Material& m : scene.materials) {
      EXPECT_FALSE(m.missing()) << m.name;
      EXPECT_EQ(m.baseColor.width, m.width) << m.name;
    }
  }
}

// LibreQuake's {char_0_fbr.png is an RGB image (no alpha) of 16x16 palette colours, 72 of them
// palette entry 255, the '{' see-through colour: exactly those turn transparent.
TEST(LoadMaterials, LooseFenceImagesWithoutAlphaKeyOutPaletteColour255) {
  BT_REQUIRE_SHARED(shared);
  const fs::path lq = shared / "maps/librequake";
  Scene scene = makeScene(lq / "lq1/maps/src/dm/test.map", {{"wad", "../../../../texture-wads/lq_dev.wad"}}, {"{char_0"});
  loadMaterials(scene, TextureSearch{});
  const Material& fence = material(scene, "{char_0");
  ASSERT_EQ(fence.source, TextureSource::LooseImage) << test::describe(scene.diagnostics);
  EXPECT_TRUE(endsWith(fence.sourcePath, "{char_0_fbr.png"));

  const Image original = loadImage(fence.sourcePath);
  ASSERT_EQ(original.rgba.size(), fence.baseColor.rgba.size());
  int transparent = 0;
  for (size_t i = 0; i < original.rgba.size(); i += 4) {
    const uint8_t* o = &original.rgba[i];
    ASSERT_EQ(o[3], 255) << "the file has no alpha";
    const bool key = o[0] == 159 && o[1] == 91 && o[2] == 83;
    EXPECT_EQ(fence.baseColor.rgba[i + 3], key ? 0 : 255) << "texel " << i / 4;
    transparent += key;
  }
  EXPECT_EQ(transparent, 72);
  EXPECT_TRUE(fence.emissive.empty()) << "colour 255 of a '{' texture is see-through, not fullbright";
}

// ericw-tools' own loose-texture test maps. qbsp's test compiles q1_loose_textures.map with
// "-path q1_loose_textures" (a game dir whose textures/ holds the images): our --textures. An
// image lying beside the map itself is not a texture folder for qbsp, nor for us.
TEST(LoadMaterials, EricwToolsLooseTextureMaps) {
  BT_REQUIRE_SHARED(shared);
  const fs::path testmaps = shared / "maps/ericw-tools/testmaps";
  Scene found = makeScene(testmaps / "q1_loose_textures.map", {{"_tb_textures", "textures"}}, {"floor_purple_c", "wall_tan_a"});
  TextureSearch search;
  search.textureDirs = {(testmaps / "q1_loose_textures/textures").string()};
  loadMaterials(found, search);
  EXPECT_TRUE(found.diagnostics.empty()) << test::describe(found.diagnostics);
  EXPECT_EQ(material(found, "wall_tan_a").source, TextureSource::LooseImage);
  EXPECT_TRUE(endsWith(material(found, "floor_purple_c").sourcePath, "q1_loose_textures/textures/floor_purple_c.png"));

  Scene ignored = makeScene(testmaps / "q1_loose_textures_ignored/q1_loose_textures_ignored.map",
                            {{"wad", "../deprecated/fence.wad;../deprecated/origin.wad"}}, {"orangestuff8"});
  loadMaterials(ignored, TextureSearch{});
  EXPECT_TRUE(material(ignored, "orangestuff8").missing());
  EXPECT_EQ(warningsMentioning(ignored, "orangestuff8"), 1) << test::describe(ignored.diagnostics);
}

TEST(LoadMaterials, LooseImagesByEngineSpellingFolderAndCase) {
  test::TempDir dir;
  test::writeImage(dir / "textures/#lava1.png", 8, 8, 3, solid(8, 8, 3, {200, 40, 0}));
  test::writeImage(dir / "textures/plus_0button.tga", 16, 8, 3, solid(16, 8, 3, {10, 20, 30}));
  test::writeImage(dir / "textures/e1u1/floor1_3.png", 4, 4, 4, solid(4, 4, 4, {1, 2, 3, 128}));
  test::writeImage(dir / "textures/e1u1/floor1_3.jpg", 4, 4, 3, solid(4, 4, 3, {9, 9, 9}));
  test::writeImage(dir / "extra/Grey.png", 2, 2, 1, solid(2, 2, 1, {77}));
  Scene scene = makeScene(dir / "level.map", {}, {"*lava1", "+0button", "E1U1/Floor1_3", "grey"});
  TextureSearch search;
  search.textureDirs = {(dir / "extra").string()};
  loadMaterials(scene, search);
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);

  const Material& lava = material(scene, "*lava1");
  EXPECT_EQ(lava.source, TextureSource::LooseImage);
  EXPECT_EQ(lava.width, 8);
  EXPECT_EQ(lava.baseColor.texel(3, 3)[0], 200);
  EXPECT_EQ(material(scene, "+0button").width, 16);
  EXPECT_EQ(material(scene, "+0button").baseColor.texel(0, 0)[2], 30);
  const Material& floor = material(scene, "e1u1/floor1_3");
  EXPECT_TRUE(endsWith(floor.sourcePath, "floor1_3.png")) << "PNG is preferred over JPG: " << floor.sourcePath;
  EXPECT_EQ(floor.baseColor.texel(1, 1)[3], 128);
  const Material& grey = material(scene, "grey");
  EXPECT_EQ(grey.baseColor.texel(1, 1)[0], 77);
  EXPECT_EQ(grey.baseColor.texel(1, 1)[2], 77);
  EXPECT_EQ(grey.baseColor.texel(1, 1)[3], 255);
}

TEST(LoadMaterials, ALooseImageReplacesATextureOfKnownSizeWithoutChangingIt) {
  test::TempDir dir;
  test::writeImage(dir / "textures/hires.png", 128, 128, 3, solid(128, 128, 3, {1, 2, 3}));
  test::writeImage(dir / "textures/plain.png", 32, 16, 3, solid(32, 16, 3, {1, 2, 3}));
  Scene scene = makeScene(dir / "level.bsp", {}, {"hires", "plain"});
  scene.materials[0].width = 32; // as a .bsp importer sets it from an external miptex's header
  scene.materials[0].height = 32;
  loadMaterials(scene, TextureSearch{});
  const Material& hires = material(scene, "hires");
  EXPECT_EQ(hires.source, TextureSource::LooseImage);
  EXPECT_EQ(hires.width, 32);
  EXPECT_EQ(hires.height, 32);
  EXPECT_EQ(hires.baseColor.width, 128) << "the image keeps its resolution";
  EXPECT_EQ(material(scene, "plain").width, 32) << "unknown size: the image's";
  EXPECT_EQ(material(scene, "plain").height, 16);
}

TEST(LoadMaterials, CompanionMapsFillNormalRoughnessMetallicAndEmissive) {
  test::TempDir dir;
  const fs::path t = dir / "textures";
  test::writeImage(t / "metal.png", 4, 4, 3, solid(4, 4, 3, {100, 100, 100}));
  test::writeImage(t / "metal_norm.png", 4, 4, 3, solid(4, 4, 3, {128, 128, 255}));
  test::writeImage(t / "metal_gloss.png", 4, 4, 1, solid(4, 4, 1, {200}));
  test::writeImage(t / "metal_metal.png", 4, 4, 1, solid(4, 4, 1, {255}));
  test::writeImage(t / "metal_luma.png", 4, 4, 3, solid(4, 4, 3, {0, 250, 0}));
  test::writeImage(t / "stone.tga", 2, 2, 3, solid(2, 2, 3, {50, 50, 50}));
  test::writeImage(t / "stone_normal.tga", 2, 2, 3, solid(2, 2, 3, {127, 127, 254}));
  test::writeImage(t / "stone_rough.png", 2, 2, 1, solid(2, 2, 1, {90}));
  test::writeImage(t / "stone_glow.png", 2, 2, 3, solid(2, 2, 3, {3, 2, 1}));
  Scene scene = makeScene(dir / "level.map", {}, {"metal", "stone"});
  loadMaterials(scene, TextureSearch{});
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);

  const Material& metal = material(scene, "metal");
  ASSERT_FALSE(metal.normal.empty());
  EXPECT_EQ(metal.normal.texel(0, 0)[2], 255);
  ASSERT_FALSE(metal.roughness.empty());
  EXPECT_EQ(metal.roughness.texel(2, 2)[0], 55) << "roughness = 1 - gloss";
  ASSERT_FALSE(metal.metallic.empty());
  EXPECT_EQ(metal.metallic.texel(0, 0)[0], 255);
  ASSERT_FALSE(metal.emissive.empty());
  EXPECT_EQ(metal.emissive.texel(0, 0)[1], 250);

  const Material& stone = material(scene, "stone");
  EXPECT_EQ(stone.normal.texel(1, 1)[2], 254);
  EXPECT_EQ(stone.roughness.texel(1, 1)[0], 90);
  EXPECT_TRUE(stone.metallic.empty());
  EXPECT_EQ(stone.emissive.texel(0, 0)[0], 3);
}

// `brushtrace view` reloads when any file the import read is saved: the WAD, the palette its
// textures needed, each loose image and each companion map; not the files it passed over.
TEST(LoadMaterials, ListsTheWadPaletteImagesAndCompanionMapsItReadAsInputFiles) {
  test::TempDir dir;
  test::writeFile(dir / "gfx/palette.lmp", std::vector<uint8_t>(768, 40));
  test::writeFile(
      dir / "base.wad",
      test::makeWad("WAD2", {{"brick", WadFile::kTypeMiptexWad2, test::makeMiptex("brick", 16, 16, std::vector<uint8_t>(256, 3))}}));
  test::writeImage(dir / "textures/metal.png", 2, 2, 3, solid(2, 2, 3, {100, 100, 100}));
  test::writeImage(dir / "textures/metal_glow.png", 2, 2, 3, solid(2, 2, 3, {0, 250, 0}));
  test::writeImage(dir / "textures/unused.png", 2, 2, 3, solid(2, 2, 3, {1, 2, 3}));
  test::writeImage(dir / "textures/unused_norm.png", 2, 2, 3, solid(2, 2, 3, {128, 128, 255}));
  Scene scene = makeScene(dir / "level.map", {{"wad", "base.wad"}}, {"brick", "metal"});
  loadMaterials(scene, TextureSearch{});
  EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
  ASSERT_EQ(material(scene, "brick").source, TextureSource::Wad2);

  std::set<fs::path> listed;
  for (const std::string& file : scene.inputFiles) listed.insert(fs::absolute(file).lexically_normal());
  EXPECT_EQ(listed.size(), scene.inputFiles.size()) << "a file listed twice";
  const std::set<fs::path> expected{dir / "base.wad", dir / "gfx/palette.lmp", dir / "textures/metal.png", dir / "textures/metal_glow.png"};
  EXPECT_EQ(listed, expected);
}

// ... and where each missing texture would have been read from, so that one that appears reloads
// the level: every spelling with every image extension in every loose folder, none for the found.
TEST(LoadMaterials, ListsWhereAMissingTextureWouldBeRead) {
  test::TempDir dir;
  test::writeImage(dir / "textures/metal.png", 2, 2, 3, solid(2, 2, 3, {100, 100, 100}));
  Scene scene = makeScene(dir / "level.map", {}, {"metal", "*Lava1"});
  loadMaterials(scene, TextureSearch{});
  const std::vector<std::string> files = missingTextureFiles(scene, TextureSearch{});
  const std::set<fs::path> listed(files.begin(), files.end());
  for (const char* file : {"textures/*lava1.png", "textures/*lava1.tga", "textures/star_lava1.png", "textures/#lava1.jpg"})
    EXPECT_TRUE(listed.count(dir / file)) << file << " not listed";
  for (const fs::path& file : listed) EXPECT_EQ(file.string().find("metal"), std::string::npos) << file << ": metal was found";
  scene.materials[0].source = TextureSource::LooseImage; // as if both were found
  scene.materials[1].source = TextureSource::LooseImage;
  EXPECT_TRUE(missingTextureFiles(scene, TextureSearch{}).empty());
}

TEST(LoadMaterials, CompanionMapsAlsoApplyToTexturesFromWads) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  fs::copy_file(shared / "maps/ericw-tools/testmaps/deprecated/hlwad.wad", dir / "hl.wad");
  test::writeImage(dir / "textures/hltest_norm.png", 2, 2, 3, solid(2, 2, 3, {128, 128, 255}));
  Scene scene = makeScene(dir / "level.map", {{"wad", "hl.wad"}}, {"hltest"});
  loadMaterials(scene, TextureSearch{});
  EXPECT_EQ(material(scene, "hltest").source, TextureSource::Wad3);
  EXPECT_FALSE(material(scene, "hltest").normal.empty());
}

TEST(LoadMaterials, Quake2WalNamesWithFoldersUseTheQuake2Palette) {
  BT_REQUIRE_SHARED(shared);
  const fs::path mapDir = shared / "maps/ericw-tools/testmaps/q2_wal_metadata";
  {
    Scene scene = makeScene(mapDir / "q2.map", {}, {"e1u1/alphamask"});
    TextureSearch search;
    search.palette = (shared / "maps/palettes/quake2.lmp").string();
    loadMaterials(scene, search);
    EXPECT_TRUE(scene.diagnostics.empty()) << test::describe(scene.diagnostics);
    const Material& m = material(scene, "e1u1/alphamask");
    EXPECT_EQ(m.source, TextureSource::Wal);
    EXPECT_EQ(m.name, "e1u1/alphamask");
    EXPECT_EQ(m.width, 64);
  }
  {
    // No Quake 2 palette anywhere up the tree: the built-in one, and a warning that says so.
    Scene scene = makeScene(mapDir / "q2.map", {}, {"e1u1/alphamask"});
    loadMaterials(scene, TextureSearch{});
    EXPECT_EQ(material(scene, "e1u1/alphamask").source, TextureSource::Wal);
    EXPECT_EQ(warningsMentioning(scene, "built-in Quake 2 palette"), 1) << test::describe(scene.diagnostics);
  }
}

// Broken WADs named by a map are warnings: the import goes on with placeholders.
TEST(LoadMaterials, MalformedWadsAreWarningsNotErrors) {
  BT_REQUIRE_SHARED(shared);
  const fs::path dir = shared / "maps/trenchbroom/lib/TbFsLib/test/fixture/fs/Wad";
  for (const char* file : {"bad_magic.wad", "too_small.wad", "directory_out_of_bounds.wad", "entry_count_too_large.wad",
                           "entry_out_of_bounds.wad", "skips_empty_entry_name.wad", "wad3_empty.wad"}) {
    SCOPED_TRACE(file);
    Scene scene = makeScene(dir / "level.map", {{"wad", file}}, {"real", "toofar"});
    TextureSearch search;
    search.palette = (shared / "maps/palettes/quake.lmp").string();
    ASSERT_NO_THROW(loadMaterials(scene, search));
    EXPECT_TRUE(material(scene, "real").missing());
    EXPECT_EQ(material(scene, "real").baseColor.width, 64);
    const bool readable = std::string_view(file) == "wad3_empty.wad";
    // One warning about the WAD (or its broken "real" lump), one listing missing textures.
    EXPECT_EQ(test::countWarnings(scene), readable ? 1 : 2) << test::describe(scene.diagnostics);
    if (!readable) {
      EXPECT_NE(scene.diagnostics[0].file.find(file), std::string::npos) << test::describe(scene.diagnostics);
    }
  }
}

// Unreadable images (garbage, a PNG cut in half) are warnings naming the file; the texture is
// then missing like any other.
TEST(LoadMaterials, BrokenImagesAreWarningsNamingTheFile) {
  test::TempDir dir;
  test::writeFile(dir / "textures/garbage.png", std::vector<uint8_t>(300, 0xAB));
  test::writeImage(dir / "whole.png", 64, 64, 3, std::vector<uint8_t>(64 * 64 * 3, 90));
  std::vector<uint8_t> png = test::readFile(dir / "whole.png");
  png.resize(png.size() / 2);
  test::writeFile(dir / "textures/halfpng.png", png);
  Scene scene = makeScene(dir / "level.map", {}, {"garbage", "halfpng"});
  ASSERT_NO_THROW(loadMaterials(scene, TextureSearch{}));
  EXPECT_TRUE(material(scene, "garbage").missing());
  EXPECT_TRUE(material(scene, "halfpng").missing());
  EXPECT_EQ(test::countWarnings(scene), 3) << test::describe(scene.diagnostics);
  EXPECT_EQ(warningsMentioning(scene, "garbage, halfpng"), 1) << test::describe(scene.diagnostics);
  const auto namesFile = [&](std::string_view file) {
    return std::count_if(scene.diagnostics.begin(), scene.diagnostics.end(), [&](const Diagnostic& d) { return d.file.ends_with(file); });
  };
  EXPECT_EQ(namesFile("garbage.png"), 1);
  EXPECT_EQ(namesFile("halfpng.png"), 1);
}

TEST(LoadMaterials, BadPaletteOptionIsAWarning) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  test::writeFile(dir / "bad.lmp", std::vector<uint8_t>(10, 0));
  Scene scene = makeScene(shared / "maps/ericw-tools/testmaps/x.map", {{"wad", "deprecated/fence.wad"}}, {"{trigger"});
  TextureSearch search;
  search.palette = (dir / "bad.lmp").string();
  ASSERT_NO_THROW(loadMaterials(scene, search));
  // Said once; the texture is then drawn with the built-in Quake palette, not as a placeholder.
  EXPECT_EQ(material(scene, "{trigger").source, TextureSource::Wad2);
  const auto namesBadPalette = [](const Diagnostic& d) { return d.file.find("bad.lmp") != std::string::npos; };
  EXPECT_EQ(std::count_if(scene.diagnostics.begin(), scene.diagnostics.end(), namesBadPalette), 1) << test::describe(scene.diagnostics);
}

} // namespace
} // namespace bt
