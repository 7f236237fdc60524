// The faces qbsp makes of a side (lighting/qbsp_faces.h), against the compiler's own in the
// oracle .bsp: q2_areaportals' third room (x 320..496), whose light is all bounced from those
// faces. qbsp's tree puts the north wall's plane (y 176) above the doorway's top (z 192), so the
// wall's pieces either side of that plane merge on the wall's node and the 240-texel subdivision
// cuts the whole wall at z 128; the east wall's plane (x 496) comes below z 192, which cuts it.
// Then qbsp's T-junction fix re-cuts the faces with their neighbours' vertices on their edges.
#include "importers/bsp/bsp_file.h"
#include "importers/import.h"
#include "lighting/bounce.h"
#include "lighting/qbsp_faces.h"
#include "lighting/qbsp_tjunc.h"
#include "lighting/render_scene.h"
#include "tests/render/oracle_levels.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace bt {
namespace {

using Box = std::array<double, 6>; // min x y z, max x y z

Box boxOf(const std::vector<dvec3>& polygon) {
  Bounds b;
  for (const dvec3& p : polygon) b.grow(p);
  return {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z};
}

// The boxes of the pieces of the side on `plane` (its outward normal and distance) within x
// xMin..xMax (the third room by default).
std::vector<Box> piecesOf(const Scene& scene, const std::vector<BrushContents>& contents, const QbspTree& world, const Plane& plane,
                          double xMin = 320.0, double xMax = 512.0) {
  std::vector<Box> boxes;
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    const Plane& p = scene.faces[f].plane;
    if (glm::length(p.normal - plane.normal) > 1e-6 || std::abs(p.dist - plane.dist) > 1e-3) continue;
    for (const std::vector<dvec3>& w : compiledFacePolygons(scene, f, contents, world))
      if (boxOf(w)[0] >= xMin - 1e-3 && boxOf(w)[3] <= xMax + 1e-3) boxes.push_back(boxOf(w));
  }
  std::sort(boxes.begin(), boxes.end());
  return boxes;
}

TEST(QbspFaces, WallsMergeAcrossTheDoorwayPlanesBelowThemAndAreCutByThoseAbove) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/q2_areaportals.map").string(), ImportOptions{});
  const std::vector<BrushContents> contents = brushContents(scene);
  const QbspTree world = worldTree(scene, contents);

  // The compiler's faces 15 (z 96..128) and 13 + 14 (z 128..352) of the .bsp, before its
  // T-junction fix cuts that one into a quad and a triangle (below).
  const std::vector<Box> north = piecesOf(scene, contents, world, Plane{dvec3(0, -1, 0), -176.0});
  EXPECT_EQ(north, (std::vector<Box>{{320, 176, 96, 496, 176, 128}, {320, 176, 128, 496, 176, 352}}));
  // The south wall, its mirror: faces 24 and 22 + 23.
  const std::vector<Box> south = piecesOf(scene, contents, world, Plane{dvec3(0, 1, 0), -432.0});
  EXPECT_EQ(south, (std::vector<Box>{{320, -432, 96, 496, -432, 128}, {320, -432, 128, 496, -432, 352}}));
  // The east wall: faces 67-69 below z 192 and 47-49 above it, each cut at y -208 and 16 by the
  // subdivision (224 texels from y -432).
  const std::vector<Box> east = piecesOf(scene, contents, world, Plane{dvec3(-1, 0, 0), -496.0});
  EXPECT_EQ(east,
            (std::vector<Box>{{496, -432, 96, 496, -208, 192},
                              {496, -432, 192, 496, -208, 352},
                              {496, -208, 96, 496, 16, 192},
                              {496, -208, 192, 496, 16, 352},
                              {496, 16, 96, 496, 176, 192},
                              {496, 16, 192, 496, 176, 352}}));
}

