// The reference compiler as oracle for WAD resolution: ericw-tools qbsp compiled every shared
// Quake 1 / Half-Life map with -notex, which keeps, for each texture, the size qbsp found in the
// map's WADs (0x0 when it found none) but no pixels. loadMaterials on the same map's "wad" key must
// find exactly those textures in WADs, with the same sizes.
#include "importers/textures/textures.h"
#include "tests/test_data.h"
#include "tests/textures/texture_fixtures.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace bt {
namespace {

namespace fs = std::filesystem;

struct CompiledTexture {
  std::string name;
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> miptex; // the whole miptex_t record as stored in the .bsp
};

uint32_t u32(const std::vector<uint8_t>& b, size_t at) {
  return b.at(at) | b.at(at + 1) << 8 | b.at(at + 2) << 16 | uint32_t{b.at(at + 3)} << 24;
}

// The miptex lump (lump 2) of a BSP29 / BSP2 / BSP30 file: int32 count, int32 offsets[count]
// (-1 for none), then the miptex records. Returns false for other formats (Quake 2 IBSP).
bool readCompiledTextures(const std::vector<uint8_t>& bsp, std::vector<CompiledTexture>& out) {
  const uint32_t version = u32(bsp, 0);
  if (version != 29 && version != 30 && version != 0x32505342 /* "BSP2" */) return false;
  const uint32_t lump = u32(bsp, 4 + 8 * 2), lumpSize = u32(bsp, 4 + 8 * 2 + 4);
  if (lumpSize == 0) return true;
  const uint32_t count = u32(bsp, lump);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t offset = u32(bsp, lump + 4 + 4 * i);
    if (offset == 0xffffffffu) continue;
    const size_t at = size_t{lump} + offset;
    CompiledTexture t;
    for (size_t c = 0; c < 16 && bsp.at(at + c); ++c) t.name.push_back(static_cast<char>(bsp[at + c]));
    t.width = u32(bsp, at + 16);
    t.height = u32(bsp, at + 20);
    t.miptex.assign(bsp.begin() + static_cast<ptrdiff_t>(at), bsp.begin() + static_cast<ptrdiff_t>(at + 40));
    if (!t.name.empty()) out.push_back(std::move(t));
  }
  return true;
}

std::string wadKeyOf(const fs::path& map) {
  std::ifstream in(map);
  for (std::string line; std::getline(in, line);) {
    const size_t key = line.find("\"wad\"");
    if (key == std::string::npos) continue;
    const size_t open = line.find('"', key + 5), close = line.rfind('"');
    if (open != std::string::npos && close > open) return line.substr(open + 1, close - open - 1);
  }
  return {};
}

TEST(Oracle, WadTexturesResolveExactlyAsQbspResolvedThem) {
  BT_REQUIRE_SHARED(shared);
  std::ifstream manifestFile(shared / "oracle/manifest.json");
  ASSERT_TRUE(manifestFile);
  const nlohmann::json manifest = nlohmann::json::parse(manifestFile);
  const Palette quake = loadPalette(shared / "maps/palettes/quake.lmp");

  int bspsChecked = 0, foundInWads = 0;
  for (const auto& entry : manifest) {
    const std::string mapPath = entry.at("map");
    // LibreQuake's WADs are not in shared/ (qbsp found none of them); its PNG folders are
    // checked by EveryTextureOfLibreQuakeMapsIsFound.
    if (mapPath.starts_with("maps/librequake/")) continue;
    const fs::path bspPath = shared / "oracle" / entry.at("bsp").get<std::string>();
    SCOPED_TRACE(bspPath.string());
    std::vector<CompiledTexture> compiled;
    if (!readCompiledTextures(test::readFile(bspPath), compiled)) continue;
    ++bspsChecked;

    std::vector<std::string> names;
    for (const CompiledTexture& t : compiled) {
      names.push_back(t.name);
      // -notex: no pixels in the .bsp, which decodeMiptex reports so the importer looks it up.
      EXPECT_THROW(decodeMiptex(t.miptex, &quake, false, t.name), ImportError) << t.name;
    }
    const fs::path map = shared / mapPath;
    Scene scene = test::makeScene(map, {{"wad", wadKeyOf(map)}}, names);
    TextureSearch search;
    search.palette = (shared / "maps/palettes/quake.lmp").string();
    ASSERT_NO_THROW(loadMaterials(scene, search));

    for (const CompiledTexture& t : compiled) {
      const Material& m = scene.materials.at(*scene.findMaterial(t.name));
      const bool fromWad = m.source == TextureSource::Wad2 || m.source == TextureSource::Wad3;
      EXPECT_EQ(fromWad, t.width > 0) << t.name << " qbsp size " << t.width << "x" << t.height << ", ours from " << toString(m.source)
                                      << " " << m.sourcePath;
      if (fromWad && t.width > 0) {
        ++foundInWads;
        EXPECT_EQ(m.width, static_cast<int>(t.width)) << t.name;
        EXPECT_EQ(m.height, static_cast<int>(t.height)) << t.name;
        EXPECT_EQ(m.source == TextureSource::Wad3, u32(test::readFile(bspPath), 0) == 30) << t.name;
      }
    }
  }
  EXPECT_GE(bspsChecked, 130);
  EXPECT_GE(foundInWads, 50);
}

} // namespace
} // namespace bt
