// The BVH builder: structure (every brush once, bounds nest, depth), SAH quality against the
// full-sweep reference, determinism across thread counts, and brush exclusion.
#include "bvh/trace_scene.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/bvh/full_sweep_sah.h"
#include "tests/bvh/generated_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

using bt::test::expectAllBrushesPresent;
using bt::test::expectSahNearFullSweep;
using bt::test::expectWellFormed;

namespace bt {
namespace {

// Boxes of many sizes scattered over a cube, for the tests that call the builder directly.
std::vector<Aabb> scatteredBoxes(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> position(0.0f, 4096.0f), size(1.0f, 96.0f);
  std::vector<Aabb> boxes;
  for (int i = 0; i < count; ++i) {
    const glm::vec3 min(position(rng), position(rng), position(rng));
    boxes.push_back({min, min + glm::vec3(size(rng), size(rng), size(rng))});
  }
  return boxes;
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
  EXPECT_EQ(ts.sahCost(), 1.0);             // one leaf with one brush, area ratio 1
  EXPECT_EQ(ts.brushes()[0].sideCount, 0u); // a box is all axial
}

TEST(BvhBuild, SahCostFollowsTheCostModel) {
  // Root [0,2]^3 (half-area 12) over two leaves [0,1]^3 (3) with 1 box and [1,2]^3 with 2:
  // 1 * 12/12 + 1 * 3/12 + 2 * 3/12 = 1.75.
  const GpuBvhNode nodes[] = {{{0, 0, 0}, 1, {2, 2, 2}, 0}, {{0, 0, 0}, 0, {1, 1, 1}, 1}, {{1, 1, 1}, 1, {2, 2, 2}, 2}};
  EXPECT_DOUBLE_EQ(sahCost(nodes), 1.75);
}

TEST(BvhBuild, EveryBrushReachableExactlyOnce) {
  for (const auto& [name, scene] :
       {std::pair{"level", test::generateLevel(3000, 1).scene}, std::pair{"random", test::generateRandomBrushes(3000, 2)}}) {
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
  // The root is split by all threads together, each binning and partitioning one chunk of the
  // boxes: 3 threads give chunks of unequal sizes.
  const TraceScene one = TraceScene::build(scene, {.threads = 1});
  for (int threads : {2, 3, 4}) {
    SCOPED_TRACE(threads);
    const TraceScene many = TraceScene::build(scene, {.threads = threads});
    ASSERT_EQ(one.nodes().size(), many.nodes().size());
    ASSERT_EQ(one.brushes().size(), many.brushes().size());
    EXPECT_EQ(std::memcmp(one.nodes().data(), many.nodes().data(), one.nodes().size_bytes()), 0);
    EXPECT_EQ(std::memcmp(one.brushes().data(), many.brushes().data(), one.brushes().size_bytes()), 0);
    EXPECT_EQ(one.sahCost(), many.sahCost());
    expectWellFormed(many);
  }
}

TEST(BvhBuild, BaselineAndAvx2BuildsAreTheSame) {
  // buildBinnedSah() runs an AVX2 compilation of the builder where the library has one and the
  // CPU runs it; elsewhere it is the baseline, and there is nothing to compare. Same roundings,
  // same tree: generated levels, scattered boxes, sampled binning (nodes of 2048 boxes or more),
  // threads.
  if (!binnedSahAvx2Usable())
    GTEST_SKIP() << "no AVX2 build of the SAH builder to compare with the baseline: "
                    "the library has none (a compiler other than GCC or Clang, or not x86-64) or this CPU lacks AVX2";
  const std::vector<Aabb> scattered = scatteredBoxes(20000, 8);
  const TraceScene level = TraceScene::build(test::generateLevel(12000, 9).scene, {.threads = 1});
  const std::vector<Aabb> levelBoxes = [&] {
    std::vector<Aabb> boxes;
    for (const GpuBrush& g : level.brushes())
      boxes.push_back({{g.boundsMin[0], g.boundsMin[1], g.boundsMin[2]}, {g.boundsMax[0], g.boundsMax[1], g.boundsMax[2]}});
    return boxes;
  }();
  for (const std::vector<Aabb>* boxes : {&scattered, &levelBoxes}) {
    for (int threads : {1, 2}) {
      SCOPED_TRACE(threads);
      const FlatBvh fast = buildBinnedSah(*boxes, {.threads = threads});
      const FlatBvh baseline = buildBinnedSahBaseline(*boxes, {.threads = threads});
      ASSERT_EQ(fast.nodes.size(), baseline.nodes.size());
      EXPECT_EQ(std::memcmp(fast.nodes.data(), baseline.nodes.data(), fast.nodes.size() * sizeof(GpuBvhNode)), 0);
      EXPECT_EQ(fast.order, baseline.order);
    }
  }
}

TEST(BvhBuild, BuilderLaysTheTreeOutDepthFirst) {
  // With threads, the builder squeezes the holes that tasks leave out of its slots (several
  // threads at once, child indices shifted by the holes before them); compactDepthFirst() lays
  // a tree out with one stack. A tree already in depth-first order is its own compaction.
  const std::vector<Aabb> boxes = scatteredBoxes(8000, 6); // threads from 4096 boxes
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    const FlatBvh bvh = buildBinnedSah(boxes, {.threads = threads});
    const std::vector<GpuBvhNode> compacted = compactDepthFirst(bvh.nodes);
    ASSERT_EQ(compacted.size(), bvh.nodes.size());
    EXPECT_EQ(std::memcmp(compacted.data(), bvh.nodes.data(), compacted.size() * sizeof(GpuBvhNode)), 0);
  }
}

TEST(BvhBuild, CoincidentCentroidsWithThreads) {
  // No SAH split exists at the root, so the threads that would split it together hand it to
  // the median fallback instead.
  Scene scene;
  for (int i = 0; i < 5000; ++i) test::addBox(scene, {0, 0, 0}, {16, 16, 16});
  const TraceScene one = TraceScene::build(scene, {.threads = 1});
  const TraceScene two = TraceScene::build(scene, {.threads = 2});
  ASSERT_EQ(one.nodes().size(), two.nodes().size());
  EXPECT_EQ(std::memcmp(one.nodes().data(), two.nodes().data(), one.nodes().size_bytes()), 0);
  expectWellFormed(two);
  expectAllBrushesPresent(scene, two);
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

// Found by tests/fuzz/fuzz_bsp: a corrupt level's brush whose +X face lay below its -X face
// (a sliver of no thickness) made an empty box, and the builder threw std::invalid_argument.
TEST(BvhBuild, BrushWhoseAxialFacesCrossIsSkipped) {
  Scene scene;
  test::addBox(scene, {0, 0, 0}, {16, 16, 16});
  test::addBox(scene, {32, 0, 0}, {48, 16, 16});
  for (uint32_t f = scene.brushes[1].firstFace; f < scene.brushes[1].firstFace + scene.brushes[1].faceCount; ++f) {
    Plane& plane = scene.faces[f].plane;
    if (plane.normal.x == 1.0) plane.dist = 31.0; // +X now below -X (32)
  }
  const TraceScene ts = TraceScene::build(scene);
  ASSERT_EQ(ts.brushes().size(), 1u);
  EXPECT_EQ(ts.brushes()[0].sceneBrush, 0u);
}

TEST(BvhBuild, InconsistentSceneIsRejected) {
  Scene scene;
  test::addBox(scene, {0, 0, 0}, {16, 16, 16});
  scene.brushes[0].faceCount = 7; // one more face than the scene has
  EXPECT_THROW(TraceScene::build(scene), std::invalid_argument);
}

TEST(BvhBuild, NonFiniteBoxIsRejected) {
  // A NaN or infinite bound would give unordered centroids, which no split can place.
  const float inf = std::numeric_limits<float>::infinity();
  for (const Aabb& bad : {Aabb{{-inf, 0, 0}, {inf, 1, 1}}, Aabb{{0, 0, 0}, {1, std::nanf(""), 1}}}) {
    const std::vector<Aabb> boxes = {{{0, 0, 0}, {1, 1, 1}}, bad, {{2, 0, 0}, {3, 1, 1}}};
    EXPECT_THROW(buildBinnedSah(boxes, {}), std::invalid_argument);
  }
}

TEST(BvhBuild, FirstInvalidBoxIsReportedWhicheverThreadReadsIt) {
  // With threads, each reads and checks one chunk of the boxes; the error is about the first
  // invalid box of all, as with one thread.
  std::vector<Aabb> boxes = scatteredBoxes(20000, 7);
  boxes[15000] = {{1, 1, 1}, {0, 0, 0}}; // empty, in the last chunk for 2 and 3 threads
  boxes[5000].max.y = std::nanf("");     // in the first chunk
  const auto errorOf = [&](int threads) -> std::string {
    try {
      buildBinnedSah(boxes, {.threads = threads});
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    EXPECT_EQ(errorOf(threads), "buildBinnedSah: box with an infinite or NaN bound");
  }
  boxes[5000] = boxes[0];
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    EXPECT_EQ(errorOf(threads), "buildBinnedSah: empty box");
  }
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

TEST(BvhBuild, CoincidentAndDenormalCentroidsBuildValidTrees) {
  // All centroids in one point (no SAH split exists: median fallback), and centroids spread
  // over denormal distances along X, where the bin scale binCount / extent overflows to inf.
  Scene same, tiny;
  for (int i = 0; i < 40; ++i) test::addBox(same, {0, 0, 0}, {16, 16, 16});
  for (int i = 1; i <= 40; ++i) test::addBox(tiny, {0, i * 16.0, 0}, {i * 1e-40, i * 16.0 + 8.0, 8});
  for (int i = 1; i <= 40; ++i) test::addBox(tiny, {0, 0, 0}, {i * 1e-40, 8, 8});
  for (const auto& [name, scene] : {std::pair{"coincident", &same}, std::pair{"denormal", &tiny}}) {
    SCOPED_TRACE(name);
    for (int leafSize : {1, 4}) {
      const TraceScene ts = TraceScene::build(*scene, {.leafSize = leafSize});
      EXPECT_EQ(ts.brushes().size(), scene->brushes.size()); // none lost its windings
      expectWellFormed(ts);
      expectAllBrushesPresent(*scene, ts);
    }
  }
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

TEST(BvhBuild, ChainOfTasksWithThreads) {
  // Boxes growing geometrically to one side of a cluster of small ones: the SAH peels big
  // boxes off level by level, and the rest, the left child, goes to the task queue each time:
  // a chain of tasks nested in each other's slots, each leaving a hole at its end, that the
  // layout squeezes out. The threads still build the one-thread tree, depth first.
  std::vector<Aabb> boxes = scatteredBoxes(5800, 12);
  for (int i = 0; i < 200; ++i) {
    const float s = 4096.0f * std::pow(1.15f, static_cast<float>(i));
    boxes.push_back({{s, 0, 0}, {s * 1.01f + 1.0f, 1, 1}});
  }
  const FlatBvh one = buildBinnedSah(boxes, {.threads = 1});
  for (int threads : {2, 3}) {
    SCOPED_TRACE(threads);
    const FlatBvh many = buildBinnedSah(boxes, {.threads = threads});
    ASSERT_EQ(one.nodes.size(), many.nodes.size());
    EXPECT_EQ(std::memcmp(one.nodes.data(), many.nodes.data(), one.nodes.size() * sizeof(GpuBvhNode)), 0);
    EXPECT_EQ(one.order, many.order);
  }
  const std::vector<GpuBvhNode> compacted = compactDepthFirst(one.nodes);
  ASSERT_EQ(compacted.size(), one.nodes.size());
  EXPECT_EQ(std::memcmp(compacted.data(), one.nodes.data(), compacted.size() * sizeof(GpuBvhNode)), 0);
}

} // namespace
} // namespace bt
