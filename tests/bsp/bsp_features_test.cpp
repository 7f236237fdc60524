// BSP features beyond geometry: entities, brush entity origins, lightmaps (.lit, BSPX
// RGBLIGHTING, LMSHIFT, DECOUPLED_LM), BSPX BRUSHLIST, embedded miptex (Half-Life and Quake). Where ../shared has no file with a feature, the
// test writes one by appending BSPX lumps or a miptex lump to a compiled level.
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/bsp_import.h"
#include "importers/bsp/entities.h"
#include "importers/bsp/lightmaps.h"
#include "importers/import.h"
#include "importers/textures/textures.h"
#include "scene/compiled_lighting.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace {

using Bytes = std::vector<uint8_t>;

Bytes readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::filesystem::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

uint32_t u32At(const Bytes& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, &b[at], 4);
  return v;
}
void putU32(Bytes& b, size_t at, uint32_t v) {
  std::memcpy(&b[at], &v, 4);
}
void appendU32(Bytes& b, uint32_t v) {
  b.resize(b.size() + 4);
  putU32(b, b.size() - 4, v);
}
void appendF32(Bytes& b, float f) {
  uint32_t v;
  std::memcpy(&v, &f, 4);
  appendU32(b, v);
}
void appendU16(Bytes& b, uint16_t v) {
  b.push_back(static_cast<uint8_t>(v));
  b.push_back(static_cast<uint8_t>(v >> 8));
}

// Appends a BSPX directory with the given lumps after a Quake 1 or 2 file's last lump, as
// ericw-tools writes it: 4-byte aligned, "BSPX", count, {name[24], offset, length}, then the data.
Bytes withBspx(Bytes bsp, const std::vector<std::pair<std::string, Bytes>>& lumps) {
  const bool quake2 = std::memcmp(bsp.data(), "IBSP", 4) == 0;
  const size_t table = quake2 ? 8 : 4;
  const int lumpCount = quake2 ? 19 : 15;
  size_t end = 0;
  for (int i = 0; i < lumpCount; ++i) end = std::max<size_t>(end, size_t(u32At(bsp, table + i * 8)) + u32At(bsp, table + 4 + i * 8));
  bsp.resize((end + 3) & ~size_t{3}, 0);
  const size_t directory = bsp.size();
  bsp.resize(directory + 8 + lumps.size() * 32, 0);
  std::memcpy(&bsp[directory], "BSPX", 4);
  putU32(bsp, directory + 4, static_cast<uint32_t>(lumps.size()));
  for (size_t i = 0; i < lumps.size(); ++i) {
    const size_t entry = directory + 8 + i * 32;
    std::memcpy(&bsp[entry], lumps[i].first.c_str(), lumps[i].first.size());
    putU32(bsp, entry + 24, static_cast<uint32_t>(bsp.size()));
    putU32(bsp, entry + 28, static_cast<uint32_t>(lumps[i].second.size()));
    bsp.insert(bsp.end(), lumps[i].second.begin(), lumps[i].second.end());
    bsp.resize((bsp.size() + 3) & ~size_t{3}, 0);
  }
  return bsp;
}

std::filesystem::path scratchDir() {
  const auto dir = std::filesystem::temp_directory_path() / "brushtrace_bsp_features_test";
  std::filesystem::create_directories(dir);
  return dir;
}

bt::Scene importPath(const std::filesystem::path& path, bt::ImportOptions options = {}) {
  return bt::importScene(path.string(), options);
}

// --- entities ------------------------------------------------------------------------------

TEST(BspEntities, KeysInOrderWithTheirLumpLine) {
  const auto entities = bt::bsp::parseEntities("{\n\"classname\" \"worldspawn\"\n\"wad\" \"a.wad\"\n}\n"
                                               "{\n\"classname\" \"light\"\n\"light\" \"300\"\n\"light\" \"200\"\n}\n",
                                               "x.bsp");
  ASSERT_EQ(entities.size(), 2u);
  EXPECT_EQ(entities[0].line, 1);
  EXPECT_EQ(entities[1].line, 5);
  EXPECT_EQ(entities[1].classname(), "light");
  ASSERT_EQ(entities[1].keys.size(), 3u); // duplicates kept
  EXPECT_EQ(entities[1].keys[2].second, "200");
}

TEST(BspEntities, MalformedLumpNamesLineAndColumn) {
  try {
    bt::bsp::parseEntities("{\n\"classname\" \"worldspawn\"\n}\n{\n\"origin\" \"0 0 0\n}\n", "x.bsp");
    FAIL() << "no ImportError";
  } catch (const bt::ImportError& e) {
    EXPECT_EQ(e.diagnostic().line, 5);
    EXPECT_EQ(e.diagnostic().column, 10);
    EXPECT_NE(std::string(e.what()).find("x.bsp:5:10"), std::string::npos) << e.what();
  }
  EXPECT_THROW(bt::bsp::parseEntities("{ \"a\" \"b\" ", "x.bsp"), bt::ImportError);
  EXPECT_THROW(bt::bsp::parseEntities("{ \"a\" \"b\" { } }", "x.bsp"), bt::ImportError);
  EXPECT_THROW(bt::bsp::parseEntities("\"a\" \"b\"", "x.bsp"), bt::ImportError);
}

