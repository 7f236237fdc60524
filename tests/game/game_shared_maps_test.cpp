// The shared Quake 1 maps with their WADs and palette only inside a game's pak0.pak.
#include "importers/import.h"
#include "tests/game/game_fixtures.h"
#include "tests/test_data.h"
#include "tests/textures/texture_fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>

namespace bt {
namespace {

namespace fs = std::filesystem;

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
  return b.at(at) | b.at(at + 1) << 8 | b.at(at + 2) << 16 | uint32_t{b.at(at + 3)} << 24;
}

// The textures qbsp found in WADs when it compiled a BSP29 level with -notex: the name and
// width (0 where it found none) of each miptex record of lump 2.
std::map<std::string, uint32_t> texturesQbspFound(const std::vector<uint8_t>& bsp) {
  std::map<std::string, uint32_t> found;
  const uint32_t lump = u32(bsp, 4 + 8 * 2), lumpSize = u32(bsp, 4 + 8 * 2 + 4);
  if (lumpSize == 0) return found;
  for (uint32_t i = 0, count = u32(bsp, lump); i < count; ++i) {
    const uint32_t offset = u32(bsp, lump + 4 + 4 * i);
    if (offset == 0xffffffffu) continue;
    std::string name;
    for (size_t c = 0; c < 16 && bsp.at(lump + offset + c); ++c) name.push_back(static_cast<char>(bsp[lump + offset + c]));
    found[name] = u32(bsp, lump + offset + 16);
  }
  return found;
}

// Every shared Quake 1 map, copied away from its WADs, imported with only the install (--basedir)
// naming a folder whose id1/pak0.pak this test made from the shared WADs and palette: every
// texture that qbsp found in a WAD (the oracle's sizes) is drawn from a WAD, none as a
// placeholder. The materials checked are the ones the renderer draws (and `info` reports); the
// import runs in this process, as `brushtrace render --basedir` runs it, since starting the
// executable for each of 120 maps took minutes on a loaded CI machine.
TEST(GameInstall, EverySharedQuake1MapFindsItsWadsInsideThePak) {
  BT_REQUIRE_SHARED(shared);
  test::TempDir dir;
  std::vector<test::ArchiveEntry> pak{{"gfx/palette.lmp", test::readFile(shared / "maps/palettes/quake.lmp")}};
  for (const auto& entry : fs::recursive_directory_iterator(shared / "maps"))
    if (entry.path().extension() == ".wad" && entry.path().string().find("trenchbroom") == std::string::npos)
      pak.push_back({entry.path().filename().string(), test::readFile(entry.path())});
  test::writePak(dir / "quake/id1/pak0.pak", pak);
  for (const auto& entry : fs::recursive_directory_iterator(shared / "maps"))
    if (entry.path().extension() == ".map") {
      const fs::path copy = dir / "levels" / entry.path().lexically_relative(shared);
      fs::create_directories(copy.parent_path());
      fs::copy_file(entry.path(), copy);
    }

  std::ifstream manifestFile(shared / "oracle/manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(manifestFile);
  int maps = 0, fromWads = 0;
  for (const auto& entry : manifest) {
    const std::string flags = entry.at("qbsp_flags");
    if (flags.find("-q2bsp") != std::string::npos || flags.find("-hlbsp") != std::string::npos ||
        flags.find("-hexen2") != std::string::npos)
      continue;
    const fs::path map = dir / "levels" / entry.at("map").get<std::string>();
    SCOPED_TRACE(map.string());
    ImportOptions options;
    options.textures.game.baseDir = (dir / "quake").string();
    Scene scene;
    try {
      scene = importScene(map.string(), options);
    } catch (const ImportError&) {
      continue; // maps qbsp compiled but that stop our import are the map tests' business
    }
    ++maps;
    const auto qbsp = texturesQbspFound(test::readFile(shared / "oracle" / entry.at("bsp").get<std::string>()));
    for (const Material& m : scene.materials) {
      const auto it = qbsp.find(m.name);
      if (it == qbsp.end() || it->second == 0) continue;
      ++fromWads;
      EXPECT_EQ(m.source, TextureSource::Wad2) << m.name << "\n" << test::describe(scene.diagnostics);
      EXPECT_NE(m.sourcePath.find("pak0.pak:"), std::string::npos) << m.name << " from " << m.sourcePath;
      EXPECT_EQ(m.width, static_cast<int>(it->second)) << m.name;
    }
  }
  EXPECT_GE(maps, 100);
  EXPECT_GE(fromWads, 20);
}

} // namespace
} // namespace bt
