// renderer/gl/gl_wide_bvh.h: TraceScene's binary tree collapsed into gl_structs.h GlWideNodes,
// the GPU walk's wide layout. Every brush reachable exactly once, every child box (as the shader
// computes it) holding its subtree's exact box, the depth within the walk's stack (no GL
// context); and the wide walk's hits on a shared level, the binary walk's bit for bit.
#include "importers/import.h"
#include "renderer/camera.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"
#include "renderer/gl/gl_wide_bvh.h"
#include "tests/gl/test_scenes.h"
#include "tests/bvh/generated_scenes.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <vector>

namespace bt::gl {
namespace {

struct Box {
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  float hi[3] = {std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest()};
  void grow(const Box& b) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], b.lo[a]), hi[a] = std::max(hi[a], b.hi[a]);
  }
  bool holds(const Box& b) const {
    for (int a = 0; a < 3; ++a)
      if (b.lo[a] < lo[a] || b.hi[a] > hi[a]) return false;
    return true;
  }
};

// Walks the wide tree from its root, counting what it reaches.
struct WideWalk {
  const WideBvh& wide;
  std::span<const GpuBrush> brushes; // by binary leaf index
  uint32_t firstRow;
  std::vector<int> nodeReached, primitiveReached;
  uint32_t depth = 0;
  int badBoxes = 0;

  // The exact box of everything under node `n`.
  Box node(uint32_t n, uint32_t level) {
    ++nodeReached.at(n);
    depth = std::max(depth, level);
    const GlWideNode& node = wide.nodes[n];
    Box all;
    uint32_t interior = 0;
    for (int slot = 0; slot < 8; ++slot) {
      const uint8_t meta = node.meta[slot];
      EXPECT_EQ((node.imask >> slot & 1) != 0, meta != 0 && wideMetaIsInner(meta)) << "node " << n << " slot " << slot;
      if (meta == 0) continue;
      Box exact;
      if (wideMetaIsInner(meta)) {
        EXPECT_EQ(meta, wideInnerMeta(slot));
        const uint32_t row = node.childBase + kGlWideNodeRows * interior++;
        EXPECT_EQ((row - firstRow) % kGlWideNodeRows, 0u);
        exact = this->node((row - firstRow) / kGlWideNodeRows, level + 1);
      } else {
        const uint32_t first = node.leafBase + wideLeafOffset(meta), count = wideLeafCount(meta);
        EXPECT_EQ(meta, wideLeafMeta(count, wideLeafOffset(meta))); // the count in unary
        EXPECT_LE(wideLeafOffset(meta) + count, kGlWideInnerBit);
        EXPECT_GE(count, 1u);
        for (uint32_t i = first; i < first + count; ++i) {
          ++primitiveReached.at(i);
          const GpuBrush& b = brushes[wide.order.at(i)];
          Box box;
          std::copy(b.boundsMin, b.boundsMin + 3, box.lo);
          std::copy(b.boundsMax, b.boundsMax + 3, box.hi);
          exact.grow(box);
        }
      }
      Box quantised;
      wideChildBox(node, slot, quantised.lo, quantised.hi);
      badBoxes += !quantised.holds(exact);
      all.grow(exact);
    }
    return all;
  }
};

void expectWideTree(std::span<const GpuBvhNode> nodes, std::span<const GpuBrush> brushes) {
  constexpr uint32_t kFirstRow = 1; // after the header, as wideSceneForGl places the brushes' tree
  const WideBvh wide = collapseBvh(nodes, kFirstRow);
  WideWalk walk{wide, brushes, kFirstRow, std::vector<int>(wide.nodes.size()), std::vector<int>(wide.order.size())};
  walk.node(0, 1);
  EXPECT_EQ(walk.badBoxes, 0) << "child boxes that do not hold their subtree";
  EXPECT_EQ(wide.order.size(), brushes.size());
  std::vector<int> brushReached(brushes.size());
  for (uint32_t b : wide.order) ++brushReached.at(b);
  EXPECT_EQ(std::count(brushReached.begin(), brushReached.end(), 1), std::ptrdiff_t(brushReached.size()))
      << "brushes not in the order once";
  EXPECT_EQ(std::count(walk.primitiveReached.begin(), walk.primitiveReached.end(), 1), std::ptrdiff_t(wide.order.size()))
      << "brushes not reached exactly once";
  EXPECT_EQ(std::count(walk.nodeReached.begin(), walk.nodeReached.end(), 1), std::ptrdiff_t(wide.nodes.size()))
      << "nodes not reached exactly once";
  EXPECT_EQ(walk.depth, wide.depth);
  EXPECT_LE(wide.depth, kGlWideMaxDepth);
}
void expectWideTree(const TraceScene& scene) {
  expectWideTree(scene.nodes(), scene.brushes());
}