TEST(BspEntities, BrushEntitiesSitAtTheirOrigin) {
  BT_REQUIRE_SHARED(shared);
  const auto path = shared / "oracle" / "maps_ericw-tools_testmaps_deprecated_h2rotate.bsp";
  const bt::Scene scene = importPath(path);
  const auto bsp = bt::bsp::readBspFile(path);
  size_t checked = 0;
  for (const bt::Entity& e : scene.entities) {
    const std::string* model = e.find("model");
    if (!model || (*model)[0] != '*' || !e.find("origin")) continue;
    const auto& m = bsp.models[std::stoul(model->substr(1))];
    glm::dvec3 origin;
    ASSERT_EQ(std::sscanf(e.find("origin")->c_str(), "%lf %lf %lf", &origin.x, &origin.y, &origin.z), 3);
    ASSERT_GT(e.brushCount, 0u);
    bt::Bounds bounds;
    for (uint32_t b = e.firstBrush; b < e.firstBrush + e.brushCount; ++b) bounds.grow(scene.brushes[b].bounds);
    // The model's faces are compiled around the origin; its brushes end up around the entity.
    EXPECT_NEAR(bounds.min.x, m.mins.x + origin.x, 1.0);
    EXPECT_NEAR(bounds.max.z, m.maxs.z + origin.z, 1.0);
    ++checked;
  }
  EXPECT_GT(checked, 0u);
}

// --- lightmaps -----------------------------------------------------------------------------

std::vector<std::filesystem::path> litOracle(const std::filesystem::path& shared) {
  std::vector<std::filesystem::path> out;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "oracle" / "lit"))
    if (entry.path().extension() == ".bsp") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

// ericw-tools' light writes the lightmaps one after another, each starting on a 4-byte boundary:
// a face's offset is where the previous face's styles x width x height luxels end, rounded up.
// That only holds if our extents match the light tool's.
TEST(BspLightmaps, ExtentsTileTheLightingLumpExactly) {
  BT_REQUIRE_SHARED(shared);
  const auto files = litOracle(shared);
  ASSERT_GE(files.size(), 20u);
  for (const auto& path : files) {
    SCOPED_TRACE(path.string());
    const auto bsp = bt::bsp::readBspFile(path);
    std::map<int32_t, size_t> sizeAt; // offset -> bytes
    for (size_t f = 0; f < bsp.faces.size(); ++f) {
      const auto& face = bsp.faces[f];
      if (face.lightOffset < 0) continue;
      const auto e = bt::bsp::lightmapExtents(bsp, f);
      const auto styles = std::count_if(face.styles.begin(), face.styles.end(), [](uint8_t s) { return s != 255; });
      sizeAt[face.lightOffset] = static_cast<size_t>(e.width * e.height * styles);
    }
    if (bsp.lighting.empty()) { // q1_light_invalid_delay: nothing lit, no face points anywhere
      EXPECT_TRUE(sizeAt.empty());
      continue;
    }
    size_t expected = 0;
    for (const auto& [offset, size] : sizeAt) {
      EXPECT_EQ(static_cast<size_t>(offset), (expected + 3) & ~size_t{3});
      expected = static_cast<size_t>(offset) + size;
    }
    EXPECT_LE(expected, bsp.lighting.size());
    EXPECT_GT(expected + 4, bsp.lighting.size());
  }
}

TEST(BspLightmaps, LitFileBesideTheLevelIsFound) {
  BT_REQUIRE_SHARED(shared);
  bt::ImportOptions options;
  options.textures.load = false;
  const bt::Scene scene = importPath(shared / "oracle" / "lit" / "maps_ericw-tools_testmaps_deprecated_suntest.bsp", options);
  ASSERT_TRUE(scene.compiledLighting);
  EXPECT_EQ(scene.compiledLighting->source, ".lit file");
}

TEST(BspLightmaps, LitFileGivesColourAndGreyLumpOtherwise) {
  BT_REQUIRE_SHARED(shared);
  size_t coloured = 0;
  for (const auto& path : litOracle(shared)) {
    SCOPED_TRACE(path.string());
    const auto bsp = bt::bsp::readBspFile(path);
    const auto litPath = std::filesystem::path(path).replace_extension(".lit");
    const bool hasLit = std::filesystem::exists(litPath);
    const Bytes lit = hasLit ? readBytes(litPath) : Bytes{};
    bt::Diagnostics diagnostics;
    const bt::CompiledLighting lighting =
        bt::bsp::readCompiledLighting(bsp, {{0, 0, glm::dvec3(0.0)}}, hasLit ? std::optional<Bytes>(lit) : std::nullopt, diagnostics);
    EXPECT_TRUE(diagnostics.empty());
    EXPECT_EQ(lighting.source, hasLit ? ".lit file" : "lighting lump");
    ASSERT_EQ(lighting.faces.size(), static_cast<size_t>(bsp.models[0].faceCount));
    size_t litFaces = 0;
    for (size_t f = 0; f < lighting.faces.size(); ++f) {
      const auto& face = lighting.faces[f];
      if (face.width == 0) continue;
      ++litFaces;
      // Every luxel of every style, against the raw bytes.
      const size_t offset = static_cast<size_t>(bsp.faces[f].lightOffset);
      for (size_t k = 0; k < face.rgb.size(); ++k)
        ASSERT_EQ(face.rgb[k], hasLit ? lit[8 + offset * 3 + k] : bsp.lighting[offset + k / 3]) << "face " << f;
    }
    EXPECT_EQ(litFaces > 0, !bsp.lighting.empty());
    coloured += hasLit;
  }
  EXPECT_GE(coloured, 5u);
}

