// The raw lump reader against the reference compiler's output in ../shared/oracle.
#include "importers/bsp/bsp_file.h"
#include "scene/diagnostics.h"
#include "tests/test_data.h"

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>

#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace {

using bt::bsp::BspFile;
using bt::bsp::Version;

struct OracleEntry {
  std::filesystem::path bsp;
  std::string flags;
};

std::vector<OracleEntry> oracleEntries(const std::filesystem::path& shared) {
  std::ifstream in(shared / "oracle" / "manifest.json");
  const auto manifest = nlohmann::json::parse(in);
  std::vector<OracleEntry> out;
  for (const auto& e : manifest) out.push_back({shared / "oracle" / e.at("bsp").get<std::string>(), e.at("qbsp_flags").get<std::string>()});
  return out;
}

std::vector<uint8_t> readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Version expectedVersion(const std::string& flags) {
  if (flags.find("-q2bsp") != std::string::npos) return Version::Quake2_38;
  if (flags.find("-hlbsp") != std::string::npos) return Version::HalfLife30;
  return Version::Bsp29;
}

// Newell's normal of a polygon: its orientation and area, robust for any convex winding.
glm::dvec3 polygonNormal(const std::vector<glm::dvec3>& w) {
  glm::dvec3 n{0.0};
  for (size_t i = 0; i < w.size(); ++i) n += glm::cross(w[i], w[(i + 1) % w.size()]);
  return n * 0.5;
}

std::string expectThrowMessage(std::span<const uint8_t> bytes) {
  try {
    bt::bsp::readBspFile(bytes, "test.bsp");
  } catch (const bt::ImportError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ImportError";
  return {};
}

const char* kSmallQ1 = "maps_ericw-tools_testmaps_deprecated_shearedcube.bsp";

TEST(BspFile, EveryOracleBspReadsWithItsVersionAndFacesOnTheirPlanes) {
  BT_REQUIRE_SHARED(shared);
  const auto entries = oracleEntries(shared);
  ASSERT_GE(entries.size(), 229u);
  for (const auto& entry : entries) {
    SCOPED_TRACE(entry.bsp.string());
    const BspFile bsp = bt::bsp::readBspFile(entry.bsp);
    EXPECT_EQ(bsp.version, expectedVersion(entry.flags));
    EXPECT_EQ(bsp.hexen2Models, entry.flags.find("-hexen2") != std::string::npos);
    EXPECT_NE(bsp.entities.find("worldspawn"), std::string::npos);
    ASSERT_FALSE(bsp.models.empty());
    size_t counterClockwise = 0;
    for (size_t f = 0; f < bsp.faces.size(); ++f) {
      const auto points = bsp.faceVertices(f);
      ASSERT_GE(points.size(), 3u) << "face " << f;
      EXPECT_FALSE(bsp.faceTexture(f).empty()) << "face " << f;
      const auto& plane = bsp.planes[static_cast<size_t>(bsp.faces[f].plane)];
      const glm::dvec3 normal = glm::dvec3(plane.normal) * (bsp.faces[f].side ? -1.0 : 1.0);
      for (const auto& p : points) ASSERT_NEAR(glm::dot(glm::dvec3(plane.normal), p), plane.dist, 0.1) << "face " << f;
      // qbsp snaps vertices, so they sit within its ON_EPSILON (0.1) of the plane, not exactly on it.
      // Quake stores face vertices clockwise seen from the front: Newell's normal points back.
      // qbsp's T-junction fixing leaves slivers and a few non-convex polygons whose sign is
      // noise, and ericw-tools' bug-repro maps (q2_missing_faces2, q2_hint_missing_faces) carry
      // a reversed face or two, so this is a statistical check.
      if (glm::dot(polygonNormal(points), normal) > 1e-9) ++counterClockwise;
    }
    EXPECT_LE(counterClockwise, 2 + bsp.faces.size() / 100) << "faces not clockwise: " << counterClockwise;
  }
}

TEST(BspFile, Quake2TexinfoCarriesNamesAndBrushesReferenceValidSides) {
  BT_REQUIRE_SHARED(shared);
  const BspFile bsp = bt::bsp::readBspFile(shared / "oracle" / "maps_ericw-tools_testmaps_q2_areaportal.bsp");
  ASSERT_EQ(bsp.version, Version::Quake2_38);
  ASSERT_FALSE(bsp.brushes.empty());
  for (const auto& b : bsp.brushes) EXPECT_GE(b.sideCount, 4);
  for (const auto& t : bsp.texinfo) EXPECT_FALSE(t.texture.empty());
}

TEST(BspFile, Quake1MiptexNamesSurviveNotex) {
  BT_REQUIRE_SHARED(shared);
  const BspFile bsp = bt::bsp::readBspFile(shared / "oracle" / kSmallQ1);
  ASSERT_FALSE(bsp.miptex.empty());
  for (const auto& m : bsp.miptex) {
    EXPECT_TRUE(m.present);
    EXPECT_FALSE(m.name.empty());
    EXPECT_FALSE(m.hasPixels); // qbsp -notex writes names and sizes only
  }
}

TEST(BspFile, TooShortFileNamesTheHeader) {
  const std::vector<uint8_t> bytes{29, 0, 0, 0, 1, 2};
  EXPECT_NE(expectThrowMessage(bytes).find("test.bsp: error: header:"), std::string::npos);
}

TEST(BspFile, UnknownMagicIsRejected) {
  std::vector<uint8_t> bytes(200, 0);
  std::memcpy(bytes.data(), "PK\3\4", 4);
  EXPECT_NE(expectThrowMessage(bytes).find("not a BSP file"), std::string::npos);
}

TEST(BspFile, LumpPastTheEndNamesTheLump) {
  BT_REQUIRE_SHARED(shared);
  auto bytes = readBytes(shared / "oracle" / kSmallQ1);
  // Lump 7 (faces): its length field sits at 4 + 7 * 8 + 4.
  const uint32_t huge = 0x7fff0000;
  std::memcpy(bytes.data() + 4 + 7 * 8 + 4, &huge, 4);
  const auto message = expectThrowMessage(bytes);
  EXPECT_NE(message.find("lump 'faces'"), std::string::npos) << message;
  EXPECT_NE(message.find("past the end"), std::string::npos) << message;
}

TEST(BspFile, OutOfRangeIndexNamesLumpAndRecord) {
  BT_REQUIRE_SHARED(shared);
  auto bytes = readBytes(shared / "oracle" / kSmallQ1);
  uint32_t facesOffset = 0;
  std::memcpy(&facesOffset, bytes.data() + 4 + 7 * 8, 4);
  // Face 0's plane number (uint16) becomes 65535.
  bytes[facesOffset] = 0xff;
  bytes[facesOffset + 1] = 0xff;
  const auto message = expectThrowMessage(bytes);
  EXPECT_NE(message.find("lump 'faces': record 0 refers to plane 65535"), std::string::npos) << message;
}

} // namespace

