// The CPU bake's shared shadow work (lighting/shadow_groups.h: the blocker cache, lights dropped
// for a whole group of luxels, lights proved seen by a whole group) against the bake without it,
// every luxel compared, on lqdm5 (2,598 lights behind walls, pillars and fixtures) and every lit
// oracle level (doors, liquids, sky, shadowless brush entities, switchable shadows).
//
// They differ in one known way: where a wall brush and a brush that lets light through (water, a
// shadowless door) share a plane, the ray walk without the cache meets both at the same t, takes
// the later brush's face by the closest-hit tie rule, steps past it and so finds itself inside
// the wall, which it leaves unblocked: light leaks through the wall. The cache tests the wall
// brush alone and finds it blocked, as the compiler does (qbsp's CSG keeps the wall there). So a
// luxel may only be darker with the cache, and such leaks are rare: e1m1 has 65 of 260,075.
#include "importers/import.h"
#include "lighting/lightmap_bake.h"
#include "tests/render/oracle_levels.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <glm/vector_relational.hpp>
#include <gtest/gtest.h>

#include <algorithm>

namespace bt {
namespace {

struct Difference {
  size_t luxels = 0, darker = 0, brighter = 0;
};

// Every `stride`-th face that has a lightmap (a whole level where 1), or the faces `only`, baked
// both ways.
Difference bakeBothWays(const std::filesystem::path& map, uint32_t stride, const std::vector<uint32_t>& only = {}) {
  const Scene scene = importScene(map.string(), ImportOptions{});
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diags);
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < scene.faces.size(); ++f)
    if (faceHasLightmap(rs, f) && (only.empty() ? f % stride == 0 : std::find(only.begin(), only.end(), f) != only.end()))
      faces.push_back(f);
  Lightmaps with = layoutLightmaps(rs, faces), without = with;
  bakeLightmaps(rs, with);
  LightmapBakeOptions plain;
  plain.shadowCache = false;
  bakeLightmaps(rs, without, plain);
  Difference d;
  d.luxels = with.luxels.size();
  for (size_t i = 0; i < with.luxels.size(); ++i) {
    const glm::vec3 a = unpackLuxel(with.luxels[i]), b = unpackLuxel(without.luxels[i]);
    d.darker += glm::all(glm::lessThanEqual(a, b)) && a != b;
    d.brighter += glm::any(glm::greaterThan(a, b));
  }
  std::printf("%s",
              fmt::format("{}: {} luxels, {} darker, {} brighter with the cache\n", map.filename().string(), d.luxels, d.darker, d.brighter)
                  .c_str());
  return d;
}

TEST(ShadowGroups, ChangeNoLuxelOfALargeLevel) {
  BT_REQUIRE_SHARED(shared);
  const Difference d = bakeBothWays(shared / "maps/librequake/lq1/maps/src/dm/lqdm5.map", 60);
  EXPECT_GT(d.luxels, 3000u);
  EXPECT_EQ(d.darker + d.brighter, 0u);
}

// Faces of lqdm5 with luxels whose sample points the bake moved out of a wall, so that a group's
// ray origins are not on one plane: its pyramid proofs take a wider margin. With the flat margin
// 16 of their 2,916 luxels came out brighter with the cache than without (light let through).
TEST(ShadowGroups, ChangeNoLuxelWhereSamplePointsLeaveTheirPlane) {
  BT_REQUIRE_SHARED(shared);
  const Difference d = bakeBothWays(shared / "maps/librequake/lq1/maps/src/dm/lqdm5.map", 1,
                                    {677, 980, 1052, 1197, 2243, 2483, 7241, 9448, 9639, 9669, 10868, 10916});
  EXPECT_GT(d.luxels, 1000u);
  EXPECT_EQ(d.darker + d.brighter, 0u);
}

TEST(ShadowGroups, OnlyStopLightLeaksOfTheLitOracleLevels) {
  BT_REQUIRE_SHARED(shared);
  Difference all;
  for (const char* level : test::kLitLevels) {
    if (std::string_view(level).find("lqdm5") != std::string_view::npos) continue; // above, in part
    const std::filesystem::path map = test::oracleSourceMap(shared, std::string("maps_") + level + ".bsp");
    ASSERT_FALSE(map.empty()) << level;
    const Difference d = bakeBothWays(map, 1);
    all.luxels += d.luxels, all.darker += d.darker, all.brighter += d.brighter;
  }
  EXPECT_EQ(all.brighter, 0u);
  EXPECT_LE(double(all.darker), 0.0005 * double(all.luxels)) << all.darker << " of " << all.luxels;
  // Pinned: a speed-up of the bake must not move a luxel, and one that changes which luxels share
  // a group moves these leaks (falloff.map 3, e1m1 68, q1_surflight_minlight 15, testsurfacelight
  // 91 at session 14). A change that stops more leaks on purpose updates it. 178 since the
  // compiler's visapprox cull (lighting/vis_approx.h), which both bakes apply alike: one more
  // luxel of testsurfacelight (92) now shows its leak, not how many leaks there are. 167 since
  // testsurfacelight's _surface points stand on the faces of qbsp's whole-level tree and its
  // T-junction cuts (quake1WorldTree): other lights, other luxels that leak (81). 169 since its
  // faces start where qbsp's portals and merges start them and its lava welds with detail (83).
  // 163 since a later brush's coplanar side takes the overlap from an earlier one's
  // (visibleFragments): e1m1 loses such doubled faces (256,994 luxels from 260,075) and 6 of its
  // leaks (62).
  EXPECT_EQ(all.darker, 163u);
}

} // namespace
} // namespace bt
