// The BVH builder: structure (every brush once, bounds nest, depth), SAH quality against the
// full-sweep reference, determinism across thread counts, and brush exclusion.
#include "bvh/trace_scene.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/bvh/full_sweep_sah.h"
#include "tests/bvh/generated_scenes.h"

#include <gtest/gtest.h>

#include <cstring>

namespace bt {
namespace {

bool contains(const float* outerMin, const float* outerMax, const float* innerMin, const float* innerMax) {
  for (int a = 0; a < 3; ++a)
    if (innerMin[a] < outerMin[a] || innerMax[a] > outerMax[a]) return false;
  return true;
}

// Walks the tree from the root and checks everything a traversal relies on.
void expectWellFormed(const TraceScene& ts) {
  const auto nodes = ts.nodes();
  const auto brushes = ts.brushes();
  if (brushes.empty()) {
    EXPECT_TRUE(nodes.empty());
    return;
  }
  ASSERT_FALSE(nodes.empty());
  std::vector<int> brushSeen(brushes.size(), 0), nodeSeen(nodes.size(), 0);
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 0}}; // node, depth
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    ASSERT_LT(index, nodes.size());
    ++nodeSeen[index];
    ASSERT_LE(depth, kBvhMaxDepth);
    const GpuBvhNode& n = nodes[index];
    if (n.count > 0) {
      ASSERT_LE(n.leftFirst + n.count, brushes.size());
      for (uint32_t b = n.leftFirst; b < n.leftFirst + n.count; ++b) {
        ++brushSeen[b];
        EXPECT_TRUE(contains(n.boundsMin, n.boundsMax, brushes[b].boundsMin, brushes[b].boundsMax)) << "brush " << b;
      }
    } else {
      ASSERT_LT(n.leftFirst + 1, nodes.size());
      for (uint32_t c : {n.leftFirst, n.leftFirst + 1}) {
        EXPECT_TRUE(contains(n.boundsMin, n.boundsMax, nodes[c].boundsMin, nodes[c].boundsMax)) << "node " << c;
        stack.push_back({c, depth + 1});
      }
    }
  }
  for (size_t b = 0; b < brushes.size(); ++b) EXPECT_EQ(brushSeen[b], 1) << "brush " << b << " reached that often";
  for (size_t n = 0; n < nodes.size(); ++n) EXPECT_EQ(nodeSeen[n], 1) << "node " << n << " reached that often";
}

// Every scene brush with a winding is in brushes() exactly once, with its faces split into
// the axial slots and the side list.
void expectAllBrushesPresent(const Scene& scene, const TraceScene& ts) {
  std::vector<int> seen(scene.brushes.size(), 0);
  for (const GpuBrush& g : ts.brushes()) {
    ASSERT_LT(g.sceneBrush, scene.brushes.size());
    ++seen[g.sceneBrush];
    const Brush& b = scene.brushes[g.sceneBrush];
    uint32_t facesWithWinding = 0;
    for (uint32_t f = b.firstFace; f < b.firstFace + b.faceCount; ++f) facesWithWinding += !scene.faces[f].winding.empty();
    uint32_t axial = 0;
    for (uint32_t f : g.axialFace) axial += f != kNoFace;
    EXPECT_LE(axial + g.sideCount, facesWithWinding);
    for (uint32_t i = g.firstSide; i < g.firstSide + g.sideCount; ++i) {
      const uint32_t f = ts.sides()[i];
      EXPECT_GE(f, b.firstFace);
      EXPECT_LT(f, b.firstFace + b.faceCount);
    }
  }
  for (size_t b = 0; b < scene.brushes.size(); ++b) EXPECT_EQ(seen[b], 1) << "scene brush " << b;
}

std::vector<Aabb> brushBoxes(const TraceScene& ts) {
  std::vector<Aabb> boxes;
  for (const GpuBrush& g : ts.brushes())
    boxes.push_back({{g.boundsMin[0], g.boundsMin[1], g.boundsMin[2]}, {g.boundsMax[0], g.boundsMax[1], g.boundsMax[2]}});
  return boxes;
}

