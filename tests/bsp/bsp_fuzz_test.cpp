// Damaged BSP files: truncated, lump table scrambled, lump contents scrambled. Each must give an
// ImportError or a scene, never a crash, a hang or an out-of-bounds read (CI runs this suite
// under ASan+UBSan).
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/bsp_import.h"
#include "importers/bsp/pk3.h"
#include "lighting/compiled_lightmaps.h"
#include "lighting/render_scene.h"
#include "bvh/trace_scene.h"

#include <glm/geometric.hpp>
#include "tests/test_data.h"

#include <algorithm>
#include <fstream>
#include <random>

namespace {

std::vector<uint8_t> readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A fixed sample of the oracle: every version and feature family, small enough that the whole
// suite stays within seconds under ASan. Sorted by name, then every fifth file up to 100 KB.
std::vector<std::filesystem::path> sampleOracle(const std::filesystem::path& shared) {
  std::vector<std::filesystem::path> all;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "oracle"))
    if (entry.path().extension() == ".bsp" && entry.file_size() <= 100 * 1024) all.push_back(entry.path());
  std::sort(all.begin(), all.end());
  std::vector<std::filesystem::path> sample;
  for (size_t i = 0; i < all.size(); i += 5) sample.push_back(all[i]);
  return sample;
}

// The end of the last lump: cutting the file anywhere before it must be reported.
size_t lumpDataEnd(std::span<const uint8_t> bytes) {
  auto u32 = [&](size_t at) {
    return uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 | uint32_t(bytes[at + 3]) << 24;
  };
  const bool ibsp = bytes[0] == 'I';
  const size_t table = ibsp ? 8 : 4;
  const int count = !ibsp ? 15 : (u32(4) == 38 ? 19 : 17);
  size_t end = table + size_t(count) * 8;
  for (int i = 0; i < count; ++i) end = std::max<size_t>(end, size_t(u32(table + i * 8)) + u32(table + i * 8 + 4));
  return end;
}

size_t lumpTableSize(std::span<const uint8_t> bytes) {
  if (bytes[0] != 'I') return 4 + 15 * 8;
  return 8 + (bytes[4] == 38 ? 19 : 17) * 8;
}

// Parses and, when that succeeds, builds the whole scene (brush cells, frames, ...).
// Returns true when it threw ImportError.
bool importOrReject(std::span<const uint8_t> bytes) {
  try {
    const bt::bsp::BspFile bsp = bt::bsp::readBspFile(bytes, "fuzz.bsp");
    bt::bsp::sceneFromBsp(bsp);
    return false;
  } catch (const bt::ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("fuzz.bsp"), std::string::npos) << e.what();
    return true;
  }
}

TEST(BspFuzz, TruncatedFilesAreRejected) {
  BT_REQUIRE_SHARED(shared);
  std::mt19937 rng(20261122);
  const auto files = sampleOracle(shared);
  ASSERT_GE(files.size(), 10u);
  for (const auto& path : files) {
    SCOPED_TRACE(path.string());
    const auto bytes = readBytes(path);
    const size_t end = lumpDataEnd(bytes);
    ASSERT_LE(end, bytes.size());
    std::uniform_int_distribution<size_t> cut(0, end - 1);
    for (int i = 0; i < 100; ++i) {
      const size_t size = cut(rng);
      EXPECT_TRUE(importOrReject(std::span(bytes).first(size))) << "truncated to " << size << " bytes";
    }
  }
}

TEST(BspFuzz, ScrambledLumpTablesNeverCrash) {
  BT_REQUIRE_SHARED(shared);
  std::mt19937 rng(42);
  size_t rejected = 0, total = 0;
  for (const auto& path : sampleOracle(shared)) {
    SCOPED_TRACE(path.string());
    const auto original = readBytes(path);
    std::uniform_int_distribution<size_t> where(4, lumpTableSize(original) - 1);
    std::uniform_int_distribution<int> value(0, 255);
    for (int i = 0; i < 100; ++i) {
      auto bytes = original;
      const int flips = 1 + i % 4;
      for (int f = 0; f < flips; ++f) bytes[where(rng)] = static_cast<uint8_t>(value(rng));
      rejected += importOrReject(bytes);
      ++total;
    }
  }
  // Most scrambles break a lump's bounds; the rest must merely not crash.
  EXPECT_GT(rejected, total / 2);
}

TEST(BspFuzz, ScrambledLumpContentsNeverCrash) {
  BT_REQUIRE_SHARED(shared);
  std::mt19937 rng(7);
  for (const auto& path : sampleOracle(shared)) {
    SCOPED_TRACE(path.string());
    const auto original = readBytes(path);
    std::uniform_int_distribution<size_t> where(lumpTableSize(original), original.size() - 1);
    std::uniform_int_distribution<int> value(0, 255);
    for (int i = 0; i < 20; ++i) {
      auto bytes = original;
      for (int f = 0; f < 16; ++f) bytes[where(rng)] = static_cast<uint8_t>(value(rng));
      importOrReject(bytes);
    }
  }
}