TEST(GlWideBvh, GeneratedLevelCollapsesWithEveryBrushOnceInsideItsBoxes) {
  const test::GeneratedLevel level = test::generateLevel(20000, 7);
  const TraceScene scene = TraceScene::build(level.scene);
  ASSERT_GT(scene.brushes().size(), 10000u);
  expectWideTree(scene);
}

// Leaves too large for a leaf child (more than kGlWideLeafMaxCount brushes, or more than 24 under
// one node) become nodes of their own: larger leaf sizes, and one leaf of 100 brushes.
TEST(GlWideBvh, LargeLeavesCollapseWithEveryBrushOnceInsideItsBoxes) {
  const test::GeneratedLevel level = test::generateLevel(3000, 3);
  for (const int leafSize : {8, 16}) {
    SCOPED_TRACE(leafSize);
    expectWideTree(TraceScene::build(level.scene, {.leafSize = leafSize}));
  }
  std::vector<GpuBrush> brushes(100);
  for (size_t i = 0; i < brushes.size(); ++i)
    for (int a = 0; a < 3; ++a) brushes[i].boundsMin[a] = float(i), brushes[i].boundsMax[a] = float(i) + 1.0f;
  const GpuBvhNode leaf{{0, 0, 0}, 0, {100, 100, 100}, 100};
  expectWideTree(std::span<const GpuBvhNode>(&leaf, 1), brushes);
}

// Also the build times, the fastest of 5 (printed: the collapse must stay a small part of the
// binary build).
TEST(GlWideBvh, SharedLevelCollapsesWithEveryBrushOnceInsideItsBoxes) {
  BT_REQUIRE_SHARED(shared);
  const Scene level = importScene((shared / "maps/librequake/lq1/maps/src/e4/lq_e4m3.map").string(), ImportOptions{});
  using Clock = std::chrono::steady_clock;
  using Ms = std::chrono::duration<double, std::milli>;
  double build = 1e9, collapse = 1e9;
  for (int i = 0; i < 5; ++i) {
    const auto start = Clock::now();
    const TraceScene scene = TraceScene::build(level);
    const auto built = Clock::now();
    const WideBvh wide = collapseBvh(scene.nodes(), 1);
    build = std::min(build, Ms(built - start).count());
    collapse = std::min(collapse, Ms(Clock::now() - built).count());
  }
  const TraceScene scene = TraceScene::build(level);
  const WideBvh wide = collapseBvh(scene.nodes(), 1);
  std::printf("lq_e4m3: %zu brushes, binary build %.2f ms, collapse %.2f ms, %zu wide nodes (%zu binary), depth %u\n",
              scene.brushes().size(), build, collapse, wide.nodes.size(), scene.nodes().size(), wide.depth);
  expectWideTree(scene);
}

