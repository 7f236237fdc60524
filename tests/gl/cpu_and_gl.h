// One level rendered by both tracers with the settings the map-based GL parity suites share, on
// one set of GL programs for the whole test program (on llvmpipe each build takes seconds).
#pragma once

#include "renderer/cpu/cpu_renderer.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <gtest/gtest.h>

#include <memory>

namespace bt::test {

struct CpuAndGl {
  RenderImage cpu, gpu;
};

// width x height, 4 spp (or `spp`), seed 7, 2 bounces, from the level's default camera; the GL
// render must report no GL error.
inline CpuAndGl renderCpuAndGl(const Scene& scene, LightingMode mode, int width, int height, int spp = 4) {
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  const CameraPose pose = defaultCameraPose(scene);
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.spp = spp;
  settings.seed = 7;
  settings.integrator.mode = mode;
  settings.integrator.bounces = 2;
  CpuAndGl r;
  r.cpu = renderCpu(rs, Camera(pose, width, height), settings);
  gl::GlContext& context = sharedGlContext();
  static const auto programs = std::make_shared<gl::TracerPrograms>(context, textureModeUnderTest());
  const int errorsBefore = context.debugErrorCount();
  r.gpu = gl::renderWithGl(context, rs, pose, settings, programs, {}).image;
  EXPECT_EQ(context.debugErrorCount(), errorsBefore);
  return r;
}

} // namespace bt::test