void expectSahNearFullSweep(const TraceScene& ts, int leafSize, const char* what) {
  const FlatBvh reference = test::buildFullSweepSah(brushBoxes(ts), leafSize);
  const double full = sahCost(reference.nodes);
  ASSERT_GT(full, 0.0);
  ::testing::Test::RecordProperty(std::string(what) + "_binned_sah", std::to_string(ts.sahCost()));
  ::testing::Test::RecordProperty(std::string(what) + "_full_sweep_sah", std::to_string(full));
  EXPECT_LE(ts.sahCost(), 1.03 * full) << what << ": binned " << ts.sahCost() << " vs full sweep " << full;
  std::printf("%s: binned SAH %.3f, full sweep %.3f (ratio %.4f)\n", what, ts.sahCost(), full, ts.sahCost() / full);
}

TEST(BvhBuild, EmptySceneHasNoNodesAndNoHits) {
  const TraceScene ts = TraceScene::build(Scene{});
  EXPECT_TRUE(ts.nodes().empty());
  EXPECT_TRUE(ts.brushes().empty());
  EXPECT_EQ(ts.sahCost(), 0.0);
  EXPECT_FALSE(ts.closestHit({{0, 0, 0}, 0.0f, {1, 0, 0}}).has_value());
  EXPECT_FALSE(ts.occluded({{0, 0, 0}, 0.0f, {1, 0, 0}}));
}

TEST(BvhBuild, SingleBrushIsOneLeaf) {
  Scene scene;
  test::addBox(scene, {0, 0, 0}, {64, 32, 16});
  const TraceScene ts = TraceScene::build(scene);
  ASSERT_EQ(ts.nodes().size(), 1u);
  EXPECT_EQ(ts.nodes()[0].count, 1u);
  EXPECT_EQ(ts.sahCost(), 1.0); // one leaf with one brush, area ratio 1
  EXPECT_EQ(ts.brushes()[0].sideCount, 0u); // a box is all axial
}

TEST(BvhBuild, SahCostFollowsTheCostModel) {
  // Root [0,2]^3 (half-area 12) over two leaves [0,1]^3 (3) with 1 box and [1,2]^3 with 2:
  // 1 * 12/12 + 1 * 3/12 + 2 * 3/12 = 1.75.
  const GpuBvhNode nodes[] = {{{0, 0, 0}, 1, {2, 2, 2}, 0}, {{0, 0, 0}, 0, {1, 1, 1}, 1}, {{1, 1, 1}, 1, {2, 2, 2}, 2}};
  EXPECT_DOUBLE_EQ(sahCost(nodes), 1.75);
}

TEST(BvhBuild, EveryBrushReachableExactlyOnce) {
  for (const auto& [name, scene] : {std::pair{"level", test::generateLevel(3000, 1).scene},
                                    std::pair{"random", test::generateRandomBrushes(3000, 2)}}) {
    SCOPED_TRACE(name);
    for (int leafSize : {1, 4, 16}) {
      const TraceScene ts = TraceScene::build(scene, {.leafSize = leafSize});
      expectWellFormed(ts);
      expectAllBrushesPresent(scene, ts);
    }
  }
}

TEST(BvhBuild, BinnedSahWithin3PercentOfFullSweep) {
  const Scene level = test::generateLevel(3000, 3).scene;
  const Scene random = test::generateRandomBrushes(3000, 4);
  expectSahNearFullSweep(TraceScene::build(level), 4, "level 3k");
  expectSahNearFullSweep(TraceScene::build(random), 4, "random 3k");
  expectSahNearFullSweep(TraceScene::build(level, {.leafSize = 1}), 1, "level 3k leaf 1");
  expectSahNearFullSweep(TraceScene::build(random, {.leafSize = 8}), 8, "random 3k leaf 8");
}