// qbsp merges only faces that look into the same contents: the floor under each doorway looks
// into its func_areaportal (CONTENTS_AREAPORTAL), the rest of the floor into empty space, so the
// doorways' floors are faces of their own (the .bsp's faces 4 and 9) and the middle room's floor
// is cut by the subdivision from its own edge (y 176), as the compiler's faces 5-8 are. Merged
// across the doorways, the middle floor was one polygon from x 16 to 320, subdivided at x 96
// and y -208, and the light it bounced into the third room stood elsewhere (q2_areaportals'
// luxels 88.6 % within 5 % against 99.7 %).
TEST(QbspFaces, FloorUnderAnAreaPortalIsAFaceOfItsOwn) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/q2_areaportals.map").string(), ImportOptions{});
  const std::vector<BrushContents> contents = brushContents(scene);
  const QbspTree world = worldTree(scene, contents);
  const std::vector<Box> floor = piecesOf(scene, contents, world, Plane{dvec3(0, 0, 1), 96.0}, 16.0, 320.0);
  EXPECT_EQ(floor,
            (std::vector<Box>{{16, -208, 96, 48, -48, 96},
                              {48, -432, 96, 288, -272, 96},
                              {48, -272, 96, 288, -48, 96},
                              {48, -48, 96, 288, 176, 96},
                              {288, -208, 96, 320, -48, 96}}));
}

// A face as a set of points (rounded to 1/1000 unit), whatever its first vertex.
using Points = std::vector<std::array<double, 3>>;