TEST(BspLightmaps, BspxRgbLightingColoursLikeTheLitFile) {
  BT_REQUIRE_SHARED(shared);
  const auto source = shared / "oracle" / "lit" / "maps_ericw-tools_testmaps_deprecated_suntest.bsp";
  const Bytes lit = readBytes(std::filesystem::path(source).replace_extension(".lit"));
  ASSERT_GT(lit.size(), 8u);
  const auto path = scratchDir() / "rgblighting.bsp";
  writeBytes(path, withBspx(readBytes(source), {{"RGBLIGHTING", Bytes(lit.begin() + 8, lit.end())}}));
  const bt::Scene fromBspx = importPath(path);
  const bt::Scene fromLit = importPath(source);
  ASSERT_EQ(fromBspx.compiledLighting->source, "BSPX RGBLIGHTING");
  ASSERT_EQ(fromBspx.compiledLighting->faces.size(), fromLit.compiledLighting->faces.size());
  for (size_t f = 0; f < fromLit.compiledLighting->faces.size(); ++f)
    ASSERT_EQ(fromBspx.compiledLighting->faces[f].rgb, fromLit.compiledLighting->faces[f].rgb) << "face " << f;
}

TEST(BspLightmaps, HalfLifeAndQuake2LightingIsRgb) {
  BT_REQUIRE_SHARED(shared);
  for (const char* name : {"maps_ericw-tools_testmaps_hl_basic.bsp", "maps_ericw-tools_testmaps_q2_areaportal.bsp"}) {
    const bt::Scene scene = importPath(shared / "oracle" / name);
    ASSERT_TRUE(scene.compiledLighting);
    EXPECT_EQ(scene.compiledLighting->source, "RGB lighting lump") << name;
  }
}

// --- BSPX LMSHIFT and DECOUPLED_LM ------------------------------------------------------------
// No compiler output in ../shared has them (qbsp -lmscale / -world_units_per_luxel were not
// used), so the tests append lumps to a lit level, written the way ericw-tools writes them.

const char* const kLitLevel = "oracle/lit/maps_ericw-tools_testmaps_deprecated_suntest.bsp";

// The world's compiled lighting of a file (grey lump: no .lit is given).
bt::CompiledLighting worldLighting(const Bytes& file, bt::Diagnostics& diagnostics) {
  const auto bsp = bt::bsp::readBspFile(file, "lit.bsp");
  return bt::bsp::readCompiledLighting(bsp, {{0, 0, glm::dvec3(0.0)}}, std::nullopt, diagnostics);
}

size_t styleCount(const bt::bsp::Face& face) {
  return static_cast<size_t>(std::count_if(face.styles.begin(), face.styles.end(), [](uint8_t s) { return s != 255; }));
}

// The luxel coordinates a face's projection gives a point.
glm::dvec2 luxelAt(const bt::LightmappedFace& face, const glm::dvec3& p) {
  return {glm::dot(p, face.luxelS) + face.luxelSOffset, glm::dot(p, face.luxelT) + face.luxelTOffset};
}

TEST(BspLightmaps, QuakeGridProjectionPutsLuxelsEverySixteenTexels) {
  BT_REQUIRE_SHARED(shared);
  bt::Diagnostics diagnostics;
  const auto lighting = worldLighting(readBytes(shared / kLitLevel), diagnostics);
  EXPECT_EQ(lighting.layout, "16 texels per luxel");
  size_t checked = 0;
  for (const bt::LightmappedFace& face : lighting.faces) {
    if (face.width == 0) continue;
    EXPECT_EQ(face.luxelSize, 16);
    for (const glm::dvec3& p : face.polygon) {
      const double s = glm::dot(p, face.sAxis) + face.sOffset, t = glm::dot(p, face.tAxis) + face.tOffset;
      const glm::dvec2 luxel = luxelAt(face, p);
      EXPECT_NEAR(luxel.x, s / 16.0 - face.lightmapMins[0], 1e-6);
      EXPECT_NEAR(luxel.y, t / 16.0 - face.lightmapMins[1], 1e-6);
      // Every vertex lies within the grid (luxel centres span the face's extents).
      EXPECT_GE(luxel.x, -1e-6);
      EXPECT_LE(luxel.x, face.width - 1 + 1e-6);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100u);
}

TEST(BspLightmaps, LmshiftGivesEachFaceItsLuxelSize) {
  BT_REQUIRE_SHARED(shared);
  const Bytes original = readBytes(shared / kLitLevel);
  const auto bsp = bt::bsp::readBspFile(original, "lit.bsp");
  bt::Diagnostics plainDiagnostics;
  const auto plain = worldLighting(original, plainDiagnostics);

  // Shift 4 everywhere is Quake's grid: the same lightmaps.
  {
    bt::Diagnostics diagnostics;
    const auto four = worldLighting(withBspx(original, {{"LMSHIFT", Bytes(bsp.faces.size(), 4)}}), diagnostics);
    EXPECT_TRUE(diagnostics.empty());
    EXPECT_EQ(four.layout, "per-face luxel size (BSPX LMSHIFT)");
    ASSERT_EQ(four.faces.size(), plain.faces.size());
    for (size_t f = 0; f < plain.faces.size(); ++f) {
      EXPECT_EQ(four.faces[f].rgb, plain.faces[f].rgb);
      EXPECT_EQ(four.faces[f].lightmapMins, plain.faces[f].lightmapMins);
      EXPECT_EQ(four.faces[f].luxelSize, 16);
    }
  }
  // Shift 5 (32 texels per luxel): each face's grid shrinks to its extents in 32-texel luxels,
  // counted here from the face's vertices, and its samples start at the same offset.
  Bytes shifts(bsp.faces.size(), 5);
  shifts[0] = 16; // no luxel is 65536 texels: a corrupt record
  bt::Diagnostics diagnostics;
  const auto five = worldLighting(withBspx(original, {{"LMSHIFT", shifts}}), diagnostics);
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_NE(diagnostics[0].message.find("lump 'BSPX LMSHIFT': 1 faces have an unusable record"), std::string::npos)
      << diagnostics[0].message;
  EXPECT_EQ(five.faces[0].width, 0);
  size_t checked = 0;
  for (size_t f = 1; f < five.faces.size(); ++f) {
    const bt::LightmappedFace& face = five.faces[f];
    if (plain.faces[f].width == 0) {
      EXPECT_EQ(face.width, 0);
      continue;
    }
    const auto& texinfo = bsp.texinfo[static_cast<size_t>(bsp.faces[f].texinfo)];
    int size[2];
    for (int a = 0; a < 2; ++a) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const glm::dvec3& p : bsp.faceVertices(f)) {
        const double st = p.x * texinfo.vecs[a][0] + p.y * texinfo.vecs[a][1] + p.z * texinfo.vecs[a][2] + texinfo.vecs[a][3];
        lo = std::min(lo, st), hi = std::max(hi, st);
      }
      EXPECT_EQ(face.lightmapMins[static_cast<size_t>(a)], static_cast<int>(std::floor(lo / 32.0))) << "face " << f;
      size[a] = static_cast<int>(std::ceil(hi / 32.0) - std::floor(lo / 32.0)) + 1;
    }
    ASSERT_EQ(face.width, size[0]) << "face " << f;
    ASSERT_EQ(face.height, size[1]) << "face " << f;
    EXPECT_EQ(face.luxelSize, 32);
    const size_t offset = static_cast<size_t>(bsp.faces[f].lightOffset);
    ASSERT_EQ(face.rgb.size(), static_cast<size_t>(size[0] * size[1]) * styleCount(bsp.faces[f]) * 3);
    for (size_t k = 0; k < face.rgb.size(); k += 3) ASSERT_EQ(face.rgb[k], bsp.lighting[offset + k / 3]);
    const glm::dvec3 p = face.polygon[0];
    EXPECT_NEAR(luxelAt(face, p).x, (glm::dot(p, face.sAxis) + face.sOffset) / 32.0 - face.lightmapMins[0], 1e-6);
    ++checked;
  }
  EXPECT_GT(checked, 20u);
}

