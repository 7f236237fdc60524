// Quake 3 patches in .map files: patchDef2/patchDef3 built into meshes with their st, bad ones
// skipped with a warning naming the line, and the text kept verbatim for the writer.
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"
#include "importers/map/map_writer.h"

#include <gtest/gtest.h>

namespace bt::map {
namespace {

// A flat 3x3 patch on z = 8 spanning 128 x 64 units, st 0..2 along x and 0..1 along y.
const std::string kFlatPatch = "{\npatchDef2\n{\nfloor\n( 3 3 0 0 0 )\n(\n"
                               "( ( 0 0 8 0 0 ) ( 0 32 8 0 0.5 ) ( 0 64 8 0 1 ) )\n"
                               "( ( 64 0 8 1 0 ) ( 64 32 8 1 0.5 ) ( 64 64 8 1 1 ) )\n"
                               "( ( 128 0 8 2 0 ) ( 128 32 8 2 0.5 ) ( 128 64 8 2 1 ) )\n)\n}\n}\n";

std::string worldWith(const std::string& blocks) {
  return "// Format: Quake3 (legacy)\n{\n\"classname\" \"worldspawn\"\n" + blocks + "}\n";
}

TEST(MapPatches, FlatPatchBecomesTwoTrianglesWithTexelSt) {
  const Scene scene = buildScene(parseMap(worldWith(kFlatPatch), "p.map"));
  ASSERT_EQ(scene.meshes.size(), 1u);
  const Mesh& mesh = scene.meshes[0];
  EXPECT_EQ(mesh.line, 5); // the patchDef2 keyword
  EXPECT_EQ(mesh.kind, MeshKind::Curve);
  ASSERT_EQ(mesh.faceCount, 4u); // straight both ways: the corners alone, two triangles, two sides each
  for (uint32_t f = mesh.firstFace; f < mesh.firstFace + mesh.faceCount; ++f) {
    const Face& face = scene.faces[f];
    EXPECT_EQ(face.texture, "floor");
    EXPECT_EQ(face.brush, kNoBrush);
    EXPECT_EQ(std::abs(face.plane.normal.z), 1.0);
    // 64x64 without loaded textures: s = x / 64 * 64 texels per unit of st.
    for (const dvec3& p : face.winding) {
      EXPECT_NEAR(face.frame.s(p), p.x, 1e-9);
      EXPECT_NEAR(face.frame.t(p), p.y, 1e-9);
    }
  }
  EXPECT_EQ(scene.bounds.min, dvec3(0, 0, 8));
  EXPECT_EQ(scene.bounds.max, dvec3(128, 64, 8));
}

TEST(MapPatches, MalformedPatchesAreSkippedWithTheirLine) {
  const std::string even = "{\npatchDef2\n{\nfloor\n( 2 3 0 0 0 )\n(\n( ( 0 0 0 0 0 ) ( 0 1 0 0 0 ) ( 0 2 0 0 0 ) )\n"
                           "( ( 1 0 0 0 0 ) ( 1 1 0 0 0 ) ( 1 2 0 0 0 ) )\n)\n}\n}\n";
  const std::string truncated = "{\npatchDef2\n{\nfloor\n( 3 3 0 0 0 )\n(\n( ( 0 0 0 0 0 ) ( 0 1 0 zero 0 ) )\n)\n}\n}\n";
  const Scene scene = buildScene(parseMap(worldWith(even + truncated + kFlatPatch), "bad.map"));
  EXPECT_EQ(scene.meshes.size(), 1u);
  std::vector<Diagnostic> warnings;
  for (const Diagnostic& d : scene.diagnostics)
    if (d.severity == Severity::Warning) warnings.push_back(d);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].file, "bad.map");
  EXPECT_EQ(warnings[0].line, 5);
  EXPECT_NE(warnings[0].message.find("2x3"), std::string::npos) << warnings[0].message;
  EXPECT_EQ(warnings[1].line, 21); // the line of the bad number
  EXPECT_NE(warnings[1].message.find("'zero'"), std::string::npos) << warnings[1].message;
}

TEST(MapPatches, WriterKeepsThemVerbatim) {
  const MapDocument doc = parseMap(worldWith(kFlatPatch), "p.map");
  const std::string written = writeMap(doc);
  EXPECT_NE(written.find("patchDef2\n{\nfloor\n( 3 3 0 0 0 )"), std::string::npos) << written;
  EXPECT_EQ(parseMap(written, "q.map"), doc);
}

} // namespace
} // namespace bt::map
