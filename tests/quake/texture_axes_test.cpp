#include "quake/texture_axes.h"

#include "importers/bsp/brushes.h"
#include "importers/map/map_geometry.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace bt::quake {
namespace {

using glm::dvec3;

TEST(TextureAxes, TiesKeepTheEarlierTableEntry) {
  // A 45-degree wall between +X and +Y: qbsp's default picks the west-wall entry (s = +Y).
  const TextureAxes axes = textureAxisFromPlane(glm::normalize(dvec3{1, 1, 0}));
  EXPECT_EQ(axes.s, dvec3(0, 1, 0));
  EXPECT_EQ(axes.t, dvec3(0, 0, -1));
  EXPECT_EQ(textureAxisFromPlane(glm::normalize(dvec3{1, 1, 1})).snappedNormal, dvec3(0, 0, 1));
}

// Normals a hair past a tie: qbsp takes the later axis as soon as its dot is strictly greater.
// The .bsp importer once needed 1e-9 more and kept the earlier axis here, while the .map
// importer took the later one; both now ask textureAxisFromPlane.
TEST(TextureAxes, BothImportersPickTheSameAxisJustPastATie) {
  struct Case {
    dvec3 normal;
    dvec3 s;
    dvec3 t;
  };
  const Case cases[] = {
      {{1, 1 + 1e-12, 0}, {1, 0, 0}, {0, 0, -1}},                                                    // south wall wins over west
      {{1e-12, 0, 1}, {1, 0, 0}, {0, -1, 0}},                                                        // floor stays floor
      {{1, 0, 1 - 1e-12}, {0, 1, 0}, {0, 0, -1}},                                                    // west wall loses to nothing earlier
      {{-1, 0, -(1 - 1e-12)}, {0, 1, 0}, {0, 0, -1}}, {{0, -(1 + 1e-12), 1}, {1, 0, 0}, {0, 0, -1}}, // north wall wins over floor
  };
  for (const Case& c : cases) {
    Plane plane;
    plane.normal = glm::normalize(c.normal);
    plane.dist = 8.0;
    const TextureAxes axes = textureAxisFromPlane(plane.normal);
    EXPECT_EQ(axes.s, c.s) << c.normal.x << " " << c.normal.y << " " << c.normal.z;
    EXPECT_EQ(axes.t, c.t);
    const TextureFrame bsp = bsp::paraxialFrame(plane);
    EXPECT_EQ(bsp.tangent, c.s);
    EXPECT_EQ(bsp.bitangent, c.t);
    const map::TexVecs vecs = map::standardVecs(plane, {0.0, 0.0}, 0.0, {1.0, 1.0});
    EXPECT_EQ(vecs.axis[0], c.s);
    EXPECT_EQ(vecs.axis[1], c.t);
  }
}

} // namespace
} // namespace bt::quake