// DECOUPLED_LM records as ericw-tools writes them (bspx_decoupled_lm_perface): uint16 width,
// height; int32 offset; float world_to_lm_space[2][4], row major. These place each face's
// luxels exactly where Quake's grid does, so the lightmaps must come out the same.
Bytes decoupledLikeQuakeGrid(const bt::bsp::BspFile& bsp) {
  Bytes lump;
  for (size_t f = 0; f < bsp.faces.size(); ++f) {
    const auto e = bt::bsp::lightmapExtents(bsp, f);
    const auto& texinfo = bsp.texinfo[static_cast<size_t>(bsp.faces[f].texinfo)];
    appendU16(lump, static_cast<uint16_t>(e.width));
    appendU16(lump, static_cast<uint16_t>(e.height));
    appendU32(lump, static_cast<uint32_t>(bsp.faces[f].lightOffset));
    for (int a = 0; a < 2; ++a) {
      for (int k = 0; k < 3; ++k) appendF32(lump, texinfo.vecs[a][k] / 16.0f);
      appendF32(lump, texinfo.vecs[a][3] / 16.0f - static_cast<float>(e.mins[static_cast<size_t>(a)]));
    }
  }
  return lump;
}

TEST(BspLightmaps, DecoupledLmPlacesEachFacesLuxels) {
  BT_REQUIRE_SHARED(shared);
  const Bytes original = readBytes(shared / kLitLevel);
  const auto bsp = bt::bsp::readBspFile(original, "lit.bsp");
  bt::Diagnostics plainDiagnostics;
  const auto plain = worldLighting(original, plainDiagnostics);
  Bytes lump = decoupledLikeQuakeGrid(bsp);
  {
    bt::Diagnostics diagnostics;
    // LMSHIFT beside it is ignored: DECOUPLED_LM says everything.
    const auto decoupled =
        worldLighting(withBspx(original, {{"LMSHIFT", Bytes(bsp.faces.size(), 7)}, {"DECOUPLED_LM", lump}}), diagnostics);
    EXPECT_TRUE(diagnostics.empty());
    EXPECT_EQ(decoupled.layout, "decoupled (BSPX DECOUPLED_LM)");
    ASSERT_EQ(decoupled.faces.size(), plain.faces.size());
    size_t lit = 0;
    for (size_t f = 0; f < plain.faces.size(); ++f) {
      const bt::LightmappedFace& face = decoupled.faces[f];
      ASSERT_EQ(face.width, plain.faces[f].width) << "face " << f;
      ASSERT_EQ(face.rgb, plain.faces[f].rgb) << "face " << f;
      EXPECT_EQ(face.luxelSize, 0);
      for (const glm::dvec3& p : face.polygon) {
        EXPECT_NEAR(luxelAt(face, p).x, luxelAt(plain.faces[f], p).x, 1e-3);
        EXPECT_NEAR(luxelAt(face, p).y, luxelAt(plain.faces[f], p).y, 1e-3);
      }
      lit += face.width > 0;
    }
    EXPECT_GT(lit, 20u);
  }
  // Bad records: no lightmap (offset -1), a size far past the lighting data, a NaN projection.
  const size_t a = 1, b = 2, c = 3;
  putU32(lump, a * 40 + 4, 0xffffffffu);
  lump[b * 40] = lump[b * 40 + 1] = lump[b * 40 + 2] = lump[b * 40 + 3] = 0xff; // 65535 x 65535
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&lump[c * 40 + 8], &nan, 4);
  bt::Diagnostics diagnostics;
  const auto broken = worldLighting(withBspx(original, {{"DECOUPLED_LM", lump}}), diagnostics);
  for (size_t f : {a, b, c}) EXPECT_EQ(broken.faces[f].width, 0) << "face " << f;
  ASSERT_EQ(diagnostics.size(), 2u);
  EXPECT_NE(diagnostics[0].message.find("faces point past the end"), std::string::npos) << diagnostics[0].message;
  EXPECT_NE(diagnostics[1].message.find("lump 'BSPX DECOUPLED_LM': 1 faces have an unusable record"), std::string::npos)
      << diagnostics[1].message;
  EXPECT_EQ(broken.faces[4].rgb, plain.faces[4].rgb);
}

