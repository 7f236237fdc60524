// The game file system: .pak reading, the engine's search order (mods over the base game, loose
// files over archives, later archives over earlier ones), corrupt archives, game profiles and
// the built-in palettes.
#include "importers/game/default_palettes.h"
#include "importers/game/file_system.h"
#include "importers/game/game_install.h"
#include "importers/game/game_profile.h"
#include "scene/compiled_lighting.h"
#include "tests/game/game_fixtures.h"
#include "tests/test_data.h"
#include "tests/textures/texture_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

namespace bt {
namespace {

namespace fs = std::filesystem;
using test::bytesOf;

std::string text(const std::optional<std::vector<uint8_t>>& bytes) {
  return bytes ? std::string(bytes->begin(), bytes->end()) : "<absent>";
}

void writeText(const fs::path& path, const std::string& content) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << content;
}

TEST(PakArchive, ReadsEntriesByNameIgnoringCase) {
  test::TempDir dir;
  test::writePak(dir / "pak0.pak", {{"gfx/palette.lmp", bytesOf("abc")}, {"maps/E1M1.bsp", bytesOf("level")}});
  const game::PakArchive pak(dir / "pak0.pak");
  EXPECT_EQ(pak.names(), (std::vector<std::string>{"gfx/palette.lmp", "maps/E1M1.bsp"}));
  EXPECT_EQ(text(pak.read("maps/e1m1.bsp")), "level");
  EXPECT_EQ(text(pak.read("GFX/PALETTE.LMP")), "abc");
  EXPECT_FALSE(pak.read("gfx/colormap.lmp"));
}

TEST(GameFileSystem, SearchesModThenBaseLooseBeforeArchivesLaterPaksFirst) {
  test::TempDir dir;
  const fs::path id1 = dir / "quake/id1", mod = dir / "quake/mymod";
  test::writePak(id1 / "pak0.pak",
                 {{"a.txt", bytesOf("pak0")}, {"b.txt", bytesOf("pak0")}, {"c.txt", bytesOf("pak0")}, {"only0.txt", bytesOf("pak0")}});
  test::writePak(id1 / "pak1.pak", {{"a.txt", bytesOf("pak1")}, {"b.txt", bytesOf("pak1")}});
  writeText(id1 / "b.txt", "id1 loose");
  test::writePak(mod / "pak0.pak", {{"c.txt", bytesOf("mod pak0")}, {"d.txt", bytesOf("mod pak0")}});
  writeText(mod / "d.txt", "mod loose");

  GameOptions options{.game = "quake", .baseDir = (dir / "quake").string(), .mods = {"mymod"}};
  const game::GameInstall install = game::openGameInstall(options, "", "");
  EXPECT_EQ(install.gameDirs, (std::vector<fs::path>{mod, id1}));
  EXPECT_EQ(text(install.files.read("a.txt")), "pak1") << "pak1 before pak0";
  EXPECT_EQ(text(install.files.read("b.txt")), "id1 loose") << "loose files before archives";
  EXPECT_EQ(text(install.files.read("c.txt")), "mod pak0") << "the mod before the base game";
  EXPECT_EQ(text(install.files.read("d.txt")), "mod loose");
  EXPECT_EQ(text(install.files.read("only0.txt")), "pak0");
  EXPECT_EQ(install.files.fileHolding("a.txt"), id1 / "pak1.pak");
  EXPECT_EQ(install.files.describe("c.txt"), (mod / "pak0.pak").string() + ":c.txt");
  EXPECT_FALSE(install.files.read("../quake/id1/b.txt")) << "names never climb out of the game";
}

TEST(GameFileSystem, Quake3LoadsPk3sAndPk3dirsByNameTheLaterFirst) {
  test::TempDir dir;
  const fs::path baseoa = dir / "openarena/baseoa";
  test::writePk3(baseoa / "pak0.pk3", {{"scripts/a.shader", bytesOf("pak0")}, {"x.txt", bytesOf("pak0")}});
  test::writePk3(baseoa / "zz-mine.pk3", {{"scripts/a.shader", bytesOf("zz")}});
  writeText(baseoa / "pak5.pk3dir/x.txt", "pk3dir");
  test::writePak(baseoa / "ignored.pak", {{"x.txt", bytesOf("a .pak is not Quake 3's")}});
  const game::GameInstall install = game::openGameInstall(GameOptions{.baseDir = (dir / "openarena").string()}, "", "ibsp46");
  ASSERT_NE(install.profile, nullptr);
  EXPECT_EQ(install.profile->name, "quake3");
  EXPECT_EQ(text(install.files.read("scripts/a.shader")), "zz");
  EXPECT_EQ(text(install.files.read("x.txt")), "pk3dir") << "pak5.pk3dir sorts after pak0.pk3";
}

TEST(GameFileSystem, ALevelInsideAGameFolderFindsItsInstall) {
  test::TempDir dir;
  writeText(dir / "quake/id1/maps/x.map", "{}");
  writeText(dir / "quake/ad/maps/y.map", "{}");
  const game::GameInstall base = game::openGameInstall({}, (dir / "quake/id1/maps/x.map").string(), "standard");
  ASSERT_NE(base.profile, nullptr);
  EXPECT_EQ(base.profile->name, "quake");
  EXPECT_EQ(base.gameDirs, (std::vector<fs::path>{dir / "quake/id1"}));
  const game::GameInstall mod = game::openGameInstall({}, (dir / "quake/ad/maps/y.map").string(), "valve220");
  EXPECT_EQ(mod.gameDirs, (std::vector<fs::path>{dir / "quake/ad", dir / "quake/id1"})) << "a mod beside id1";
}

TEST(PakArchive, TruncatedArchiveIsAnErrorNamingIt) {
  test::TempDir dir;
  std::vector<uint8_t> bytes = test::makePak({{"gfx/palette.lmp", std::vector<uint8_t>(768, 1)}});
  bytes.resize(bytes.size() - 10); // the directory's end is cut off
  test::writeFile(dir / "pak0.pak", bytes);
  try {
    game::PakArchive pak(dir / "pak0.pak");
    FAIL() << "a truncated archive opened";
  } catch (const ImportError& e) {
    EXPECT_EQ(e.diagnostic().file, (dir / "pak0.pak").string());
    EXPECT_NE(e.diagnostic().message.find("truncated"), std::string::npos) << e.what();
  }
  test::writeFile(dir / "short.pak", {'P', 'A', 'C'});
  EXPECT_THROW(game::PakArchive(dir / "short.pak"), ImportError);
}

TEST(PakArchive, EntryThatLiesAboutItsSizeIsAnErrorNamingArchiveAndEntry) {
  test::TempDir dir;
  std::vector<uint8_t> bytes = test::makePak({{"a.txt", bytesOf("a")}, {"textures/wall.wal", bytesOf("0123456789")}});
  const size_t sizeField = bytes.size() - 64 + 60; // the last entry's size
  bytes[sizeField + 2] = 0x10;                     // ~1 MB, in a file of a few hundred bytes
  test::writeFile(dir / "pak0.pak", bytes);
  try {
    game::PakArchive pak(dir / "pak0.pak");
    FAIL() << "an entry past the end of the file was accepted";
  } catch (const ImportError& e) {
    EXPECT_EQ(e.diagnostic().file, (dir / "pak0.pak").string() + ":textures/wall.wal");
    EXPECT_NE(e.diagnostic().message.find("lies about its size"), std::string::npos) << e.what();
  }
  // In a game folder the corrupt archive is left out with that message; the rest still loads.
  test::writePak(dir / "game/id1/pak1.pak", {{"a.txt", bytesOf("good")}});
  test::writeFile(dir / "game/id1/pak0.pak", bytes);
  const game::GameInstall install = game::openGameInstall({.game = "quake", .baseDir = (dir / "game").string()}, "", "");
  EXPECT_EQ(text(install.files.read("a.txt")), "good");
  ASSERT_EQ(install.problems.size(), 1u);
  EXPECT_EQ(install.problems[0].file, (dir / "game/id1/pak0.pak").string() + ":textures/wall.wal");
}

TEST(Pk3Archive, TruncatedArchiveIsAnErrorNamingIt) {
  test::TempDir dir;
  test::writePk3(dir / "full.pk3", {{"scripts/a.shader", std::vector<uint8_t>(4000, 'x')}});
  std::vector<uint8_t> bytes = test::readFile(dir / "full.pk3");
  bytes.resize(bytes.size() / 2);
  test::writeFile(dir / "cut.pk3", bytes);
  try {
    game::openArchive(dir / "cut.pk3");
    FAIL() << "a truncated .pk3 opened";
  } catch (const ImportError& e) {
    EXPECT_EQ(e.diagnostic().file, (dir / "cut.pk3").string());
  }
}

TEST(GameProfiles, AreChosenFromTheLevelsFormat) {
  const auto nameFor = [](std::string_view format) {
    const game::GameProfile* p = game::profileForFormat(format);
    return p ? std::string(p->name) : "none";
  };
  EXPECT_EQ(nameFor("standard"), "quake");
  EXPECT_EQ(nameFor("valve220"), "quake");
  EXPECT_EQ(nameFor("bsp29"), "quake");
  EXPECT_EQ(nameFor("hexen2"), "hexen2");
  EXPECT_EQ(nameFor("bsp30"), "halflife");
  EXPECT_EQ(nameFor("quake2-valve"), "quake2");
  EXPECT_EQ(nameFor("ibsp38"), "quake2");
  EXPECT_EQ(nameFor("ibsp46"), "quake3");
  EXPECT_EQ(nameFor("quake3"), "quake3");
  EXPECT_EQ(game::profileForBaseGame("baseoa")->name, "quake3");
  EXPECT_EQ(game::profileForBaseGame("valve")->name, "halflife");
}

// The built-in tables are the palettes the shared data carries (from the same ericw-tools source).
TEST(BuiltinPalettes, AreTheGamesPalettes) {
  BT_REQUIRE_SHARED(shared);
  for (const char* name : {"quake", "hexen2", "quake2"}) {
    SCOPED_TRACE(name);
    const std::optional<Palette> builtIn = game::builtinPalette(name);
    ASSERT_TRUE(builtIn);
    const std::vector<uint8_t> expected = test::readFile(shared / "maps/palettes" / (std::string(name) + ".lmp"));
    EXPECT_TRUE(std::equal(expected.begin(), expected.end(), builtIn->rgb.begin()));
  }
  EXPECT_FALSE(game::builtinPalette("halflife"));
}

// Each game's textures index its own palette: Hexen II's levels get Hexen II's, not Quake's.
TEST(BuiltinPalettes, AreChosenByTheLevelsGame) {
  for (const auto& [format, game] : {std::pair{"hexen2", "hexen2"}, {"standard", "quake"}, {"ibsp38", "quake2"}}) {
    SCOPED_TRACE(format);
    const game::GameInstall install = game::openGameInstall({}, "", format);
    Diagnostics diagnostics;
    std::string file = "unset";
    const std::optional<Palette> palette = game::installPalette(install, std::string_view(game) == "quake2", "x.map", diagnostics, &file);
    ASSERT_TRUE(palette);
    EXPECT_EQ(palette->rgb, game::builtinPalette(game)->rgb);
    EXPECT_TRUE(file.empty());
    ASSERT_EQ(diagnostics.size(), 1u);
    EXPECT_NE(diagnostics[0].message.find("built-in"), std::string::npos);
  }
}

// `view` reloads when a file the import read is saved: for what came out of a pak, the pak.
TEST(GameInstall, InputFilesListTheArchivesTexturesAndPalettesCameFrom) {
  test::TempDir dir;
  test::writePak(
      dir / "quake/id1/pak0.pak",
      {{"gfx/palette.lmp", test::testPalette()},
       {"gfx/test.wad", test::makeWad("WAD2", {{"wall", 0x44, test::makeMiptex("wall", 16, 16, std::vector<uint8_t>(256, 3))}})}});
  fs::create_directories(dir / "quake/id1/maps");
  std::ofstream(dir / "quake/id1/maps/x.map")
      << "{\n\"classname\" \"worldspawn\"\n\"wad\" \"test.wad\"\n{\n"
         "( 0 0 0 ) ( 0 1 0 ) ( 0 0 1 ) wall 0 0 0 1 1\n( 0 0 0 ) ( 0 0 1 ) ( 1 0 0 ) wall 0 0 0 1 1\n"
         "( 0 0 0 ) ( 1 0 0 ) ( 0 1 0 ) wall 0 0 0 1 1\n( 8 8 8 ) ( 8 0 8 ) ( 0 8 8 ) wall 0 0 0 1 1\n"
         "( 8 8 8 ) ( 0 8 8 ) ( 8 8 0 ) wall 0 0 0 1 1\n( 8 8 8 ) ( 8 8 0 ) ( 8 0 8 ) wall 0 0 0 1 1\n}\n}\n";
  const Scene scene = importScene((dir / "quake/id1/maps/x.map").string(), ImportOptions{});
  ASSERT_FALSE(scene.materials.empty());
  EXPECT_FALSE(scene.materials[0].missing()) << test::describe(scene.diagnostics);
  EXPECT_EQ(scene.materials[0].baseColor.rgba[0], 3) << "the pak's palette";
  EXPECT_NE(std::find(scene.inputFiles.begin(), scene.inputFiles.end(), (dir / "quake/id1/pak0.pak").string()), scene.inputFiles.end());
}

// A Valve 220 map is Quake's by default, but --basedir naming a Half-Life install makes it Half-Life's.
TEST(GameInstall, TheInstallsBaseFolderOverridesTheFormatsGuess) {
  test::TempDir dir;
  test::writeFile(dir / "hl/valve/halflife.wad", test::makeWad("WAD3", {}));
  const game::GameInstall install = game::openGameInstall({.baseDir = (dir / "hl").string()}, "", "valve220");
  ASSERT_NE(install.profile, nullptr);
  EXPECT_EQ(install.profile->name, "halflife");
  EXPECT_TRUE(install.files.read("halflife.wad"));
}

// Coloured light is looked up as the engine looks it up: maps/<level>.lit in the game's files.
TEST(GameInstall, LitFileOfALevelInAPakComesFromTheGamesFiles) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  const fs::path oracle = shared / "oracle/lit/maps_ericw-tools_testmaps_deprecated_suntest";
  test::writePak(dir / "quake/id1/pak0.pak", {{"maps/sun.bsp", test::readFile(oracle.string() + ".bsp")}});
  test::writeFile(dir / "quake/id1/maps/sun.lit", test::readFile(oracle.string() + ".lit"));
  ImportOptions options;
  options.textures.load = false;
  const Scene scene = importScene((dir / "quake/id1/pak0.pak").string() + ":maps/sun.bsp", options);
  ASSERT_TRUE(scene.compiledLighting);
  EXPECT_EQ(scene.compiledLighting->source, ".lit file");
  EXPECT_EQ(scene.inputFiles.front(), (dir / "quake/id1/pak0.pak").string());
  EXPECT_NE(std::find(scene.inputFiles.begin(), scene.inputFiles.end(), (dir / "quake/id1/maps/sun.lit").string()), scene.inputFiles.end());
}

} // namespace
} // namespace bt
