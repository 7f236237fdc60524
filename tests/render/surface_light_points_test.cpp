// Where faithful mode's `_surface` points stand (lighting/surface_lights.h), from a .map, against
// where the compiler put them: ericw-tools `light` spreads them over the faces of the compiled
// .bsp, which the .bsp import reads as they are, so a .bsp import's points are the compiler's.
// A .map import rebuilds those faces: a Quake 1 template's are cut by qbsp's tree of the whole
// level, grown as the compiler grows it after filling the void (quake1WorldTree), subdivided,
// then cut at their T-junctions with the world's other faces. This test holds how many of the
// .bsp import's points the .map import puts within 0.01 unit and within 8 units (each point
// matched once).
#include "importers/import.h"
#include "lighting/render_scene.h"
#include "tests/render/oracle_levels.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <vector>

namespace bt {
namespace {

// What the .map import reaches today, of the compiler's 111 points (its log: "112 after surface
// lights", one of them the template): all 111 within 0.01 unit. Session 26 (surf14f) took it from
// 96 and 101 (within 0.01 and 8 units); each rule taken out alone: each face starts where qbsp's
// portal starts it (without any portal start 98 and 101; without the portal's face whole, as qbsp
// makes it however CSG cut the side, 102 and 104), where TryMerge starts it (without:
// q2_areaportals' north wall fans fail in qbsp_faces_test.cpp) and where the subdivision's clip
// does (in our winding: 101 and 107); faces that look into the lava merge with none that look into
// air (without: 103 and 106); Quake 1's liquids weld with detail (without: 103 and 106); a later
// brush's coplanar side takes the overlap from an earlier one's (visibleFragments; without: 107 and
// 110); the world's sides with one texinfo are laid out together, their faces merged across brushes
// (without: 107 and 110). Earlier: with each lava face cut only by planes of a tree grown on that
// surface alone, 72 and 84; with the whole level's tree but without the T-junction cuts, 85 and 93.
// The .bsp import's points are the compiler's: `light` takes only faces that some leaf lists, a
// liquid's face only from a leaf outside the liquid (MakeSurfaceLights), and so does the .bsp
// import (LightmappedFace::takesSurfaceLights); before it did, it spread 123.
constexpr size_t kCompilerPoints = 111;
constexpr size_t kHeldExact = 111, kHeldNear = 111;

std::vector<glm::vec3> surfacePoints(const std::string& level, bool styleZeroOnly = true) {
  const Scene scene = importScene(level, ImportOptions{});
  RenderSceneOptions options;
  options.lights.styleZeroOnly = styleZeroOnly;
  options.bounceLights = false;
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  std::vector<glm::vec3> points;
  for (const GpuLight& l : rs.lights)
    if (l.flags & kLightFlagFromSurface) points.push_back(l.origin);
  return points;
}

// How many of `compiler`'s points have one of `ours` within `tolerance` units, each of ours
// taken once.
size_t matched(const std::vector<glm::vec3>& compiler, std::vector<glm::vec3> ours, float tolerance) {
  size_t n = 0;
  for (const glm::vec3& c : compiler) {
    size_t best = ours.size();
    float bestDistance = std::numeric_limits<float>::infinity();
    for (size_t i = 0; i < ours.size(); ++i)
      if (const float d = glm::distance(c, ours[i]); d < bestDistance) bestDistance = d, best = i;
    if (best == ours.size() || bestDistance > tolerance) continue;
    ours.erase(ours.begin() + std::ptrdiff_t(best));
    ++n;
  }
  return n;
}

TEST(SurfaceLightPoints, TestsurfacelightMapPointsStandWhereTheCompilersDo) {
  BT_REQUIRE_SHARED(shared);
  const std::string bsp = "maps_ericw-tools_testmaps_deprecated_testsurfacelight.bsp";
  const std::filesystem::path map = test::oracleSourceMap(shared, bsp);
  ASSERT_FALSE(map.empty());
  const std::vector<glm::vec3> compiler = surfacePoints((shared / "oracle" / "lit" / bsp).string());
  const std::vector<glm::vec3> ours = surfacePoints(map.string());
  const size_t exact = matched(compiler, ours, 0.01f), near = matched(compiler, ours, 8.0f);
  std::printf("%s",
              fmt::format("testsurfacelight _surface points: .bsp import {}, .map import {}; {} within 0.01 unit, {} within 8 units\n",
                          compiler.size(), ours.size(), exact, near)
                  .c_str());
  ASSERT_EQ(compiler.size(), kCompilerPoints) << "the .bsp import spreads the compiler's points";
  // Held where they are (see the file's comment); the faithful-mode issue (14) wants all.
  EXPECT_GE(exact, kHeldExact);
  EXPECT_GE(near, kHeldNear);
}

// The largest shared level's lava (LibreQuake lq_e4m3: `_surface` "*lava1", "*lava2" and
// "+0lava_fall3") against its compiled .bsp in ../shared/oracle: of the compiler's 1677 points,
// the .map import puts 1550, 770 of them within 0.01 unit and 926 within 8 units (session 25: 1578,
// 769 and 918; with a tree per surface, session 24's start: 1506, 745 and 860). Held where it
// stands: it guards the tree that quake1WorldTree grows only where the templates' faces are
// (qbsp_tree.h's `around`).
constexpr size_t kLqE4m3HeldExact = 770, kLqE4m3HeldNear = 926;
TEST(SurfaceLightPoints, LqE4m3MapPointsStandWhereTheCompilersDo) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path bsp = shared / "oracle" / "maps_librequake_lq1_maps_src_e4_lq_e4m3.bsp";
  const std::filesystem::path map = shared / "maps" / "librequake" / "lq1" / "maps" / "src" / "e4" / "lq_e4m3.map";
  // Its lava lights are switched (a targetname) or styled: every style counts here.
  const std::vector<glm::vec3> compiler = surfacePoints(bsp.string(), false);
  const std::vector<glm::vec3> ours = surfacePoints(map.string(), false);
  const size_t exact = matched(compiler, ours, 0.01f), near = matched(compiler, ours, 8.0f);
  std::printf("%s",
              fmt::format("lq_e4m3 _surface points: .bsp import {}, .map import {}; {} within 0.01 unit, {} within 8 units\n",
                          compiler.size(), ours.size(), exact, near)
                  .c_str());
  EXPECT_GE(exact, kLqE4m3HeldExact);
  EXPECT_GE(near, kLqE4m3HeldNear);
}

} // namespace
} // namespace bt