TEST(BspLightmaps, BspxLightmapLumpsOfTheWrongSizeAreIgnored) {
  BT_REQUIRE_SHARED(shared);
  const Bytes original = readBytes(shared / kLitLevel);
  const auto bsp = bt::bsp::readBspFile(original, "lit.bsp");
  Bytes decoupled = decoupledLikeQuakeGrid(bsp);
  decoupled.pop_back();
  bt::Diagnostics diagnostics;
  const auto lighting =
      worldLighting(withBspx(original, {{"LMSHIFT", Bytes(bsp.faces.size() + 1, 5)}, {"DECOUPLED_LM", decoupled}}), diagnostics);
  EXPECT_EQ(lighting.layout, "16 texels per luxel");
  ASSERT_EQ(diagnostics.size(), 2u);
  EXPECT_NE(diagnostics[0].message.find("lump 'BSPX DECOUPLED_LM' ignored"), std::string::npos) << diagnostics[0].message;
  EXPECT_NE(diagnostics[1].message.find("lump 'BSPX LMSHIFT' ignored"), std::string::npos) << diagnostics[1].message;
  EXPECT_EQ(diagnostics[1].file, "lit.bsp");
}

TEST(BspLightmaps, Quake2FilesCarryBspxLumpsToo) {
  BT_REQUIRE_SHARED(shared);
  const Bytes original = readBytes(shared / "oracle" / "maps_ericw-tools_testmaps_q2_areaportal.bsp");
  const auto plain = bt::bsp::readBspFile(original, "q2.bsp");
  const Bytes lump = decoupledLikeQuakeGrid(plain);
  const auto bsp = bt::bsp::readBspFile(withBspx(original, {{"DECOUPLED_LM", lump}}), "q2.bsp");
  const bt::bsp::BspxLump* read = bsp.findBspx("DECOUPLED_LM");
  ASSERT_NE(read, nullptr);
  EXPECT_EQ(read->bytes, lump);
  bt::Diagnostics diagnostics;
  const auto lighting = bt::bsp::readCompiledLighting(bsp, {{0, 0, glm::dvec3(0.0)}}, std::nullopt, diagnostics);
  EXPECT_EQ(lighting.layout, "decoupled (BSPX DECOUPLED_LM)");
  EXPECT_TRUE(diagnostics.empty());
}

// Garbage in the per-face records (any size, offset, shift or projection) gives lightmaps that
// fit their own grids, or none; never a read outside the data (the sanitizer build runs this).
TEST(BspLightmaps, CorruptBspxLightmapRecordsAreBoundsChecked) {
  BT_REQUIRE_SHARED(shared);
  const Bytes original = readBytes(shared / kLitLevel);
  const auto bsp = bt::bsp::readBspFile(original, "lit.bsp");
  const Bytes decoupled = decoupledLikeQuakeGrid(bsp);
  std::mt19937 rng(5);
  for (int round = 0; round < 60; ++round) {
    Bytes shifts(bsp.faces.size(), 4), records = decoupled;
    for (int k = 0; k < 40; ++k) {
      shifts[rng() % shifts.size()] = static_cast<uint8_t>(rng());
      records[rng() % records.size()] = static_cast<uint8_t>(rng());
    }
    std::vector<std::pair<std::string, Bytes>> lumps{{"LMSHIFT", shifts}};
    if (round % 2) lumps.push_back({"DECOUPLED_LM", records});
    bt::Diagnostics diagnostics;
    const auto lighting = worldLighting(withBspx(original, lumps), diagnostics);
    for (size_t f = 0; f < lighting.faces.size(); ++f) {
      const bt::LightmappedFace& face = lighting.faces[f];
      const size_t styles = face.width > 0 ? styleCount(bsp.faces[f]) : 0;
      ASSERT_EQ(face.rgb.size(), static_cast<size_t>(face.width) * static_cast<size_t>(face.height) * styles * 3);
    }
  }
}

// --- BSPX BRUSHLIST ------------------------------------------------------------------------