namespace {

void appendU32(std::vector<uint8_t>& out, uint32_t v) {
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<uint8_t>(v >> (8 * k)));
}

// A BSP29 file with the given lumps (by Quake 1 lump number, the others empty) and `tail`
// appended after them (where ericw-tools puts its BSPX directory).
std::vector<uint8_t> quake1File(const std::map<int, std::vector<uint8_t>>& lumps, const std::vector<uint8_t>& tail = {}) {
  std::vector<uint8_t> out;
  appendU32(out, 29);
  std::vector<uint8_t> data;
  for (int l = 0; l < 15; ++l) {
    const auto it = lumps.find(l);
    appendU32(out, static_cast<uint32_t>(4 + 15 * 8 + data.size()));
    appendU32(out, it == lumps.end() ? 0 : static_cast<uint32_t>(it->second.size()));
    if (it != lumps.end()) data.insert(data.end(), it->second.begin(), it->second.end());
  }
  out.insert(out.end(), data.begin(), data.end());
  out.insert(out.end(), tail.begin(), tail.end());
  return out;
}

} // namespace

// Found while fuzzing (tests/fuzz): directory slots that all name one miptex record each copied
// it, so a lump of a few KB grew to a copy per slot (64 KB: a GB).
TEST(BspFile, MiptexSlotsSharingOneRecordAreRejected) {
  constexpr uint32_t kSlots = 2000;
  std::vector<uint8_t> textures;
  appendU32(textures, kSlots);
  for (uint32_t i = 0; i < kSlots; ++i) appendU32(textures, 4 + 4 * kSlots); // all at the one record
  const std::vector<uint8_t> record = [] {
    std::vector<uint8_t> r(16, 0);
    std::memcpy(r.data(), "brick", 5);
    appendU32(r, 64); // width
    appendU32(r, 64); // height
    for (uint32_t mip : {40u, 40u + 4096, 40u + 5120, 40u + 5376}) appendU32(r, mip);
    r.resize(40 + 5440, 7);
    return r;
  }();
  textures.insert(textures.end(), record.begin(), record.end());
  const std::string message = expectThrowMessage(quake1File({{2, textures}}));
  EXPECT_NE(message.find("test.bsp: error: lump 'textures': texture 2 at offset 8004 shares its record"), std::string::npos) << message;

  // One slot per record is what compilers write, also when a slot is left empty (-1).
  std::vector<uint8_t> ok;
  appendU32(ok, 2);
  appendU32(ok, 12);
  appendU32(ok, 0xffffffffu);
  ok.insert(ok.end(), record.begin(), record.end());
  const BspFile bsp = bt::bsp::readBspFile(quake1File({{2, ok}}), "test.bsp");
  ASSERT_EQ(bsp.miptex.size(), 2u);
  EXPECT_EQ(bsp.miptex[0].name, "brick");
  EXPECT_EQ(bsp.miptex[0].bytes.size(), record.size());
  EXPECT_FALSE(bsp.miptex[1].present);
}

