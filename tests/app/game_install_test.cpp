// Game installs as mappers have them (issue 15), through the built executable: levels whose WADs,
// palettes and .wal files are only inside a game's .pak, levels inside archives and by bare name,
// the wad key with a path from the mapper's machine, corrupt archives, the user's config file.
// Every archive is made here from bytes the test writes; no game data is copied.
#include "tests/app/run_command.h"
#include "tests/game/game_fixtures.h"
#include "tests/test_data.h"
#include "tests/textures/texture_fixtures.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdlib>
#include <fstream>

namespace bt {
namespace {

namespace fs = std::filesystem;
using test::brushtrace;
using test::CommandResult;
constexpr auto npos = std::string::npos;

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

// One floor brush (z from -16 to 0, 512 units square) covered by `texture`; a view straight down
// at it from 64 units sees nothing else.
std::string floorMap(const std::string& format, const std::string& wadKey, const std::string& texture) {
  const std::string tail = format == "Quake2" ? " 0 0 0 1 1 0 0 0" : " 0 0 0 1 1";
  std::string map = "// Game: test\n// Format: " + format + "\n{\n\"classname\" \"worldspawn\"\n";
  if (!wadKey.empty()) map += "\"wad\" \"" + wadKey + "\"\n";
  map += "{\n";
  for (const char* plane : {"( -256 -256 -16 ) ( -256 256 -16 ) ( -256 -256 0 )", "( -256 -256 -16 ) ( -256 -256 0 ) ( 256 -256 -16 )",
                            "( -256 -256 -16 ) ( 256 -256 -16 ) ( -256 256 -16 )", "( 256 256 0 ) ( 256 -256 0 ) ( -256 256 0 )",
                            "( 256 256 0 ) ( -256 256 0 ) ( 256 256 -16 )", "( 256 256 0 ) ( 256 256 -16 ) ( 256 -256 0 )"})
    map += std::string(plane) + " " + texture + tail + "\n";
  return map + "}\n}\n";
}

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

const std::string kFloorView = " --camera '(0 0 64) 90 0 0' --size 16x12 --aov albedo --backend cpu";

// Every pixel of an 8-bit PNG, RGB.
std::vector<std::array<int, 3>> pixels(const fs::path& png) {
  auto in = OIIO::ImageInput::open(png.string());
  if (!in) return {};
  const OIIO::ImageSpec spec = in->spec();
  std::vector<uint8_t> data(size_t(spec.width) * spec.height * spec.nchannels);
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, data.data());
  std::vector<std::array<int, 3>> out;
  for (size_t i = 0; i < data.size(); i += spec.nchannels) out.push_back({data[i], data[i + 1], data[i + 2]});
  return out;
}

// How many pixels are not `rgb` (to one 8-bit step, the sRGB round trip's rounding).
size_t pixelsOtherThan(const std::vector<std::array<int, 3>>& image, std::array<int, 3> rgb) {
  size_t wrong = 0;
  for (const auto& p : image) wrong += std::abs(p[0] - rgb[0]) > 1 || std::abs(p[1] - rgb[1]) > 1 || std::abs(p[2] - rgb[2]) > 1;
  return wrong;
}

// A 16x16 WAD2 texture of one palette index, in a WAD.
std::vector<uint8_t> wadWithWall(uint8_t index) {
  return test::makeWad("WAD2", {{"wall", 0x44, test::makeMiptex("wall", 16, 16, std::vector<uint8_t>(256, index))}});
}

// A Quake level whose WAD and palette are only inside the install's pak0.pak: with --basedir the
// floor is the WAD's colour through that palette (colour 10 of the test palette, which is no
// game's), in every pixel.
TEST(GameInstall, Quake1WadAndPaletteOnlyInsideAPak) {
  test::TempDir dir;
  test::writePak(dir / "quake/id1/pak0.pak", {{"gfx/palette.lmp", test::testPalette()}, {"gfx/test.wad", wadWithWall(10)}});
  writeText(dir / "levels/room.map", floorMap("Standard", "gfx/test.wad", "wall"));
  const CommandResult r = brushtrace("render " + quoted(dir / "levels/room.map") + " -o " + quoted(dir / "room.png") + " --basedir " +
                                     quoted(dir / "quake") + kFloorView);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto image = pixels(dir / "room.png");
  ASSERT_EQ(image.size(), 16u * 12u);
  EXPECT_EQ(pixelsOtherThan(image, {10, 245, 77}), 0u) << r.err;
  EXPECT_EQ(r.err.find("palette"), npos) << "the pak's palette was used, no built-in one: " << r.err;
}

// The same level with no palette anywhere: the built-in Quake palette draws the WAD's texture (no
// placeholder), and one warning says so.
TEST(GameInstall, Quake1WadWithoutAnyPaletteUsesTheBuiltInOne) {
  test::TempDir dir;
  test::writePak(dir / "quake/id1/pak0.pak", {{"gfx/test.wad", wadWithWall(10)}});
  writeText(dir / "levels/room.map", floorMap("Standard", "test.wad", "wall"));
  const CommandResult r = brushtrace("render " + quoted(dir / "levels/room.map") + " -o " + quoted(dir / "room.png") + " --basedir " +
                                     quoted(dir / "quake") + kFloorView);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // Quake's colour 10 is (155, 155, 155) (gfx/palette.lmp; the shared copy is checked in game_archive_tests).
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "room.png"), {155, 155, 155}), 0u) << r.err;
  EXPECT_NE(r.err.find("built-in Quake palette"), npos) << r.err;
}

