#include "importers/map/map_geometry.h"
#include "importers/map/map_parser.h"
#include "importers/map/map_scene.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>

namespace bt::map {
namespace {

// A 64x64x64 box from (0,0,0), faces in TrenchBroom's order: -X, -Y, -Z, +Z, +Y, +X.
std::string boxBrush(const std::string& tail = "a 0 0 0 1 1") {
  return "( 0 0 0 ) ( 0 64 0 ) ( 0 0 64 ) " + tail + "\n( 0 0 0 ) ( 0 0 64 ) ( 64 0 0 ) " + tail + "\n( 0 0 0 ) ( 64 0 0 ) ( 0 64 0 ) " +
      tail + "\n( 64 64 64 ) ( 64 0 64 ) ( 0 64 64 ) " + tail + "\n( 64 64 64 ) ( 0 64 64 ) ( 64 64 0 ) " + tail +
      "\n( 64 64 64 ) ( 64 64 0 ) ( 64 0 64 ) " + tail + "\n";
}

Scene build(const std::string& text) {
  return buildScene(parseMap(text, "t.map"));
}

TEST(MapGeometry, PlaneFromPointsFollowsQuakeOrientation) {
  // Points clockwise seen from outside: the normal points out of the brush.
  const auto plane = planeFromPoints({dvec3{64, 64, 64}, dvec3{64, 0, 64}, dvec3{0, 64, 64}});
  ASSERT_TRUE(plane);
  EXPECT_EQ(plane->normal, dvec3(0, 0, 1));
  EXPECT_EQ(plane->dist, 64.0);
  EXPECT_FALSE(planeFromPoints({dvec3{0, 0, 0}, dvec3{1, 1, 1}, dvec3{2, 2, 2}}));
}

TEST(MapGeometry, BoxWindingsAreCounterClockwiseQuadsOnTheirPlanes) {
  const Scene scene = build("{\n{\n" + boxBrush() + "}\n}\n");
  ASSERT_EQ(scene.faces.size(), 6u);
  EXPECT_TRUE(scene.diagnostics.empty());
  EXPECT_EQ(scene.bounds.min, dvec3(0, 0, 0));
  EXPECT_EQ(scene.bounds.max, dvec3(64, 64, 64));
  for (const Face& f : scene.faces) {
    ASSERT_EQ(f.winding.size(), 4u);
    dvec3 areaNormal{0.0};
    for (size_t i = 0; i < f.winding.size(); ++i) {
      EXPECT_NEAR(f.plane.distanceTo(f.winding[i]), 0.0, 1e-9);
      areaNormal += glm::cross(f.winding[i], f.winding[(i + 1) % f.winding.size()]);
    }
    // Counter-clockwise seen from outside: the polygon's area vector points along the normal.
    EXPECT_NEAR(glm::dot(areaNormal * 0.5, f.plane.normal), 64.0 * 64.0, 1e-6);
  }
}

TEST(MapGeometry, StandardFrameRotatesScalesAndOffsetsLikeQbsp) {
  // Floor face (normal -Z picks the ceiling entry: s = +X, t = -Y), rotated 90 degrees,
  // scale 2 x 0.5, offset 16 x 8. qbsp rotates s = (1,0,0) to (0,1,0) and t = (0,-1,0) to
  // (1,0,0), then divides by the scales.
  const Scene scene = build("{\n{\n" + boxBrush("a 16 8 90 2 0.5") + "}\n}\n");
  const Face& floor = scene.faces[2];
  ASSERT_EQ(floor.plane.normal, dvec3(0, 0, -1));
  const dvec3 p{10, 20, 0};
  EXPECT_NEAR(floor.frame.s(p), 20.0 / 2.0 + 16.0, 1e-9);
  EXPECT_NEAR(floor.frame.t(p), 10.0 / 0.5 + 8.0, 1e-9);
  EXPECT_NEAR(floor.plane.distanceTo(floor.frame.origin), 0.0, 1e-9);
}

TEST(MapGeometry, ValveFrameUsesTheAxesDividedByScale) {
  const Scene scene = build("{\n{\n" + boxBrush("a [ 0.6 0.8 0 5 ] [ 0 0 -1 -3 ] 0 0.5 4") + "}\n}\n");
  const Face& wall = scene.faces[0];
  const dvec3 p{0, 30, 40};
  EXPECT_NEAR(wall.frame.s(p), (0.8 * 30) / 0.5 + 5, 1e-9);
  EXPECT_NEAR(wall.frame.t(p), -40.0 / 4 - 3, 1e-9);
}

TEST(MapGeometry, BrushPrimitiveMatrixActsOnQ3mapAxisBase) {
  // Top face (normal +Z): q3map2's axis base is texX = (0,1,0), texY = (1,0,0); qbsp assumes a
  // 64x64 texture, so s = 64 * (0.5 * y + 0.25) and t = 64 * 0.25 * x.
  const Scene scene = build("{\n{\nbrushDef\n{\n" + boxBrush("( ( 0.5 0 0.25 ) ( 0 0.25 0 ) ) a 0 0 0") + "}\n}\n}\n");
  ASSERT_EQ(scene.faces.size(), 6u);
  const Face& top = scene.faces[3];
  ASSERT_EQ(top.plane.normal, dvec3(0, 0, 1));
  const dvec3 p{10, 20, 64};
  EXPECT_NEAR(top.frame.s(p), 64 * (0.5 * 20 + 0.25), 1e-9);
  EXPECT_NEAR(top.frame.t(p), 64 * 0.25 * 10, 1e-9);
}

TEST(MapGeometry, RepairsAProjectionParallelToThePlaneLikeQbsp) {
  // Valve axes lying along the face normal: qbsp resets the face to default Standard texturing.
  const Scene scene = build("{\n{\n" + boxBrush("a [ 1 0 0 0 ] [ 1 0 0 0 ] 0 1 1") + "}\n}\n");
  const Face& wall = scene.faces[0]; // normal -X: west-wall entry reversed... s = +Y, t = -Z
  EXPECT_EQ(wall.frame.tangent, dvec3(0, 1, 0));
  EXPECT_EQ(wall.frame.bitangent, dvec3(0, 0, -1));
}

TEST(MapGeometry, ReportsDegenerateDuplicateAndUnboundedWithLines) {
  const Scene degenerate = build("{\n{\n" + boxBrush() + "( 0 0 0 ) ( 1 1 1 ) ( 2 2 2 ) a 0 0 0 1 1\n}\n}\n");
  ASSERT_EQ(degenerate.diagnostics.size(), 1u);
  EXPECT_EQ(degenerate.diagnostics[0].line, 9);
  EXPECT_NE(degenerate.diagnostics[0].message.find("collinear"), std::string::npos);
  EXPECT_EQ(degenerate.faces.size(), 6u);

  const Scene duplicate = build("{\n{\n" + boxBrush() + "( 0 0 0 ) ( 0 64 0 ) ( 0 0 64 ) b 0 0 0 1 1\n}\n}\n");
  ASSERT_EQ(duplicate.diagnostics.size(), 1u);
  EXPECT_EQ(format(duplicate.diagnostics[0]), "t.map:9:1: warning: face skipped: same plane as the face on line 3");
  EXPECT_EQ(duplicate.faces.size(), 6u);

  std::string open = boxBrush();
  open.erase(open.rfind("( 64 64 64 )")); // drop the +X face: nothing closes the box
  const Scene unbounded = build("// two brushes\n{\n{\n" + boxBrush() + "}\n{\n" + open + "}\n}\n");
  ASSERT_EQ(unbounded.diagnostics.size(), 1u);
  EXPECT_EQ(format(unbounded.diagnostics[0]), "t.map:11:1: warning: brush skipped: it is unbounded (its faces do not enclose a volume)");
  EXPECT_EQ(unbounded.brushes.size(), 1u);
  EXPECT_EQ(unbounded.entities[0].brushCount, 1u);

  const Scene flat = build("{\n{\n( 0 0 0 ) ( 0 64 0 ) ( 0 0 64 ) a 0 0 0 1 1\n( 0 0 0 ) ( 0 0 64 ) ( 0 64 0 ) a 0 0 0 1 1\n}\n}\n");
  ASSERT_EQ(flat.diagnostics.size(), 1u);
  EXPECT_EQ(format(flat.diagnostics[0]), "t.map:2:1: warning: brush skipped: faces on lines 3 and 4 are opposite on one plane (no volume)");
  EXPECT_TRUE(flat.brushes.empty());
}

// A brush's cost grows with the square of its faces (each clips every other): past 1024 faces
// it is skipped with a warning instead of taking seconds or, a few MB on, minutes.
TEST(MapGeometry, BrushWithMoreThan1024FacesIsSkippedNamingItsLine) {
  // 1025 distinct planes tangent to a sphere, one brush; then an ordinary box.
  std::string ball;
  for (int i = 0; i < 1025; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / 1025.0, r = std::sqrt(1.0 - z * z), phi = i * 2.399963;
    const dvec3 n(r * std::cos(phi), r * std::sin(phi), z), p = 512.0 * n;
    const dvec3 u = glm::normalize(glm::cross(n, std::fabs(z) < 0.9 ? dvec3(0, 0, 1) : dvec3(1, 0, 0)));
    const dvec3 v = glm::cross(n, u);
    auto point = [](const dvec3& q) { return "( " + std::to_string(q.x) + " " + std::to_string(q.y) + " " + std::to_string(q.z) + " ) "; };
    ball += point(p) + point(p + 64.0 * v) + point(p + 64.0 * u) + "a 0 0 0 1 1\n";
  }
  const Scene scene = build("{\n{\n" + ball + "}\n{\n" + boxBrush() + "}\n}\n");
  ASSERT_EQ(scene.diagnostics.size(), 1u);
  EXPECT_EQ(format(scene.diagnostics[0]), "t.map:2:1: warning: brush skipped: it has 1025 faces, more than the 1024 a brush may have");
  EXPECT_EQ(scene.brushes.size(), 1u);
  EXPECT_EQ(scene.faces.size(), 6u);
}

TEST(MapGeometry, MaterialsAreOnePerTextureNameIgnoringCase) {
  const Scene scene = build("{\n{\n" + boxBrush("Wall 0 0 0 1 1") + "}\n{\n" + boxBrush("WALL 0 0 0 1 1").replace(0, 0, "") + "}\n}\n");
  ASSERT_EQ(scene.materials.size(), 1u);
  EXPECT_EQ(scene.materials[0].name, "Wall");
  EXPECT_TRUE(scene.materials[0].missing());
  for (const Face& f : scene.faces) EXPECT_EQ(f.material, 0u);
}

} // namespace
} // namespace bt::map