// The lightmap paths: the compiled lightmaps of a damaged level are read (importer) and laid
// out on its faces (the compiled view) without a crash: Quake 1/HL/Q2 levels of the sample, and
// an OpenArena level whose draw surfaces and vertices (lightmap page, corner, axes, coordinates)
// are scrambled.
// Returns true when the level still had compiled lightmaps to lay out.
bool buildCompiledView(std::span<const uint8_t> bytes) {
  try {
    const bt::Scene scene = bt::bsp::sceneFromBsp(bt::bsp::readBspFile(bytes, "fuzz.bsp"));
    bt::Diagnostics diagnostics;
    bt::RenderScene rs = bt::buildRenderScene(scene, {}, diagnostics);
    const bool shown = bt::showCompiledLightmaps(scene, rs, "").empty();
    const bt::Lightmaps& lm = rs.lightmaps;
    for (const bt::GpuLightmapFragment& g : lm.fragments) EXPECT_LE(size_t(g.firstLuxel) + size_t(g.width) * g.height, lm.luxels.size());
    return shown;
  } catch (const bt::ImportError&) {
    return false;
  }
}

TEST(BspFuzz, ScrambledLightmapsNeverCrashTheCompiledView) {
  BT_REQUIRE_SHARED(shared);
  std::mt19937 rng(2211);
  std::uniform_int_distribution<int> value(0, 255);
  std::vector<std::filesystem::path> files; // the lit levels: Quake 1 (some with .lit), Half-Life, Quake 2
  for (const char* folder : {"oracle/lit", "oracle/lit-games"})
    for (const auto& entry : std::filesystem::directory_iterator(shared / folder))
      if (entry.path().extension() == ".bsp" && entry.file_size() <= 100 * 1024) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  int shown = 0;
  for (size_t i = 0; i < files.size(); i += 6) {
    SCOPED_TRACE(files[i].string());
    const auto original = readBytes(files[i]);
    std::uniform_int_distribution<size_t> where(lumpTableSize(original), original.size() - 1);
    for (int k = 0; k < 5; ++k) {
      auto bytes = original;
      for (int f = 0; f < 16; ++f) bytes[where(rng)] = static_cast<uint8_t>(value(rng));
      shown += buildCompiledView(bytes);
    }
  }
  EXPECT_GT(shown, 0) << "no damaged level kept lightmaps to lay out";
  const std::filesystem::path pk3 = "/usr/share/games/openarena/baseoa/pak1-maps.pk3";
  if (!std::filesystem::exists(pk3)) GTEST_SKIP() << pk3 << " not found: Quake 3 surfaces not fuzzed";
  const std::vector<uint8_t> original = *bt::bsp::Pk3Archive(pk3).read("maps/q3dm6ish.bsp");
  ASSERT_TRUE(buildCompiledView(original)) << "the undamaged level has lightmaps";
  auto lump = [&](int index) { // Quake 3's lump table: offset, length
    size_t at = 8 + size_t(index) * 8, offset = 0, length = 0;
    for (int b = 3; b >= 0; --b) offset = offset << 8 | original[at + size_t(b)], length = length << 8 | original[at + 4 + size_t(b)];
    return std::pair{offset, length};
  };
  int quake3Shown = 0;
  for (int surfacesOrVertices : {13, 10}) { // LUMP_SURFACES, LUMP_DRAWVERTS
    const auto [offset, length] = lump(surfacesOrVertices);
    std::uniform_int_distribution<size_t> where(offset, offset + length - 1);
    for (int k = 0; k < 3; ++k) {
      auto bytes = original;
      for (int f = 0; f < 64; ++f) bytes[where(rng)] = static_cast<uint8_t>(value(rng));
      quake3Shown += buildCompiledView(bytes);
    }
  }
  EXPECT_GT(quake3Shown, 0) << "no damaged Quake 3 level kept lightmaps to lay out";
}

} // namespace

// Found by tests/fuzz/fuzz_bsp (tests/bsp/data/fuzz_sliver_cell.bsp, an oracle level with bytes
// changed): two node planes 1.4e-45 apart, face to face, cut a hull-0 cell into a sliver that kept
// both as sides. Its +X face lay below its -X face; the BVH builder then threw on the empty box.
TEST(BspFuzz, CellsThinnerThanTheEpsilonAreSkippedWithAWarning) {
  const auto path = bt::test::sourceDir() / "tests/bsp/data/fuzz_sliver_cell.bsp";
  const bt::Scene scene = bt::bsp::sceneFromBsp(bt::bsp::readBspFile(path));
  bool warned = false;
  for (const bt::Diagnostic& d : scene.diagnostics)
    warned |= d.severity == bt::Severity::Warning && d.message.find("brush(es) skipped: thinner than 0.01 units") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_FALSE(scene.brushes.empty());
  for (const bt::Brush& b : scene.brushes) {
    SCOPED_TRACE(b.firstFace);
    for (uint32_t f = b.firstFace; f < b.firstFace + b.faceCount; ++f)
      for (uint32_t g = b.firstFace; g < b.firstFace + b.faceCount; ++g) {
        const bt::Plane &p = scene.faces[f].plane, &q = scene.faces[g].plane;
        // Opposite planes of one brush: the brush lies between them, so they must not cross.
        if (glm::dot(p.normal, q.normal) < -0.999999) {
          EXPECT_GT(p.dist + q.dist, 0.0) << f << " " << g;
        }
      }
  }
  EXPECT_NO_THROW(bt::TraceScene::build(scene));
}