// Writes the world's brushes as ericw-tools' BRUSHLIST (qbsp -wrbrushes) would: bounds, contents
// and the non-axial planes of each.
Bytes brushListOf(const bt::Scene& scene) {
  Bytes out;
  const bt::Entity& world = *scene.worldspawn();
  appendU32(out, 1); // version
  appendU32(out, 0); // model
  appendU32(out, world.brushCount);
  const size_t planeCountAt = out.size();
  appendU32(out, 0);
  uint32_t planes = 0;
  for (uint32_t b = world.firstBrush; b < world.firstBrush + world.brushCount; ++b) {
    const bt::Brush& brush = scene.brushes[b];
    for (int k = 0; k < 3; ++k) appendF32(out, static_cast<float>(brush.bounds.min[k]));
    for (int k = 0; k < 3; ++k) appendF32(out, static_cast<float>(brush.bounds.max[k]));
    appendU16(out, static_cast<uint16_t>(-2)); // CONTENTS_SOLID
    std::vector<const bt::Face*> nonAxial;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) {
      const auto n = glm::abs(scene.faces[f].plane.normal);
      if (std::max({n.x, n.y, n.z}) < 1.0 - 1e-9) nonAxial.push_back(&scene.faces[f]);
    }
    appendU16(out, static_cast<uint16_t>(nonAxial.size()));
    for (const bt::Face* face : nonAxial) {
      for (int k = 0; k < 3; ++k) appendF32(out, static_cast<float>(face->plane.normal[k]));
      appendF32(out, static_cast<float>(face->plane.dist));
      ++planes;
    }
  }
  putU32(out, planeCountAt, planes);
  return out;
}

TEST(BspBrushList, BrushesComeFromTheBspxLumpWithTheirFacesTextures) {
  BT_REQUIRE_SHARED(shared);
  const auto source = shared / "oracle" / "maps_ericw-tools_testmaps_deprecated_shearedcube.bsp";
  const bt::Scene cells = importPath(source);
  const auto path = scratchDir() / "brushlist.bsp";
  writeBytes(path, withBspx(readBytes(source), {{"BRUSHLIST", brushListOf(cells)}}));
  const bt::Scene listed = importPath(path);
  ASSERT_EQ(listed.worldspawn()->brushCount, cells.worldspawn()->brushCount);
  std::map<std::string, size_t> cellTextures, listedTextures;
  for (uint32_t b = 0; b < cells.worldspawn()->brushCount; ++b) {
    const bt::Brush& a = cells.brushes[cells.worldspawn()->firstBrush + b];
    const bt::Brush& c = listed.brushes[listed.worldspawn()->firstBrush + b];
    EXPECT_NEAR(glm::length(a.bounds.min - c.bounds.min), 0.0, 0.01);
    EXPECT_NEAR(glm::length(a.bounds.max - c.bounds.max), 0.0, 0.01);
    EXPECT_EQ(a.faceCount, c.faceCount);
    for (uint32_t f = a.firstFace; f < a.firstFace + a.faceCount; ++f) ++cellTextures[cells.faces[f].texture];
    for (uint32_t f = c.firstFace; f < c.firstFace + c.faceCount; ++f) ++listedTextures[listed.faces[f].texture];
  }
  EXPECT_EQ(listedTextures, cellTextures);
  EXPECT_GT(cellTextures.size(), 1u);
}

TEST(BspBrushList, MalformedLumpIsAnImportError) {
  BT_REQUIRE_SHARED(shared);
  const auto source = shared / "oracle" / "maps_ericw-tools_testmaps_deprecated_shearedcube.bsp";
  Bytes lump;
  appendU32(lump, 1);
  appendU32(lump, 0);
  appendU32(lump, 5); // five brushes promised, none follow
  appendU32(lump, 0);
  const auto bsp = bt::bsp::readBspFile(withBspx(readBytes(source), {{"BRUSHLIST", lump}}), "cut.bsp");
  try {
    bt::bsp::sceneFromBsp(bsp);
    FAIL() << "no ImportError";
  } catch (const bt::ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("lump 'BSPX BRUSHLIST': truncated"), std::string::npos) << e.what();
  }
}

// --- textures ------------------------------------------------------------------------------

// Rebuilds a BSP29/30 file's miptex lump with the textures a WAD has (a compiler run without
// -notex would have embedded them), keeping the other entries as they are.
Bytes withEmbeddedTextures(const Bytes& original, const bt::WadFile& wad) {
  const auto bsp = bt::bsp::readBspFile(original, "original.bsp");
  Bytes lump;
  appendU32(lump, static_cast<uint32_t>(bsp.miptex.size()));
  const size_t directory = lump.size();
  lump.resize(directory + 4 * bsp.miptex.size());
  for (size_t i = 0; i < bsp.miptex.size(); ++i) {
    putU32(lump, directory + 4 * i, static_cast<uint32_t>(lump.size()));
    const bt::WadFile::Entry* entry = wad.findTexture(bsp.miptex[i].name);
    if (entry) {
      const auto data = wad.data(*entry);
      lump.insert(lump.end(), data.begin(), data.end());
    } else {
      lump.insert(lump.end(), bsp.miptex[i].bytes.begin(), bsp.miptex[i].bytes.end());
    }
    lump.resize((lump.size() + 3) & ~size_t{3}, 0);
  }
  Bytes out = original;
  putU32(out, 4 + 2 * 8, static_cast<uint32_t>(out.size())); // lump 2: textures
  putU32(out, 8 + 2 * 8, static_cast<uint32_t>(lump.size()));
  out.insert(out.end(), lump.begin(), lump.end());
  return out;
}

