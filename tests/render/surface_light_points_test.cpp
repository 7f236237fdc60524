// Where faithful mode's `_surface` points stand (lighting/surface_lights.h), from a .map, against
// where the compiler put them: ericw-tools `light` spreads them over the faces of the compiled
// .bsp, which the .bsp import reads as they are, so a .bsp import's points are the compiler's.
// A .map import rebuilds those faces (lighting/qbsp_faces.h) with a tree grown on each surface
// alone, where qbsp grows one tree over the whole level: planes of brushes far from a surface
// cut it too, so some points land elsewhere. This test holds how many of the .bsp import's
// points the .map import puts within 0.01 unit and within 8 units (each point matched once).
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
// lights", one of them the template): 72 within 0.01 unit, 84 within 8 units. Every point left
// over stands on the lava's top (z 66), on faces qbsp cut with planes of brushes elsewhere in the
// level (its tree is grown over the whole level) and then re-cut at T-junctions. The .bsp
// import's points are the compiler's: `light` takes only faces that some leaf lists, a liquid's
// face only from a leaf outside the liquid (MakeSurfaceLights), and so does the .bsp import
// (LightmappedFace::takesSurfaceLights); before it did, it spread 123.
constexpr size_t kCompilerPoints = 111;
constexpr size_t kHeldExact = 72, kHeldNear = 84;

std::vector<glm::vec3> surfacePoints(const std::string& level) {
  const Scene scene = importScene(level, ImportOptions{});
  RenderSceneOptions options;
  options.lights.styleZeroOnly = true;
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

} // namespace
} // namespace bt