// The wad key as the mapper's Windows machine wrote it; the map lies in the install's id1/maps/
// and finds its install (no --basedir), and the WAD in pak0.pak by the path below the game folder.
TEST(GameInstall, WadKeyWithAWindowsAbsolutePathFallsBackToTheGamesFiles) {
  test::TempDir dir;
  test::writePak(dir / "quake/id1/pak0.pak", {{"gfx/palette.lmp", test::testPalette()}, {"gfx/test.wad", wadWithWall(30)}});
  writeText(dir / "quake/id1/maps/win.map", floorMap("Standard", "C:\\Program Files\\Quake\\id1\\gfx\\test.wad", "wall"));
  const CommandResult r = brushtrace("render " + quoted(dir / "quake/id1/maps/win.map") + " -o " + quoted(dir / "win.png") + kFloorView);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "win.png"), {30, 225, 77}), 0u) << r.err;
}

// A Quake 2 level whose .wal files and pics/colormap.pcx are only inside baseq2/pak0.pak.
TEST(GameInstall, Quake2WalAndColormapOnlyInsideAPak) {
  test::TempDir dir;
  test::writePak(dir / "q2/baseq2/pak0.pak",
                 {{"pics/colormap.pcx", test::testPalettePcx()},
                  {"textures/e1u1/floor.wal", test::makeWal("e1u1/floor", 16, 16, std::vector<uint8_t>(256, 20))}});
  writeText(dir / "levels/q2room.map", floorMap("Quake2", "", "e1u1/floor"));
  const CommandResult r = brushtrace("render " + quoted(dir / "levels/q2room.map") + " -o " + quoted(dir / "q2.png") + " --basedir " +
                                     quoted(dir / "q2") + kFloorView);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "q2.png"), {20, 235, 77}), 0u) << r.err;
}

// --mod is searched before the base game: the mod's pak wins over id1's.
TEST(GameInstall, ModIsSearchedBeforeTheBaseGame) {
  test::TempDir dir;
  test::writePak(dir / "quake/id1/pak0.pak", {{"gfx/palette.lmp", test::testPalette()}, {"gfx/test.wad", wadWithWall(10)}});
  test::writePak(dir / "quake/mymod/pak0.pak", {{"gfx/test.wad", wadWithWall(50)}});
  writeText(dir / "levels/room.map", floorMap("Standard", "gfx/test.wad", "wall"));
  const std::string args =
      "render " + quoted(dir / "levels/room.map") + " -o " + quoted(dir / "mod.png") + " --basedir " + quoted(dir / "quake") + kFloorView;
  ASSERT_EQ(brushtrace(args + " --mod mymod").exitCode, 0);
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "mod.png"), {50, 205, 77}), 0u);
  ASSERT_EQ(brushtrace(args).exitCode, 0);
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "mod.png"), {10, 245, 77}), 0u);
}

