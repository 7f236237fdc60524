// TraceScene::entersBox against intersectBrush, brush by brush, on real levels: the CPU bake's
// shadow rays test a solid recent blocker that is a box with it, and its luxels must not move.
#include "bvh/trace_scene.h"
#include "importers/import.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <random>

namespace bt {
namespace {

class EntersBoxOnSharedMap : public ::testing::TestWithParam<const char*> {};

TEST_P(EntersBoxOnSharedMap, AnswersAsIntersectBrush) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path path = shared / "maps" / GetParam();
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  const Scene scene = importScene(path.string(), {.textures = {.load = false}});
  const TraceScene ts = TraceScene::build(scene);
  std::vector<uint32_t> boxes; // the brushes entersBox answers for
  for (uint32_t slot = 0; slot < ts.brushes().size(); ++slot)
    if (ts.entersBox(RayContext(Ray{glm::vec3(0.0f), 0.0f, glm::vec3(1.0f)}), slot)) boxes.push_back(slot);
  ASSERT_GT(boxes.size(), ts.brushes().size() / 4);

  // Random rays (on the boxes' grid planes, with tMin and tMax among them), and rays aimed at a
  // box's corner from outside, ending there or beyond: the ties of an entry at tMin, tMax or an edge.
  std::vector<Ray> rays = test::randomRays(ts.bounds(), 400, 11);
  std::mt19937 rng(5);
  for (int i = 0; i < 400; ++i) {
    const GpuBrush& b = ts.brushes()[boxes[rng() % boxes.size()]];
    const glm::vec3 corner(i & 1 ? b.boundsMax[0] : b.boundsMin[0], i & 2 ? b.boundsMax[1] : b.boundsMin[1],
                           i & 4 ? b.boundsMax[2] : b.boundsMin[2]);
    const Ray r = rays[size_t(i)];
    rays.push_back(Ray{r.origin, 0.0f, corner - r.origin, i & 8 ? 1.0f : 2.0f});
  }
  int entered = 0, zero = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const RayContext r(rays[i]);
    for (uint32_t slot : boxes) {
      const std::optional<bool> enters = ts.entersBox(r, slot);
      if (!enters) {
        EXPECT_TRUE(r.hasZeroComponent) << "ray " << i << ", brush " << slot;
        ++zero;
        continue;
      }
      const std::optional<Hit> hit = ts.intersectBrush(rays[i], slot);
      ASSERT_EQ(*enters, hit && !hit->inside) << "ray " << i << ", brush " << slot;
      entered += *enters;
    }
  }
  EXPECT_GT(entered, 1000);
  EXPECT_GT(zero, 0); // rays with a zero direction component are left to intersectBrush
}

INSTANTIATE_TEST_SUITE_P(Maps, EntersBoxOnSharedMap, ::testing::Values("quake_map_source/e1m1.map", "librequake/lq1/maps/src/dm/lqdm5.map"),
                         [](const auto& info) { return std::filesystem::path(info.param).stem().string(); });

} // namespace
} // namespace bt