// The same for BSPX lumps: entries naming the same bytes again each copied them (a few MB of
// directory naming the whole file: terabytes).
TEST(BspFile, OverlappingBspxLumpsAreRejected) {
  const std::vector<uint8_t> entities = {'{', '}', '\n', 0};
  auto bspxFile = [&](const std::vector<std::pair<uint32_t, uint32_t>>& lumps) {
    std::vector<uint8_t> tail = {'B', 'S', 'P', 'X'};
    appendU32(tail, static_cast<uint32_t>(lumps.size()));
    for (size_t i = 0; i < lumps.size(); ++i) {
      std::vector<uint8_t> name(24, 0);
      name[0] = static_cast<uint8_t>('A' + i);
      tail.insert(tail.end(), name.begin(), name.end());
      appendU32(tail, lumps[i].first);
      appendU32(tail, lumps[i].second);
    }
    return quake1File({{0, entities}}, tail);
  };
  const size_t size = bspxFile({{0, 0}, {0, 0}}).size();
  // Two lumps side by side are read; the same two lumps over the whole file are not.
  const BspFile bsp = bt::bsp::readBspFile(bspxFile({{0, 64}, {64, 64}}), "test.bsp");
  ASSERT_EQ(bsp.bspx.size(), 2u);
  EXPECT_EQ(bsp.bspx[1].name, "B");
  EXPECT_EQ(bsp.bspx[1].bytes.size(), 64u);
  const std::string message = expectThrowMessage(bspxFile({{0, uint32_t(size)}, {0, uint32_t(size)}}));
  EXPECT_NE(message.find("test.bsp: error: lump 'BSPX B': the BSPX lumps overlap"), std::string::npos) << message;
}

// Each face owns its run of surfedges. Faces that all named one long run each became a polygon
// of it: 200 KB of faces cost half a GB and seconds (found while checking the fuzzers' cost).
TEST(BspFile, FacesSharingSurfedgesAreRejected) {
  auto f32 = [](std::vector<uint8_t>& out, float v) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    appendU32(out, bits);
  };
  auto u16 = [](std::vector<uint8_t>& out, uint16_t v) { out.insert(out.end(), {uint8_t(v), uint8_t(v >> 8)}); };
  std::vector<uint8_t> planes, textures, vertices, texinfo, edges;
  for (float v : {0.0f, 0.0f, 1.0f, 0.0f}) f32(planes, v);
  appendU32(planes, 2);
  appendU32(textures, 1);
  appendU32(textures, 8);
  textures.resize(textures.size() + 16, 0);
  textures[8] = 'a';
  for (uint32_t v : {16u, 16u, 0u, 0u, 0u, 0u}) appendU32(textures, v); // no pixels in the file
  for (float v : {0.0f, 0.0f, 0.0f, 64.0f, 0.0f, 0.0f, 0.0f, 64.0f, 0.0f}) f32(vertices, v);
  for (float v : {1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f}) f32(texinfo, v);
  appendU32(texinfo, 0); // miptex
  appendU32(texinfo, 0); // flags
  for (uint16_t v : {0, 1, 1, 2, 2, 0}) u16(edges, v);
  auto level = [&](const std::vector<std::pair<int32_t, int16_t>>& runs, int surfedgeCount) {
    std::vector<uint8_t> faces, surfedges;
    for (const auto& [first, count] : runs) {
      u16(faces, 0); // plane
      u16(faces, 0); // side
      appendU32(faces, static_cast<uint32_t>(first));
      u16(faces, static_cast<uint16_t>(count));
      u16(faces, 0);                 // texinfo
      appendU32(faces, 0xffffffffu); // no light styles
      appendU32(faces, 0xffffffffu); // no lightmap
    }
    for (int i = 0; i < surfedgeCount; ++i) appendU32(surfedges, static_cast<uint32_t>(i % 3));
    return quake1File({{1, planes}, {2, textures}, {3, vertices}, {6, texinfo}, {7, faces}, {12, edges}, {13, surfedges}});
  };
  const BspFile ok = bt::bsp::readBspFile(level({{0, 3}, {3, 3}}, 6), "test.bsp");
  ASSERT_EQ(ok.faces.size(), 2u);
  EXPECT_EQ(ok.faceVertices(1).size(), 3u);
  const std::string message = expectThrowMessage(level({{0, 3}, {0, 3}}, 3));
  EXPECT_NE(message.find("test.bsp: error: lump 'faces': record 1: the faces share surfedges"), std::string::npos) << message;
}