// The user's config file remembers the install; BT_QUAKE_BASEDIR overrides it; --basedir both.
TEST(GameInstall, ConfigFileRemembersTheInstallAndTheEnvironmentOverridesIt) {
  test::TempDir dir;
  test::writePak(dir / "quake/id1/pak0.pak", {{"gfx/palette.lmp", test::testPalette()}, {"gfx/test.wad", wadWithWall(10)}});
  test::writePak(dir / "other/id1/pak0.pak", {{"gfx/palette.lmp", test::testPalette()}, {"gfx/test.wad", wadWithWall(60)}});
  writeText(dir / "levels/room.map", floorMap("Standard", "test.wad", "wall"));
  ::setenv("XDG_CONFIG_HOME", (dir / "config").c_str(), 1);
  ::unsetenv("BT_QUAKE_BASEDIR");
  const CommandResult set = brushtrace("config set quake.basedir " + quoted(dir / "quake"));
  ASSERT_EQ(set.exitCode, 0) << set.err;
  EXPECT_TRUE(fs::is_regular_file(dir / "config/brushtrace/config.json"));
  const CommandResult get = brushtrace("config get quake.basedir");
  EXPECT_EQ(get.exitCode, 0);
  EXPECT_EQ(get.out, (dir / "quake").string() + "\n");
  EXPECT_NE(brushtrace("config list").out.find("quake.basedir = " + (dir / "quake").string()), npos);
  EXPECT_EQ(brushtrace("config get quake2.basedir").exitCode, 1) << "not set";
  EXPECT_EQ(brushtrace("config set doom.basedir /x").exitCode, 2) << "no such game";

  const std::string render = "render " + quoted(dir / "levels/room.map") + " -o " + quoted(dir / "cfg.png") + kFloorView;
  ASSERT_EQ(brushtrace(render).exitCode, 0);
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "cfg.png"), {10, 245, 77}), 0u) << "the configured install";
  ::setenv("BT_QUAKE_BASEDIR", (dir / "other").c_str(), 1);
  ASSERT_EQ(brushtrace(render).exitCode, 0);
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "cfg.png"), {60, 195, 77}), 0u) << "the environment over the file";
  ASSERT_EQ(brushtrace(render + " --basedir " + quoted(dir / "quake")).exitCode, 0);
  EXPECT_EQ(pixelsOtherThan(pixels(dir / "cfg.png"), {10, 245, 77}), 0u) << "the command line over both";
  ::unsetenv("BT_QUAKE_BASEDIR");

  writeText(dir / "config/brushtrace/config.json", "{ not json");
  const CommandResult bad = brushtrace("config set quake.basedir " + quoted(dir / "quake"));
  EXPECT_EQ(bad.exitCode, 1);
  EXPECT_NE(bad.err.find((dir / "config/brushtrace/config.json").string()), npos) << bad.err;
  ::unsetenv("XDG_CONFIG_HOME");
}

TEST(GameInstall, UnknownGameIsAUsageError) {
  test::TempDir dir;
  writeText(dir / "room.map", floorMap("Standard", "test.wad", "wall"));
  const CommandResult r = brushtrace("info " + (dir / "room.map").string() + " --game doom");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("unknown game 'doom'"), npos) << r.err;
}

// `info ARCHIVE` lists the levels and textures the archive holds.
TEST(GameInstall, InfoOnAnArchiveListsItsLevelsAndTextures) {
  test::TempDir dir;
  test::writePak(dir / "pak0.pak",
                 {{"maps/e1m1.bsp", test::bytesOf("x")},
                  {"maps/e1m2.bsp", test::bytesOf("x")},
                  {"textures/e1u1/floor.wal", test::makeWal("e1u1/floor", 16, 16, std::vector<uint8_t>(256, 1))},
                  {"gfx/test.wad", wadWithWall(10)},
                  {"sound/x.wav", test::bytesOf("x")}});
  const CommandResult r = brushtrace("info " + quoted(dir / "pak0.pak") + " --json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const nlohmann::json info = nlohmann::json::parse(r.out);
  EXPECT_EQ(info["levels"], nlohmann::json({"maps/e1m1.bsp", "maps/e1m2.bsp"}));
  EXPECT_EQ(info["textures"], nlohmann::json({"textures/e1u1/floor.wal"}));
  EXPECT_EQ(info["wads"][0]["path"], "gfx/test.wad");
  EXPECT_EQ(info["wads"][0]["textures"], nlohmann::json({"wall"}));
  const CommandResult text = brushtrace("info " + quoted(dir / "pak0.pak"));
  EXPECT_NE(text.out.find("  levels    2\n    maps/e1m1.bsp\n    maps/e1m2.bsp\n"), npos) << text.out;
}

// A truncated archive and a directory entry that lies about its size: a message naming the
// archive (and the entry), exit 1 where the job cannot go on, never a crash.
TEST(GameInstall, CorruptArchivesAreClearErrors) {
  test::TempDir dir;
  std::vector<uint8_t> pak = test::makePak({{"maps/x.bsp", std::vector<uint8_t>(100, 0)}, {"gfx/test.wad", wadWithWall(10)}});
  std::vector<uint8_t> cut(pak.begin(), pak.end() - 20);
  test::writeFile(dir / "cut.pak", cut);
  CommandResult r = brushtrace("info " + quoted(dir / "cut.pak"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find((dir / "cut.pak").string() + ": error: truncated archive"), npos) << r.err;
  r = brushtrace("render " + quoted(dir / "cut.pak") + ":maps/x.bsp -o " + quoted(dir / "x.png") + " --size 8x8");
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find((dir / "cut.pak").string()), npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));

  std::vector<uint8_t> lying = pak;
  lying[lying.size() - 64 + 60 + 3] = 0x7f; // the WAD's size: 2 GB
  test::writeFile(dir / "quake/id1/pak0.pak", lying);
  test::writePak(dir / "quake/id1/pak1.pak", {{"gfx/palette.lmp", test::testPalette()}});
  r = brushtrace("info " + quoted(dir / "quake/id1/pak0.pak"));
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find((dir / "quake/id1/pak0.pak").string() + ":gfx/test.wad"), npos) << r.err;
  // In the install it is left out with that message; the level still renders, the texture missing.
  writeText(dir / "levels/room.map", floorMap("Standard", "test.wad", "wall"));
  r = brushtrace("render " + quoted(dir / "levels/room.map") + " -o " + quoted(dir / "room.png") + " --basedir " + quoted(dir / "quake") +
                 kFloorView);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.err.find((dir / "quake/id1/pak0.pak").string() + ":gfx/test.wad: warning: archive skipped"), npos) << r.err;
}

