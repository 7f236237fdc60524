// The faces qbsp makes of a side (lighting/qbsp_faces.h), against the compiler's own in the
// oracle .bsp: q2_areaportals' third room (x 320..496), whose light is all bounced from those
// faces. qbsp's tree puts the north wall's plane (y 176) above the doorway's top (z 192), so the
// wall's pieces either side of that plane merge on the wall's node and the 240-texel subdivision
// cuts the whole wall at z 128; the east wall's plane (x 496) comes below z 192, which cuts it.
#include "importers/import.h"
#include "lighting/qbsp_faces.h"
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

// The boxes of the pieces of the side on `plane` (its outward normal and distance).
std::vector<Box> piecesOf(const Scene& scene, const std::vector<BrushContents>& contents, const QbspTree& world, const Plane& plane) {
  std::vector<Box> boxes;
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    const Plane& p = scene.faces[f].plane;
    if (glm::length(p.normal - plane.normal) > 1e-6 || std::abs(p.dist - plane.dist) > 1e-3) continue;
    for (const std::vector<dvec3>& w : compiledFacePolygons(scene, f, contents, world))
      if (boxOf(w)[0] >= 320.0 - 1e-3 && boxOf(w)[3] <= 512.0 + 1e-3) boxes.push_back(boxOf(w));
  }
  std::sort(boxes.begin(), boxes.end());
  return boxes;
}

TEST(QbspFaces, WallsMergeAcrossTheDoorwayPlanesBelowThemAndAreCutByThoseAbove) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/ericw-tools/testmaps/q2_areaportals.map").string(), ImportOptions{});
  const std::vector<BrushContents> contents = brushContents(scene);
  const QbspTree world = worldTree(scene, contents);

  // The compiler's faces 15 (z 96..128) and 13 + 14 (z 128..352; its T-junction fix cuts that
  // one into a quad and a triangle, not modelled) of the .bsp.
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

} // namespace
} // namespace bt
