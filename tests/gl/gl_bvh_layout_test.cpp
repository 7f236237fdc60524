// renderer/gl/gl_structs.h GlBvhNode, made from TraceScene's tree at upload: the same leaves and
// boxes, reached through the same parents. Needs no GL context.
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_scene.h"
#include "tests/gl/test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace bt::gl {
namespace {

bool sameBox(const float (&min)[3], const float (&max)[3], const GpuBvhNode& n) {
  return std::equal(min, min + 3, n.boundsMin) && std::equal(max, max + 3, n.boundsMax);
}

// Walks both trees together from the root: each TraceScene child appears in the GL node as
// its box and a reference of the right kind; every TraceScene node is reached exactly once.
void expectSameTree(const TraceScene& scene) {
  const std::span<const GpuBvhNode> nodes = scene.nodes();
  const std::vector<GlBvhNode> gl = bvhForGl(nodes);
  std::vector<int> reached(nodes.size(), 0);
  std::vector<int> glReached(gl.size(), 0);
  ++reached[0];
  struct Pair {
    uint32_t node, glNode;
  };
  std::vector<Pair> unvisited{{0, 0}};
  while (!unvisited.empty()) {
    const auto [n, g] = unvisited.back();
    unvisited.pop_back();
    ASSERT_LT(g, gl.size());
    ++glReached[g];
    const GlBvhNode& node = gl[g];
    for (int side = 0; side < 2; ++side) {
      const uint32_t child = nodes[n].leftFirst + side;
      ++reached[child];
      const uint32_t ref = side == 0 ? node.left : node.right;
      EXPECT_TRUE(side == 0 ? sameBox(node.leftMin, node.leftMax, nodes[child]) : sameBox(node.rightMin, node.rightMax, nodes[child]));
      if (nodes[child].count > 0) {
        EXPECT_EQ(ref, kGlLeafRef | nodes[child].count << 24 | nodes[child].leftFirst);
      } else {
        EXPECT_EQ(ref & kGlLeafRef, 0u);
        EXPECT_NE(ref, kGlNoChild);
        unvisited.push_back({child, ref});
      }
    }
  }
  for (size_t i = 0; i < reached.size(); ++i) EXPECT_EQ(reached[i], 1) << "TraceScene node " << i;
  for (size_t i = 0; i < glReached.size(); ++i) EXPECT_EQ(glReached[i], 1) << "GlBvhNode " << i;
}

TEST(GlBvhLayout, SameLeavesAndBoxesAsTraceScene) {
  Scene scene = test::makeTestRoom();
  for (int i = 0; i < 40; ++i) test::addBox(scene, {-250.0 + i * 12.0, 100, 0}, {-242.0 + i * 12.0, 108, 8.0 + i}, i % 3);
  for (const int leafSize : {1, 4, 8}) {
    const TraceScene traceScene = TraceScene::build(scene, {.leafSize = leafSize});
    ASSERT_GT(traceScene.nodes().size(), 1u);
    expectSameTree(traceScene);
  }
}

TEST(GlBvhLayout, LeafRootBecomesTheOnlyChild) {
  Scene scene;
  scene.materials = test::makeTestRoom().materials;
  test::addBox(scene, {0, 0, 0}, {8, 8, 8}, 0);
  const TraceScene traceScene = TraceScene::build(scene);
  ASSERT_EQ(traceScene.nodes().size(), 1u);
  const std::vector<GlBvhNode> gl = bvhForGl(traceScene.nodes());
  ASSERT_EQ(gl.size(), 1u);
  EXPECT_EQ(gl[0].left, kGlLeafRef | 1u << 24 | 0u);
  EXPECT_TRUE(sameBox(gl[0].leftMin, gl[0].leftMax, traceScene.nodes()[0]));
  EXPECT_EQ(gl[0].right, kGlNoChild);
}

TEST(GlBvhLayout, EmptyTreeIsARootWithoutChildren) {
  const std::vector<GlBvhNode> gl = bvhForGl({});
  ASSERT_EQ(gl.size(), 1u);
  EXPECT_EQ(gl[0].left, kGlNoChild);
  EXPECT_EQ(gl[0].right, kGlNoChild);
}

TEST(GlBvhLayout, LeafBeyondTheReferenceLimitsIsAnError) {
  const GpuBvhNode tooMany{{0, 0, 0}, 0, {1, 1, 1}, kGlLeafMaxCount + 1};
  EXPECT_THROW(bvhForGl(std::span<const GpuBvhNode>(&tooMany, 1)), GlError);
  const GpuBvhNode tooFar{{0, 0, 0}, kGlLeafMaxFirst + 1, {1, 1, 1}, 1};
  EXPECT_THROW(bvhForGl(std::span<const GpuBvhNode>(&tooFar, 1)), GlError);
  const GpuBvhNode atTheLimits{{0, 0, 0}, kGlLeafMaxFirst, {1, 1, 1}, kGlLeafMaxCount};
  EXPECT_NO_THROW(bvhForGl(std::span<const GpuBvhNode>(&atTheLimits, 1)));
}

} // namespace
} // namespace bt::gl
