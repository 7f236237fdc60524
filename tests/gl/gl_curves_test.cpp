// Quake 3 curves (mesh triangles) in the GL tracer against the CPU reference: maps/curves.map,
// a room with a patchDef2 arch and a round pillar: its AOVs pixel by pixel and faithful beauty,
// and physical beauty in the megakernel and wavefront forms.
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_lighting.h"
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

const Scene& curvesMap() {
  static const Scene scene = importScene((test::mapsDir() / "curves.map").string(), ImportOptions{});
  return scene;
}

using Renders = test::CpuAndGl;

Renders render(LightingMode mode) {
  return test::renderCpuAndGl(curvesMap(), mode, kWidth, kHeight);
}

bool onMesh(uint32_t pixelFace) {
  return pixelFace > 0 && curvesMap().faces[pixelFace - 1].brush == kNoBrush;
}

// The AOVs: the same face (a triangle's side) at all but a few pixels whose ray grazes an edge,
// and there the same albedo, normal and depth.
void expectAovsAgree(const Renders& r) {
  size_t sameFace = 0, curvePixels = 0, gpuCurvePixels = 0, close = 0;
  for (size_t i = 0; i < r.cpu.face.size(); ++i) {
    curvePixels += onMesh(r.cpu.face[i]);
    gpuCurvePixels += onMesh(r.gpu.face[i]);
    if (r.gpu.face[i] != r.cpu.face[i]) continue;
    ++sameFace;
    close += glm::length(r.gpu.albedo[i] - r.cpu.albedo[i]) < 2e-3f && glm::length(r.gpu.normal[i] - r.cpu.normal[i]) < 1e-4f &&
        std::abs(r.gpu.depth[i] - r.cpu.depth[i]) <= 1e-3f * r.cpu.depth[i];
  }
  EXPECT_GT(curvePixels, r.cpu.face.size() / 5) << "the camera should see the arch and the pillar";
  EXPECT_NEAR(double(gpuCurvePixels), double(curvePixels), curvePixels * 0.005 + 1);
  EXPECT_GE(sameFace, r.cpu.face.size() * 995 / 1000) << sameFace << " of " << r.cpu.face.size() << " pixels see the CPU's face";
  EXPECT_GE(close, sameFace * 995 / 1000) << close << " of " << sameFace << " pixels have the CPU's AOVs";
}

// Beauty as gl_engine_rules_test: means within `meanTolerance`, 97 % of pixels within 1 %.
void expectBeautyAgrees(const Renders& r, double meanTolerance) {
  size_t close = 0;
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  for (size_t i = 0; i < r.cpu.beauty.size(); ++i) {
    gpuSum += glm::dvec3(r.gpu.beauty[i]);
    cpuSum += glm::dvec3(r.cpu.beauty[i]);
    close += glm::length(r.gpu.beauty[i] - r.cpu.beauty[i]) <= 0.01f * glm::length(r.cpu.beauty[i]) + 1e-3f;
  }
  EXPECT_GE(close, r.cpu.beauty.size() * 97 / 100) << close << " of " << r.cpu.beauty.size() << " pixels agree";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], meanTolerance * cpuSum[c] + 1e-6) << "channel " << c;
  EXPECT_GT(cpuSum.x + cpuSum.y + cpuSum.z, 0.0) << "a black image proves nothing";
}

TEST(GlCurves, FaithfulMatchesTheCpu) {
  const Renders r = render(LightingMode::Faithful);
  expectAovsAgree(r);
  expectBeautyAgrees(r, 0.01);
}

// Physical mode: both forms of the path tracer trace the triangles alike (gl_wavefront_map_test's
// tolerance), and their mean is the CPU's (the samples differ: the means within 5 %).
TEST(GlCurves, PhysicalFormsMatchEachOtherAndTheCpu) {
  const Scene& scene = curvesMap();
  Diagnostics diagnostics;
  const RenderScene render = buildRenderScene(scene, {}, diagnostics);
  GlTracer tracer(test::sharedGlContext(), scene, render.tracer, test::textureModeUnderTest(), lightingFor(render));
  const CameraBasis camera = cameraFrom(defaultCameraPose(scene), kWidth, kHeight);
  BeautySettings settings{.width = kWidth, .height = kHeight, .spp = 2, .seed = 11, .physical = true, .bounces = 2};
  settings.form = PathTracerForm::Megakernel;
  const BeautyImage mega = tracer.renderBeauty(camera, settings);
  settings.form = PathTracerForm::Wavefront;
  const BeautyImage wave = tracer.renderBeauty(camera, settings);
  ASSERT_EQ(wave.wavefrontSamples, 2);
  size_t differing = 0;
  for (size_t i = 0; i < mega.beauty.size(); ++i) {
    const glm::vec3 a = mega.beauty[i], d = glm::abs(a - wave.beauty[i]);
    differing += std::max(d.x, std::max(d.y, d.z)) > 1e-4f * std::max(1.0f, std::max(a.x, std::max(a.y, a.z)));
  }
  EXPECT_LE(differing, mega.beauty.size() / 200);
  RenderSettings cpuSettings;
  cpuSettings.width = kWidth;
  cpuSettings.height = kHeight;
  cpuSettings.spp = 8;
  cpuSettings.integrator.mode = LightingMode::Physical;
  cpuSettings.integrator.bounces = 2;
  const RenderImage cpu = renderCpu(render, Camera(defaultCameraPose(scene), kWidth, kHeight), cpuSettings);
  glm::dvec3 gpuSum(0.0), cpuSum(0.0);
  for (size_t i = 0; i < cpu.beauty.size(); ++i) {
    gpuSum += glm::dvec3(mega.beauty[i]);
    cpuSum += glm::dvec3(cpu.beauty[i]);
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(gpuSum[c], cpuSum[c], 0.05 * cpuSum[c]) << "channel " << c;
  EXPECT_GT(cpuSum.x + cpuSum.y + cpuSum.z, 0.0) << "a black image proves nothing";
}

} // namespace
} // namespace bt::gl
