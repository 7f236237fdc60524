// gl_bench's ray benchmark variants (GlTracer::benchmarkRays with RayBenchVariant): what a
// variant measures must not change what the benchmark prints as the walk's results, and the
// counts it prints must be the walk's.
#include "bvh/trace_scene.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <gtest/gtest.h>

#include <memory>

namespace bt::gl {
namespace {

constexpr int kWidth = 64;
constexpr int kHeight = 48;

// The test room with a row of boxes: a tree of several levels, rays that hit and rays that pass.
Scene roomWithBoxes() {
  Scene scene = test::makeTestRoom();
  for (int i = 0; i < 40; ++i) test::addBox(scene, {-250.0 + i * 12.0, 100, 0}, {-242.0 + i * 12.0, 108, 8.0 + i}, i % 3);
  return scene;
}

// The benchmark on that scene in each trace layout (llvmpipe's and the GPUs'), whatever runs it.
template <typename Check> void inEachLayout(const Check& check) {
  GlContext& context = test::sharedGlContext();
  const Scene scene = roomWithBoxes();
  const TraceScene traceScene = TraceScene::build(scene);
  for (const TraceLayout layout : {TraceLayout::Software, TraceLayout::Hardware}) {
    SCOPED_TRACE(layout == TraceLayout::Software ? "software trace layout" : "hardware trace layout");
    GlTracer tracer(context, scene, traceScene, std::make_shared<TracerPrograms>(context, TextureMode::Arrays, layout));
    check(tracer, test::testCamera(kWidth, kHeight));
  }
}

TEST(GlRayBench, VariantsKeepThePlainResultsAndTheirOwnWhereTheWalkIsWhole) {
  inEachLayout([](GlTracer& tracer, const CameraBasis& camera) {
    const RayBenchmark plain = tracer.benchmarkRays(camera, kWidth, kHeight, 1);
    ASSERT_GT(plain.bounceRays, 0u);
    const RayBenchmark counted = tracer.benchmarkRays(camera, kWidth, kHeight, 1, {.defines = {"BT_RB_COUNT"}});
    const RayBenchmark stack = tracer.benchmarkRays(camera, kWidth, kHeight, 1, {.defines = {"BT_RB_STACK_DEPTH 32"}});
    const RayBenchmark nodesOnly = tracer.benchmarkRays(camera, kWidth, kHeight, 1, {.defines = {"BT_RB_NODES_ONLY"}});
    for (const RayBenchmark* variant : {&counted, &stack, &nodesOnly}) {
      EXPECT_EQ(variant->primaryHash, plain.primaryHash);
      EXPECT_EQ(variant->bounceHash, plain.bounceHash);
      EXPECT_EQ(variant->shadowHash, plain.shadowHash);
      EXPECT_EQ(variant->bounceRays, plain.bounceRays);
    }
    // Two whole walks give the same results of their own; leaves that answer "no hit" do not.
    EXPECT_EQ(counted.variantHashes, stack.variantHashes);
    EXPECT_NE(nodesOnly.variantHashes[0], counted.variantHashes[0]);
    EXPECT_FALSE(plain.counted);
    EXPECT_FALSE(stack.counted);
  });
}

// Every ray visits the root node; a primary ray that hits has read a brush past its box; no sum
// is above the rays' count times the largest.
TEST(GlRayBench, CountsAreTheWalksPerRay) {
  inEachLayout([](GlTracer& tracer, const CameraBasis& camera) {
    const RayBenchmark counted = tracer.benchmarkRays(camera, kWidth, kHeight, 1, {.defines = {"BT_RB_COUNT"}});
    ASSERT_TRUE(counted.counted);
    for (int mode = 0; mode < 3; ++mode) {
      SCOPED_TRACE(mode == 0 ? "primary" : mode == 1 ? "bounce" : "shadow");
      const size_t rays = mode == 0 ? counted.primaryRays : counted.bounceRays;
      const auto sum = [&](int i) { return size_t(counted.walkCounts[16 * mode + 2 * i]); };
      const auto max = [&](int i) { return size_t(counted.walkCounts[16 * mode + 2 * i + 1]); };
      EXPECT_GE(sum(0), rays);   // interior nodes: the root at least
      EXPECT_GT(sum(1), 0u);     // brush boxes tested
      EXPECT_LE(sum(2), sum(1)); // past their box: some of those
      EXPECT_GT(max(4), 0u);     // the deepest stack
      for (int i = 0; i < 5; ++i) EXPECT_LE(sum(i), max(i) * rays) << "count " << i;
    }
    EXPECT_GE(counted.walkCounts[4], counted.bounceRays); // primary rays past a brush box >= those that hit
  });
}

} // namespace
} // namespace bt::gl