// The compiler's faces that bounce light on the side on `plane` within x 320..496 (the third
// room), each as its points, in order.
std::vector<Points> bouncingFacesOf(const RenderScene& rs, const std::vector<BrushContents>& contents, const Plane& plane) {
  std::vector<Points> faces;
  for (const BounceFace& face : bounceFaces(rs, contents)) {
    const Plane& p = rs.scene->faces[face.face].plane;
    if (glm::length(p.normal - plane.normal) > 1e-6 || std::abs(p.dist - plane.dist) > 1e-3) continue;
    if (boxOf(face.polygon)[0] < 320.0 - 1e-3 || boxOf(face.polygon)[3] > 496.0 + 1e-3) continue;
    Points points;
    for (const dvec3& v : face.polygon)
      points.push_back({std::round(v.x * 1e3) / 1e3, std::round(v.y * 1e3) / 1e3, std::round(v.z * 1e3) / 1e3});
    std::sort(points.begin(), points.end());
    faces.push_back(std::move(points));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// Faces of the .bsp (their points in its order) as the bounce sees them: without the points
// where they go straight on, which `light` drops first (qbsp_tjunc.h withoutColinearPoints).
std::vector<Points> asBounced(const std::vector<Winding>& compiled) {
  std::vector<Points> faces;
  for (const Winding& w : compiled) {
    Points points;
    for (const dvec3& v : withoutColinearPoints(w)) points.push_back({v.x, v.y, v.z});
    std::sort(points.begin(), points.end());
    faces.push_back(std::move(points));
  }
  std::sort(faces.begin(), faces.end());
  return faces;
}

// The lightest triangulation of q2_areaportals' north wall above z 128 (qbsp's superface: the
// rectangle with the doorway walls' vertices at z 192 on both sides, from its first point on):
// of the rectangle's equally light diagonals the compiler's, gathered into its two faces (the
// .bsp's faces 13 and 14, a pentagon and a triangle), the larger fan first.
TEST(QbspFaces, LightestTriangulationGathersIntoTheCompilersFans) {
  const Winding superface{{320, 176, 128}, {320, 176, 192}, {320, 176, 352}, {496, 176, 352}, {496, 176, 192}, {496, 176, 128}};
  std::vector<Points> fans;
  for (const Winding& w : minimumWeightFans(superface)) {
    fans.emplace_back();
    for (const dvec3& v : w) fans.back().push_back({v.x, v.y, v.z});
  }
  EXPECT_EQ(fans,
            (std::vector<Points>{{{320, 176, 192}, {320, 176, 352}, {496, 176, 352}, {496, 176, 192}, {496, 176, 128}},
                                 {{320, 176, 128}, {320, 176, 192}, {496, 176, 128}}}));
}

// qbsp's T-junction fix (lighting/qbsp_tjunc.h) as the oracle .bsp has it: each face with the
// vertices of its neighbours on its edges, cut by the lightest triangulation into fans.
TEST(QbspFaces, TJunctionFixCutsTheWallsAndTheFloorAsTheCompilerDoes) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/q2_areaportals.map").string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderSceneOptions options;
  options.bounceLights = false;
  options.visApproxBoxes = RenderSceneOptions::VisBoxes::Off;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  const std::vector<BrushContents> contents = brushContents(scene);

  // The north wall: faces 13-15 of the .bsp. Above z 128 the doorway walls' vertices at z 192 on
  // both sides make a hexagon, cut along its lightest diagonals into a pentagon (a quad with the
  // east side's z 192 on an edge) and a triangle.
  EXPECT_EQ(bouncingFacesOf(rs, contents, Plane{dvec3(0, -1, 0), -176.0}),
            asBounced({{{496, 176, 192}, {496, 176, 128}, {320, 176, 192}, {320, 176, 352}, {496, 176, 352}},
                       {{320, 176, 128}, {320, 176, 192}, {496, 176, 128}},
                       {{496, 176, 128}, {496, 176, 96}, {320, 176, 96}, {320, 176, 128}}}));
  // The floor: faces 0-3. The doorway's corners (x 320, y -208 and -48) and the east wall's
  // subdivision (x 496, y -208 and 16) on its edges.
  EXPECT_EQ(bouncingFacesOf(rs, contents, Plane{dvec3(0, 0, 1), 96.0}),
            asBounced({{{320, -208, 96}, {320, -48, 96}, {496, -208, 96}, {496, -272, 96}, {320, -272, 96}},
                       {{496, -48, 96}, {496, -208, 96}, {320, -48, 96}},
                       {{496, 16, 96}, {496, -48, 96}, {320, -48, 96}, {320, 176, 96}, {496, 176, 96}},
                       {{320, -272, 96}, {496, -272, 96}, {496, -432, 96}, {320, -432, 96}}}));
}

// testsurfacelight's world tree grown from the .map (quake1WorldTree, everywhere) against the
// compiled .bsp's: walked side by side from the root, every .bsp node has our plane at its
// place. Below a .bsp leaf ours may go on (qbsp prunes the nodes whose leaves are all solid).
// The slanted brushes at the lava's west end have two slanted sides of equal value at some
// nodes; qbsp takes the one its side order (AddBrushBevels' swaps) puts first.
int nodesInPlace(const QbspTree& ours, int32_t a, const bsp::BspFile& file, int32_t b) {
  if (b < 0) return 0;
  if (a < 0) return 0;
  const QbspTree::Node& n = ours.nodes()[size_t(a)];
  const bsp::Node& node = file.nodes[size_t(b)];
  const bsp::BspPlane& p = file.planes[size_t(node.plane)];
  if (glm::length(dvec3(p.normal) - n.plane.normal) > 1e-4 || std::abs(double(p.dist) - n.plane.dist) > 0.02) return 0;
  return 1 + nodesInPlace(ours, n.children[0], file, node.children[0]) + nodesInPlace(ours, n.children[1], file, node.children[1]);
}

int nodesUnder(const bsp::BspFile& file, int32_t b) {
  return b < 0 ? 0 : 1 + nodesUnder(file, file.nodes[size_t(b)].children[0]) + nodesUnder(file, file.nodes[size_t(b)].children[1]);
}

TEST(QbspFaces, TestsurfacelightWorldTreeIsTheCompilersNodeForNode) {
  BT_REQUIRE_SHARED(shared);
  const std::string name = "maps_ericw-tools_testmaps_deprecated_testsurfacelight.bsp";
  const Scene scene = importScene(test::oracleSourceMap(shared, name).string(), ImportOptions{});
  Diagnostics diagnostics;
  RenderSceneOptions options;
  options.bounceLights = false;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  const VoidTest voids(scene, rs.tracer);
  std::vector<Winding> everywhere;
  for (const Face& f : scene.faces)
    if (f.winding.size() >= 3) everywhere.push_back(f.winding);
  const QbspTree tree = quake1WorldTree(scene, brushContents(scene), voids, everywhere);
  const bsp::BspFile file = bsp::readBspFile(shared / "oracle" / "lit" / name);
  const int32_t root = file.models[0].headNode[0];
  EXPECT_EQ(nodesUnder(file, root), 349);
  EXPECT_EQ(nodesInPlace(tree, 0, file, root), 349);
}

} // namespace
} // namespace bt