TEST(BvhBuild, LayoutDoesNotDependOnThreadCount) {
  // Big enough that subtrees are built on other threads.
  const Scene scene = test::generateRandomBrushes(20000, 5);
  const TraceScene one = TraceScene::build(scene, {.threads = 1});
  const TraceScene four = TraceScene::build(scene, {.threads = 4});
  ASSERT_EQ(one.nodes().size(), four.nodes().size());
  ASSERT_EQ(one.brushes().size(), four.brushes().size());
  EXPECT_EQ(std::memcmp(one.nodes().data(), four.nodes().data(), one.nodes().size_bytes()), 0);
  EXPECT_EQ(std::memcmp(one.brushes().data(), four.brushes().data(), one.brushes().size_bytes()), 0);
  EXPECT_EQ(one.sahCost(), four.sahCost());
  expectWellFormed(four);
}

TEST(BvhBuild, ExcludedBrushesAreNeitherStoredNorHit) {
  Scene scene;
  test::addBox(scene, {0, -16, -16}, {16, 16, 16});  // 0: nearer along +X
  test::addBox(scene, {32, -16, -16}, {48, 16, 16}); // 1
  const Ray ray{{-100, 0, 0}, 0.0f, {1, 0, 0}};

  const TraceScene all = TraceScene::build(scene);
  ASSERT_TRUE(all.closestHit(ray));
  EXPECT_EQ(all.closestHit(ray)->brush, 0u);

  const TraceScene without0 = TraceScene::build(scene, {.includeBrush = {false, true}});
  ASSERT_EQ(without0.brushes().size(), 1u);
  EXPECT_EQ(without0.brushes()[0].sceneBrush, 1u);
  ASSERT_TRUE(without0.closestHit(ray));
  EXPECT_EQ(without0.closestHit(ray)->brush, 1u);
  EXPECT_FLOAT_EQ(without0.closestHit(ray)->t, 132.0f);

  EXPECT_THROW(TraceScene::build(scene, {.includeBrush = {true}}), std::invalid_argument);
}

TEST(BvhBuild, BrushWithoutWindingsIsSkipped) {
  Scene scene;
  test::addBox(scene, {0, 0, 0}, {16, 16, 16});
  test::addBox(scene, {32, 0, 0}, {48, 16, 16});
  for (uint32_t f = scene.brushes[1].firstFace; f < scene.brushes[1].firstFace + scene.brushes[1].faceCount; ++f)
    scene.faces[f].winding.clear();
  const TraceScene ts = TraceScene::build(scene);
  ASSERT_EQ(ts.brushes().size(), 1u);
  EXPECT_EQ(ts.brushes()[0].sceneBrush, 0u);
  EXPECT_EQ(ts.faces().size(), scene.faces.size()); // faces stay indexable by scene index
}

TEST(BvhBuild, NeighbourBoxesShareTheirFloatBoundary) {
  // 0.1 is not a float: both sides of the shared face must round to the same float, so the
  // two brushes neither overlap nor leave a gap.
  Scene scene;
  test::addBox(scene, {-1.0, 0, 0}, {0.1, 1, 1});
  test::addBox(scene, {0.1, 0, 0}, {1.0, 1, 1});
  const TraceScene ts = TraceScene::build(scene);
  const GpuBrush* a = nullptr;
  const GpuBrush* b = nullptr;
  for (const GpuBrush& g : ts.brushes()) (g.sceneBrush == 0 ? a : b) = &g;
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->boundsMax[0], b->boundsMin[0]);
  EXPECT_EQ(a->boundsMax[0], 0.1f);
}

TEST(BvhBuild, DegenerateInputStaysShallow) {
  // Boxes whose sizes form a geometric series around one corner: the SAH peels one box per
  // level, the chain the median fallback exists for.
  Scene scene;
  for (int i = 0; i < 200; ++i) {
    const double s = std::pow(1.15, i);
    test::addBox(scene, {s, 0, 0}, {s * 1.01 + 0.01, 1, 1});
  }
  const TraceScene ts = TraceScene::build(scene, {.leafSize = 1});
  expectWellFormed(ts);
}

} // namespace
} // namespace bt