namespace bt::map {
namespace {

TEST(MapGeometry, QuarkTx1ProjectionFollowsThePlanePoints) {
  // QuArK "etp": p0 is texel (0,0), p2 - p0 spans 128 texels of s, p1 - p0 128 texels of t
  // (negated by the dual basis, as qbsp computes it).
  const std::string top = "( 0 0 64 ) ( 0 32 64 ) ( 64 0 64 ) a 0 0 0 1 1 //TX1\n";
  std::string text = "{\n{\n" + boxBrush();
  const std::string plainTop = "( 64 64 64 ) ( 64 0 64 ) ( 0 64 64 ) a 0 0 0 1 1\n";
  text.replace(text.find(plainTop), plainTop.size(), top);
  const Scene scene = buildScene(parseMap(text + "}\n}\n", "q.map"));
  ASSERT_EQ(scene.faces.size(), 6u);
  const Face& f = scene.faces[3];
  ASSERT_EQ(f.plane.normal, dvec3(0, 0, 1));
  EXPECT_NEAR(f.frame.s({0, 0, 64}), 0.0, 1e-9);
  EXPECT_NEAR(f.frame.t({0, 0, 64}), 0.0, 1e-9);
  EXPECT_NEAR(f.frame.s({64, 0, 64}), 128.0, 1e-9);
  EXPECT_NEAR(f.frame.t({64, 0, 64}), 0.0, 1e-9);
  EXPECT_NEAR(f.frame.s({0, 32, 64}), 0.0, 1e-9);
  EXPECT_NEAR(f.frame.t({0, 32, 64}), -128.0, 1e-9);
}

} // namespace
} // namespace bt::map

