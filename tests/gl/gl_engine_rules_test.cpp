// The GL tracer on the engine-rule maps (maps/engine_rules/, tests/render/engine_rules_test.cpp
// holds the CPU tracer to the rules): hidden brushes, a PNG fence's holes for camera rays and
// for shadow rays, in both lighting modes, against the CPU reference.
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/cpu_and_gl.h"
#include "tests/gl/test_scenes.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace bt::gl {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 64;

using Renders = test::CpuAndGl;

Renders renderMap(const std::string& name, LightingMode mode) {
  const Scene scene = importScene((test::mapsDir() / "engine_rules" / name).string(), ImportOptions{});
  return test::renderCpuAndGl(scene, mode, kWidth, kHeight);
}

// Faces equal but for a few pixels whose ray grazes an edge; beauty as gl_cpu_parity_test's
// stated tolerance: means within `meanTolerance`, 97 % of pixels within 1 % (+ 1e-3).
void expectAgree(const Renders& r, double meanTolerance) {
  ASSERT_EQ(r.gpu.face.size(), r.cpu.face.size());
  ASSERT_EQ(r.gpu.beauty.size(), r.cpu.beauty.size());
  size_t faces = 0, close = 0;
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  for (size_t i = 0; i < r.cpu.face.size(); ++i) {
    faces += r.gpu.face[i] == r.cpu.face[i];
    gpuSum += glm::dvec3(r.gpu.beauty[i]);
    cpuSum += glm::dvec3(r.cpu.beauty[i]);
    close += glm::length(r.gpu.beauty[i] - r.cpu.beauty[i]) <= 0.01f * glm::length(r.cpu.beauty[i]) + 1e-3f;
  }
  EXPECT_GE(faces, r.cpu.face.size() * 995 / 1000) << faces << " of " << r.cpu.face.size() << " pixels see the CPU's face";
  EXPECT_GE(close, r.cpu.beauty.size() * 97 / 100) << close << " of " << r.cpu.beauty.size() << " pixels agree";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], meanTolerance * cpuSum[c] + 1e-6) << "channel " << c;
  EXPECT_GT(cpuSum.x + cpuSum.y + cpuSum.z, 0.0) << "a black image proves nothing";
}

TEST(GlEngineRules, HiddenBrushesAreNeitherSeenNorCastShadows) {
  const Renders hidden = renderMap("hidden.map", LightingMode::Faithful);
  const Renders reference = renderMap("hidden_reference.map", LightingMode::Faithful);
  expectAgree(hidden, 0.01);
  size_t same = 0;
  for (size_t i = 0; i < hidden.gpu.face.size(); ++i) same += hidden.gpu.face[i] == reference.gpu.face[i];
  EXPECT_GE(same, hidden.gpu.face.size() * 995 / 1000) << "the GL image sees a hidden brush";
}

TEST(GlEngineRules, PngFenceCutsCameraAndShadowRaysInFaithfulMode) {
  const Renders fence = renderMap("fence.map", LightingMode::Faithful);
  expectAgree(fence, 0.01);
  // The fence is neither gone nor solid: its face and the wall behind it both show.
  const Renders open = renderMap("fence_open.map", LightingMode::Faithful);
  size_t behind = 0, fenceFace = 0;
  for (size_t i = 0; i < fence.gpu.face.size(); ++i) {
    behind += fence.gpu.face[i] == open.gpu.face[i];
    fenceFace += fence.gpu.face[i] != open.gpu.face[i];
  }
  EXPECT_GT(behind, fence.gpu.face.size() / 4);
  EXPECT_GT(fenceFace, fence.gpu.face.size() / 10);
}

TEST(GlEngineRules, PngFenceCutsCameraAndShadowRaysInPhysicalMode) {
  expectAgree(renderMap("fence.map", LightingMode::Physical), 0.03);
}

} // namespace
} // namespace bt::gl