TEST(BspTextures, HalfLifeMiptexInsideTheBspAreDecodedWithTheirPalette) {
  BT_REQUIRE_SHARED(shared);
  const auto wadPath = shared / "maps/ericw-tools/testmaps/deprecated/hlwad.wad";
  const bt::WadFile wad = bt::WadFile::open(wadPath);
  const auto path = scratchDir() / "hl_embedded.bsp";
  writeBytes(path, withEmbeddedTextures(readBytes(shared / "oracle" / "maps_ericw-tools_testmaps_hl_basic.bsp"), wad));
  bt::ImportOptions options;
  const bt::Scene scene = importPath(path, options);
  const auto index = scene.findMaterial("hltest");
  ASSERT_TRUE(index);
  const bt::Material& m = scene.materials[*index];
  EXPECT_EQ(m.source, bt::TextureSource::Miptex);
  const auto fromWad = wad.loadTexture("hltest", nullptr);
  ASSERT_TRUE(fromWad);
  EXPECT_EQ(m.width, fromWad->width);
  EXPECT_EQ(m.baseColor.rgba, fromWad->baseColor.rgba);
}

// A Quake level compiled with its textures (qbsp without -notex): the BSP29 miptex lump holds
// 8-bit indices into Quake's palette, which the importer finds through --palette (or
// gfx/palette.lmp up the tree). Each texel must be the palette colour of its index, as the
// raw lump says; indices 224..255 also shine (fullbright).
TEST(BspTextures, QuakeMiptexInsideTheBspAreDecodedWithTheQuakePalette) {
  BT_REQUIRE_SHARED(shared);
  const bt::WadFile wad = bt::WadFile::open(shared / "maps/librequake/texture-wads/lq_dev_legacy/lq_dev_legacy.wad");
  const auto path = scratchDir() / "q1_embedded.bsp";
  const Bytes file = withEmbeddedTextures(readBytes(shared / "oracle" / "maps_librequake_lq1_maps_src_misc_slope.bsp"), wad);
  writeBytes(path, file);
  const auto bsp = bt::bsp::readBspFile(file, "q1_embedded.bsp");
  const bt::Palette palette = bt::loadPalette(shared / "maps/palettes/quake.lmp");

  bt::ImportOptions options;
  options.textures.palette = (shared / "maps/palettes/quake.lmp").string();
  const bt::Scene scene = importPath(path, options);
  size_t decoded = 0, fullbrightTexels = 0;
  for (const bt::bsp::Miptex& miptex : bsp.miptex) {
    if (!miptex.present || !miptex.hasPixels) continue;
    SCOPED_TRACE(miptex.name);
    const auto index = scene.findMaterial(miptex.name);
    ASSERT_TRUE(index);
    const bt::Material& m = scene.materials[*index];
    EXPECT_EQ(m.source, bt::TextureSource::Miptex);
    EXPECT_EQ(m.sourcePath, path.string());
    ASSERT_EQ(m.width, static_cast<int>(miptex.width));
    ASSERT_EQ(m.height, static_cast<int>(miptex.height));
    // Mip level 0 as stored: header {name[16], width, height, offsets[4]}, then indices.
    const size_t pixels = u32At(miptex.bytes, 24);
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) {
        const uint8_t i = miptex.bytes[pixels + static_cast<size_t>(y) * m.width + x];
        const uint8_t* texel = m.baseColor.texel(x, y);
        const bool transparent = miptex.name[0] == '{' && i == 255;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(texel[c], transparent ? 0 : palette.rgb[i * 3 + c]) << x << "," << y;
        ASSERT_EQ(texel[3], transparent ? 0 : 255);
        if (i >= 224 && !transparent) {
          ASSERT_FALSE(m.emissive.empty());
          for (int c = 0; c < 3; ++c) ASSERT_EQ(m.emissive.texel(x, y)[c], palette.rgb[i * 3 + c]);
          ++fullbrightTexels;
        }
      }
    // The same texture from the WAD it came from decodes to the same pixels.
    const auto fromWad = wad.loadTexture(miptex.name, &palette);
    ASSERT_TRUE(fromWad);
    EXPECT_EQ(m.baseColor.rgba, fromWad->baseColor.rgba);
    ++decoded;
  }
  EXPECT_EQ(decoded, 20u);
  EXPECT_GT(fullbrightTexels, 0u);

  // Without a palette anywhere the level's own pixels are read with the built-in Quake palette
  // (the same table), and one warning says so.
  const bt::Scene withoutPalette = importPath(path);
  size_t warnings = 0;
  for (const bt::Diagnostic& d : withoutPalette.diagnostics) warnings += d.message.find("built-in Quake palette") != std::string::npos;
  EXPECT_EQ(warnings, 1u);
  for (const bt::bsp::Miptex& miptex : bsp.miptex) {
    if (!miptex.present || !miptex.hasPixels) continue;
    const bt::Material& m = withoutPalette.materials[*withoutPalette.findMaterial(miptex.name)];
    EXPECT_EQ(m.source, bt::TextureSource::Miptex) << m.name;
    EXPECT_EQ(m.baseColor.rgba, scene.materials[*scene.findMaterial(miptex.name)].baseColor.rgba) << m.name;
  }
}

TEST(BspTextures, TexturesMissingFromTheBspAreSearchedInWads) {
  BT_REQUIRE_SHARED(shared);
  bt::ImportOptions options;
  options.textures.wads.push_back((shared / "maps/ericw-tools/testmaps/deprecated/hlwad.wad").string());
  const bt::Scene scene = importPath(shared / "oracle" / "maps_ericw-tools_testmaps_hl_basic.bsp", options);
  const auto index = scene.findMaterial("hltest");
  ASSERT_TRUE(index);
  EXPECT_EQ(scene.materials[*index].source, bt::TextureSource::Wad3);
}

} // namespace

