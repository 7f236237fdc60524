// Faithful `_bounce` on a whole level (LibreQuake's lq_e3m1, worldspawn `_bounce 3`): what the
// preparation cuts short must leave its bounce lights and light grid bit for bit as they were.
// Not under the sanitizers: the reference sweep alone takes seconds.
#include "importers/import.h"
#include "lighting/bounce.h"
#include "lighting/light_grid.h"
#include "lighting/render_scene.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

namespace bt {
namespace {

void expectSameLights(const std::vector<GpuLight>& a, const std::vector<GpuLight>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a[i], &b[i], sizeof(GpuLight)) != 0;
  EXPECT_EQ(differ, 0u) << what << ": lights that differ, of " << a.size();
}

struct E3m1 {
  Scene scene;
  RenderScene rs; // the direct lights and their grid, as makeBounceLights gets them
  std::vector<BrushContents> contents;
  explicit E3m1(const std::filesystem::path& shared)
      : scene(importScene((shared / "maps/librequake/lq1/maps/src/e3/lq_e3m1.map").string(), ImportOptions{})), rs(prepared(scene)),
        contents(brushContents(scene)) {}
  static RenderScene prepared(const Scene& s) {
    Diagnostics diags;
    RenderSceneOptions options;
    options.bounceLights = false;
    return buildRenderScene(s, options, diags);
  }
};

// Its three passes with the default budget: later passes draw among thousands of lights, each
// luxel sweeping those a light grid of them lists (6 800 -> 2 900 on average) instead of all, and
// a luxel sampled again reuses its dirt occlusion. The same lights as the reference (every light
// swept, every dirt ray cast, on one thread); and the same that buildRenderScene adds to the level.
TEST(FaithfulBounceLevel, LqE3m1ShortcutsAndThreadsChangeNoBit) {
  BT_REQUIRE_SHARED(shared);
  const E3m1 level(shared);
  ASSERT_EQ(level.rs.world.bounces, 3);
  BounceBudget budget;
  const BounceLights fast = makeBounceLights(level.rs, level.contents, budget);
  ASSERT_TRUE(fast.sampledLights) << "the path under test: later passes draw";
  ASSERT_GT(fast.madeLights, 20000u);
  BounceBudget reference = budget;
  reference.gatherGridCellsPerAxis = 0;
  reference.reuseDirtOcclusion = false; // lq_e3m1 has `_dirt 1`
  reference.threads = 1;
  const BounceLights swept = makeBounceLights(level.rs, level.contents, reference);
  expectSameLights(fast.lights, swept.lights, "shortcuts on all cores against the reference on one");
  EXPECT_EQ(fast.madeLights, swept.madeLights);
  EXPECT_EQ(fast.sampledLuxels, swept.sampledLuxels);

  Diagnostics diags;
  const RenderScene rs = buildRenderScene(level.scene, {}, diags);
  // The same lights, each with its box for the bakes' cull (vis_approx.h assignBounceVisBoxes).
  std::vector<GpuLight> added(rs.lights.begin() + std::ptrdiff_t(level.rs.lights.size()), rs.lights.end());
  for (GpuLight& l : added) {
    EXPECT_GT(l.visBox, 0u);
    l.visBox = 0;
  }
  expectSameLights(added, fast.lights, "buildRenderScene's bounce lights");
}

// buildRenderScene makes the direct lights' grid, then adds the bounce lights to it
// (extendLightGrid): the grid of every light, as if made at once.
TEST(FaithfulBounceLevel, LqE3m1GridIsMadeOnceAndIsTheGridOfEveryLight) {
  BT_REQUIRE_SHARED(shared);
  const Scene scene = importScene((shared / "maps/librequake/lq1/maps/src/e3/lq_e3m1.map").string(), ImportOptions{});
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const LightGrid all = buildLightGrid(rs.lights, rs.tracer.bounds(), rs.world.scaledist);
  EXPECT_EQ(std::memcmp(&rs.lightGrid.header, &all.header, sizeof(GpuLightGrid)), 0);
  ASSERT_EQ(rs.lightGrid.cells.size(), all.cells.size());
  for (size_t c = 0; c < all.cells.size(); ++c) {
    ASSERT_EQ(rs.lightGrid.cells[c].first, all.cells[c].first) << "cell " << c;
    ASSERT_EQ(rs.lightGrid.cells[c].count, all.cells[c].count) << "cell " << c;
  }
  EXPECT_TRUE(rs.lightGrid.indices == all.indices);
}

} // namespace
} // namespace bt