#include "importers/import.h"

#include <filesystem>
#include <fstream>

namespace bt::map {
namespace {

TEST(MapImport, BrushDefMatricesAreSizedByTheLoadedTexture) {
  // qbsp sizes a brushDef matrix by the real texture (64x64 only when it is missing).
  const auto dir = std::filesystem::temp_directory_path() / "bt_map_brushdef_size";
  std::filesystem::create_directories(dir);
  {
    // A 128x32 uncompressed true-colour TGA.
    std::ofstream tga(dir / "bp.tga", std::ios::binary);
    const unsigned char header[18] = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 128, 0, 32, 0, 24, 0};
    tga.write(reinterpret_cast<const char*>(header), sizeof header);
    const std::string pixels(128 * 32 * 3, '\x80');
    tga.write(pixels.data(), static_cast<std::streamsize>(pixels.size()));
  }
  std::ofstream(dir / "bp.map") << "{\n\"classname\" \"worldspawn\"\n{\nbrushDef\n{\n"
                                << boxBrush("( ( 0.5 0 0.25 ) ( 0 0.25 0 ) ) bp 0 0 0") << "}\n}\n}\n";
  ImportOptions options;
  options.textures.textureDirs = {dir.string()};
  const Scene scene = importScene((dir / "bp.map").string(), options);
  ASSERT_EQ(scene.materials.size(), 1u);
  ASSERT_EQ(scene.materials[0].width, 128) << toString(scene.materials[0].source);
  ASSERT_EQ(scene.materials[0].height, 32);
  const Face& top = scene.faces.at(3);
  const dvec3 p{10, 20, 64};
  EXPECT_NEAR(top.frame.s(p), 128 * (0.5 * 20 + 0.25), 1e-9);
  EXPECT_NEAR(top.frame.t(p), 32 * 0.25 * 10, 1e-9);
  std::filesystem::remove_all(dir);
}

} // namespace
} // namespace bt::map