namespace {

// --- BSP2 and 2PSB ---------------------------------------------------------------------------

// Rewrites a BSP29 file in the 32-bit layouts: BSP2 (float node/leaf bounds) or RMQ's 2PSB
// (int16 bounds). No compiler output in ../shared uses them, so the test makes its own.
Bytes widenBsp29(const Bytes& in, bool floatBounds) {
  auto i16 = [&](size_t at) { return static_cast<int16_t>(in[at] | (in[at + 1] << 8)); };
  auto u16 = [&](size_t at) { return static_cast<uint16_t>(in[at] | (in[at + 1] << 8)); };
  auto bounds = [&](Bytes& out, size_t at) {
    for (int k = 0; k < 6; ++k) {
      if (floatBounds)
        appendF32(out, static_cast<float>(i16(at + 2 * k)));
      else
        appendU16(out, static_cast<uint16_t>(i16(at + 2 * k)));
    }
  };
  std::vector<Bytes> lumps(15);
  for (int l = 0; l < 15; ++l) {
    const size_t offset = u32At(in, 4 + l * 8), length = u32At(in, 8 + l * 8);
    Bytes& out = lumps[static_cast<size_t>(l)];
    switch (l) {
    case 5: // nodes
      for (size_t at = offset; at < offset + length; at += 24) {
        appendU32(out, u32At(in, at));
        appendU32(out, static_cast<uint32_t>(int32_t{i16(at + 4)}));
        appendU32(out, static_cast<uint32_t>(int32_t{i16(at + 6)}));
        bounds(out, at + 8);
        appendU32(out, u16(at + 20));
        appendU32(out, u16(at + 22));
      }
      break;
    case 7: // faces
      for (size_t at = offset; at < offset + length; at += 20) {
        appendU32(out, u16(at));
        appendU32(out, static_cast<uint32_t>(int32_t{i16(at + 2)}));
        appendU32(out, u32At(in, at + 4));
        appendU32(out, u16(at + 8));
        appendU32(out, u16(at + 10));
        out.insert(out.end(), in.begin() + static_cast<long>(at + 12), in.begin() + static_cast<long>(at + 20));
      }
      break;
    case 9: // clipnodes
      for (size_t at = offset; at < offset + length; at += 8) {
        appendU32(out, u32At(in, at));
        appendU32(out, static_cast<uint32_t>(int32_t{i16(at + 4)}));
        appendU32(out, static_cast<uint32_t>(int32_t{i16(at + 6)}));
      }
      break;
    case 10: // leafs
      for (size_t at = offset; at < offset + length; at += 28) {
        appendU32(out, u32At(in, at));
        appendU32(out, u32At(in, at + 4));
        bounds(out, at + 8);
        appendU32(out, u16(at + 20));
        appendU32(out, u16(at + 22));
        out.insert(out.end(), in.begin() + static_cast<long>(at + 24), in.begin() + static_cast<long>(at + 28));
      }
      break;
    case 11: // marksurfaces
      for (size_t at = offset; at < offset + length; at += 2) appendU32(out, u16(at));
      break;
    case 12: // edges
      for (size_t at = offset; at < offset + length; at += 2) appendU32(out, u16(at));
      break;
    default: out.assign(in.begin() + static_cast<long>(offset), in.begin() + static_cast<long>(offset + length));
    }
  }
  Bytes out(4 + 15 * 8, 0);
  std::memcpy(out.data(), floatBounds ? "BSP2" : "2PSB", 4);
  for (size_t l = 0; l < 15; ++l) {
    putU32(out, 4 + l * 8, static_cast<uint32_t>(out.size()));
    putU32(out, 8 + l * 8, static_cast<uint32_t>(lumps[l].size()));
    out.insert(out.end(), lumps[l].begin(), lumps[l].end());
    out.resize((out.size() + 3) & ~size_t{3}, 0);
  }
  return out;
}

TEST(BspVersions, Bsp2And2psbImportLikeTheBsp29TheyWereWidenedFrom) {
  BT_REQUIRE_SHARED(shared);
  // phongtest: 200 KB of nodes, leafs and clip hulls, quick enough under ASan.
  const auto bytes29 = readBytes(shared / "oracle" / "maps_ericw-tools_testmaps_deprecated_phongtest.bsp");
  const bt::Scene reference = bt::bsp::sceneFromBsp(bt::bsp::readBspFile(bytes29, "phongtest.bsp"));
  for (const bool floatBounds : {true, false}) {
    const auto bsp = bt::bsp::readBspFile(widenBsp29(bytes29, floatBounds), "phongtest-wide.bsp");
    EXPECT_EQ(bsp.version, floatBounds ? bt::bsp::Version::Bsp2 : bt::bsp::Version::Bsp2rmq);
    const bt::Scene wide = bt::bsp::sceneFromBsp(bsp);
    EXPECT_EQ(wide.format, floatBounds ? "bsp2" : "2psb");
    ASSERT_EQ(wide.faces.size(), reference.faces.size());
    ASSERT_EQ(wide.brushes.size(), reference.brushes.size());
    for (size_t f = 0; f < wide.faces.size(); ++f) {
      ASSERT_EQ(wide.faces[f].texture, reference.faces[f].texture);
      ASSERT_EQ(wide.faces[f].plane.normal, reference.faces[f].plane.normal);
      ASSERT_EQ(wide.faces[f].winding, reference.faces[f].winding);
    }
  }
}

} // namespace