// lq_e4m3 from its camera, both GPU trees on one device (the hardware layout, forced on
// llvmpipe): every pixel's face and depth the same, slanted brushes and ties included.
TEST(GlWideBvh, WideWalkHitsWhatTheBinaryWalkHitsOnASharedLevel) {
  BT_REQUIRE_SHARED(shared);
  const Scene level = importScene((shared / "maps/librequake/lq1/maps/src/e4/lq_e4m3.map").string(), ImportOptions{});
  const TraceScene traceScene = TraceScene::build(level);
  constexpr int kWidth = 160, kHeight = 90;
  const CameraBasis camera = cameraFrom(defaultCameraPose(level), kWidth, kHeight);
  GlContext& context = test::sharedGlContext();
  const auto render = [&](TraceLayout layout) {
    GlTracer tracer(context, level, traceScene, std::make_shared<TracerPrograms>(context, TextureMode::Arrays, layout));
    return tracer.renderAovs(camera, kWidth, kHeight);
  };
  const AovImages binary = render(TraceLayout::Hardware), wide = render(TraceLayout::Wide);
  size_t differ = 0, hits = 0;
  for (size_t i = 0; i < binary.face.size(); ++i) {
    differ += binary.face[i] != wide.face[i] || binary.depth[i] != wide.depth[i];
    hits += binary.face[i] != AovImages::kNothingHit;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(hits, binary.face.size() / 2);
}

// The benchmark's rays on lq_e4m3 (gl_bench ... rays), both GPU trees on one device: every
// primary ray's face, every bounce ray's t (cosine-distributed from the primary hits: all
// octants, slanted brushes met at every angle), every shadow ray's verdict (any hit within the
// bounce rays' median length, leaves met in another order by each walk) the same.
TEST(GlWideBvh, WideWalkTracesTheBenchmarkRaysAsTheBinaryWalkOnASharedLevel) {
  BT_REQUIRE_SHARED(shared);
  const Scene level = importScene((shared / "maps/librequake/lq1/maps/src/e4/lq_e4m3.map").string(), ImportOptions{});
  const TraceScene traceScene = TraceScene::build(level);
  constexpr int kWidth = 320, kHeight = 180;
  const CameraBasis camera = cameraFrom(defaultCameraPose(level), kWidth, kHeight);
  GlContext& context = test::sharedGlContext();
  const auto trace = [&](TraceLayout layout) {
    GlTracer tracer(context, level, traceScene, std::make_shared<TracerPrograms>(context, TextureMode::Arrays, layout));
    return tracer.benchmarkRays(camera, kWidth, kHeight, 1);
  };
  const RayBenchmark binary = trace(TraceLayout::Hardware), wide = trace(TraceLayout::Wide);
  ASSERT_EQ(binary.primaryFace.size(), size_t(kWidth * kHeight));
  ASSERT_EQ(wide.primaryFace.size(), binary.primaryFace.size());
  EXPECT_EQ(wide.shadowLength, binary.shadowLength);
  size_t primaryDiffer = 0, bounceDiffer = 0, shadowDiffer = 0, bounces = 0, blocked = 0;
  for (size_t i = 0; i < binary.primaryFace.size(); ++i) {
    primaryDiffer += binary.primaryFace[i] != wide.primaryFace[i];
    if (binary.primaryFace[i] == 0) continue; // no bounce ray
    ++bounces;
    bounceDiffer += binary.bounceT[i] != wide.bounceT[i];
    shadowDiffer += binary.shadowBlocked[i] != wide.shadowBlocked[i];
    blocked += binary.shadowBlocked[i];
  }
  EXPECT_EQ(primaryDiffer, 0u);
  EXPECT_EQ(bounceDiffer, 0u);
  EXPECT_EQ(shadowDiffer, 0u);
  EXPECT_GT(bounces, binary.primaryFace.size() / 2);
  EXPECT_GT(blocked, bounces / 4); // about half, the median length
  EXPECT_LT(blocked, bounces * 3 / 4);
}

// A one-leaf tree and an empty one: a root holding the leaf, a root holding nothing.
TEST(GlWideBvh, SmallTrees) {
  const WideBvh empty = collapseBvh({}, 1);
  ASSERT_EQ(empty.nodes.size(), 1u);
  EXPECT_EQ(std::count(std::begin(empty.nodes[0].meta), std::end(empty.nodes[0].meta), 0), 8);
  const GpuBvhNode leaf{{0, 0, 0}, 0, {1, 2, 3}, 3};
  const WideBvh one = collapseBvh(std::span<const GpuBvhNode>(&leaf, 1), 1);
  ASSERT_EQ(one.nodes.size(), 1u);
  EXPECT_EQ(one.order, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(std::count(std::begin(one.nodes[0].meta), std::end(one.nodes[0].meta), wideLeafMeta(3, 0)), 1);
}

} // namespace
} // namespace bt::gl