// Quake 3's surfaces may share index lists (q3map2 reuses identical ones), never vertices, and a
// surface of V vertices has at most 2V triangles. Surfaces that all named one long run of
// indexes (or vertices) each became its triangles again: quadratic memory in the file size.
TEST(BspFile, Quake3SurfacesSharingVerticesOrWithFarMoreTrianglesThanVerticesAreRejected) {
  struct SurfaceRecord {
    int32_t firstVertex, vertexCount, firstIndex, indexCount;
  };
  auto quake3File = [](const std::vector<SurfaceRecord>& surfaces, uint32_t vertexCount, const std::vector<int32_t>& indexes) {
    std::map<int, std::vector<uint8_t>> lumps;
    lumps[1].resize(64 + 8, 0); // one shader, "a"
    lumps[1][0] = 'a';
    lumps[10].resize(size_t{44} * vertexCount, 0);
    for (int32_t i : indexes) appendU32(lumps[11], static_cast<uint32_t>(i));
    for (const SurfaceRecord& s : surfaces) {
      std::vector<uint8_t>& out = lumps[13];
      for (int32_t v : {0, -1, 1, s.firstVertex, s.vertexCount, s.firstIndex, s.indexCount, -1}) appendU32(out, static_cast<uint32_t>(v));
      out.resize(out.size() + 104 - 32, 0);
    }
    std::vector<uint8_t> file = {'I', 'B', 'S', 'P'};
    appendU32(file, 46);
    std::vector<uint8_t> data;
    for (int l = 0; l < 17; ++l) {
      const std::vector<uint8_t>& bytes = lumps[l];
      appendU32(file, static_cast<uint32_t>(8 + 17 * 8 + data.size()));
      appendU32(file, static_cast<uint32_t>(bytes.size()));
      data.insert(data.end(), bytes.begin(), bytes.end());
    }
    file.insert(file.end(), data.begin(), data.end());
    return file;
  };
  // Two triangles with vertices of their own, sharing one index list: what q3map2 writes.
  const BspFile ok = bt::bsp::readBspFile(quake3File({{0, 3, 0, 3}, {3, 3, 0, 3}}, 6, {0, 1, 2}), "test.bsp");
  EXPECT_EQ(ok.surfaces.size(), 2u);

  std::string message = expectThrowMessage(quake3File({{0, 3, 0, 3}, {0, 3, 0, 3}}, 3, {0, 1, 2}));
  EXPECT_NE(message.find("test.bsp: error: lump 'surfaces': record 1: the surfaces share drawverts"), std::string::npos) << message;
  // A mesh may use its vertices in more triangles than a plane triangulation (a model with
  // handles): 24 triangles on 3 vertices, 72 indexes, is still accepted; one more is not.
  std::vector<int32_t> many;
  for (int i = 0; i < 24; ++i) many.insert(many.end(), {0, 1, 2});
  EXPECT_EQ(bt::bsp::readBspFile(quake3File({{0, 3, 0, 72}}, 3, many), "test.bsp").surfaces.size(), 1u);
  many.insert(many.end(), {0, 1, 2});
  message = expectThrowMessage(quake3File({{0, 3, 0, 75}}, 3, many));
  EXPECT_NE(message.find("test.bsp: error: lump 'surfaces': record 0: 75 indexes for 3 vertices"), std::string::npos) << message;
}