// A level inside an archive, by ARCHIVE:maps/x.bsp and by bare name with a game profile, with its
// textures from a WAD in the same pak: the level's archive is what `view` watches.
TEST(GameInstall, LevelsInsideAPakByArchivePathAndByName) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  test::writePak(dir / "quake/id1/pak0.pak",
                 {{"maps/cubes.bsp", test::readFile(shared / "oracle/maps_ericw-tools_testmaps_q1_cubes.bsp")},
                  {"gfx/palette.lmp", test::readFile(shared / "maps/palettes/quake.lmp")},
                  {"gfx/fence.wad", test::readFile(shared / "maps/ericw-tools/testmaps/deprecated/fence.wad")}});
  for (const std::string& level :
       {quoted(dir / "quake/id1/pak0.pak") + ":maps/cubes.bsp", std::string("cubes --game quake --basedir ") + quoted(dir / "quake"),
        std::string("cubes --basedir ") + quoted(dir / "quake")}) {
    SCOPED_TRACE(level);
    const CommandResult info = brushtrace("info " + level + " --json");
    ASSERT_EQ(info.exitCode, 0) << info.err;
    const nlohmann::json json = nlohmann::json::parse(info.out);
    EXPECT_EQ(json["dialect"], "bsp29");
    EXPECT_EQ(json["path"], (dir / "quake/id1/pak0.pak").string() + ":maps/cubes.bsp");
  }
  const CommandResult render = brushtrace("render cubes --basedir " + quoted(dir / "quake") + " -o " + quoted(dir / "cubes.png") +
                                          " --size 16x12 --aov albedo --backend cpu --quiet");
  ASSERT_EQ(render.exitCode, 0) << render.err;
  EXPECT_EQ(pixels(dir / "cubes.png").size(), 16u * 12u);
  const CommandResult missing = brushtrace("info e9m9 --game quake --basedir " + quoted(dir / "quake"));
  EXPECT_EQ(missing.exitCode, 1);
  EXPECT_NE(missing.err.find("e9m9: error: no such file, and no game install holds maps/e9m9.bsp"), npos) << missing.err;
}

// OpenArena as Debian packages it (openarena-085-data): the level by name, from its .pk3, with its
// textures from the install's other archives.
TEST(GameInstall, OpenArenaLevelByNameFromItsArchive) {
  const fs::path install = "/usr/share/games/openarena";
  if (!fs::exists(install / "baseoa/pak1-maps.pk3"))
    GTEST_SKIP() << "openarena-085-data not installed (scripts/install-deps.sh --with-test-data)";
  test::TempDir dir;
  const std::string level = "oa_dm1 --game quake3 --basedir " + quoted(install);
  const CommandResult info = brushtrace("info " + level + " --json");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  const nlohmann::json json = nlohmann::json::parse(info.out);
  EXPECT_EQ(json["path"], (install / "baseoa/pak1-maps.pk3").string() + ":maps/oa_dm1.bsp");
  size_t found = 0;
  for (const auto& texture : json["textures"]) found += texture["found"].get<bool>();
  EXPECT_GE(found * 10, json["textures"].size() * 9) << "nine textures in ten found: " << info.out;
  const CommandResult render =
      brushtrace("render " + level + " -o " + quoted(dir / "oa.png") + " --size 32x18 --aov albedo --backend cpu --quiet");
  ASSERT_EQ(render.exitCode, 0) << render.err;
  EXPECT_EQ(pixels(dir / "oa.png").size(), 32u * 18u);
}

} // namespace
} // namespace bt
