#include "renderer/gl/gl_bench.h"

#include "renderer/cpu/camera.h"
#include "renderer/cpu/render_scene.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_lighting.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

namespace bt::gl {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }
} // namespace

int runGlBench(const Scene& scene, const GlBenchSettings& s) {
  Diagnostics diagnostics;
  const RenderScene renderScene = buildRenderScene(scene, {}, diagnostics);
  // The render command's default view (info_intermission, info_player_start, else the whole
  // level), so the rays see what a user first sees.
  const CameraPose pose = defaultCameraPose(scene);
  fmt::print("camera: {} ({}), {} lights, {} emitter triangles\n", formatCameraPose(pose), pose.source,
             renderScene.lights.size(), renderScene.emitters.size());

  auto start = Clock::now();
  auto context = gl::GlContext::createHeadless();
  gl::GlTracer tracer(*context, scene, renderScene.tracer, s.textures, gl::lightingFor(renderScene));
  const gl::CameraBasis camera = gl::cameraFrom(pose, s.width, s.height);
  const gl::BeautySettings oneSample{
      .width = s.width, .height = s.height, .spp = 1, .physical = s.physical, .bounces = s.bounces};
  tracer.renderBeauty(camera, oneSample);
  const double firstImage = secondsSince(start);
  const auto& info = context->info();
  fmt::print("device: {} ({}, {}), textures: {}\n", info.renderer, info.platform, info.version,
             gl::toString(tracer.textureMode()));
  fmt::print("time to first image: {:.3f} s (context, upload, shader build, 1 spp at {}x{})\n", firstImage, s.width, s.height);

  // Ray rates: enough passes to fill about a third of the time budget each. The first probe
  // also builds the program, so the second one sizes the run.
  tracer.benchmarkRays(camera, s.width, s.height, 1);
  gl::RayBenchmark probe = tracer.benchmarkRays(camera, s.width, s.height, 1);
  const double perPass = std::max(probe.primarySeconds + probe.bounceSeconds, 1e-4);
  const int passes = std::max(1, static_cast<int>(s.seconds / 3.0 / perPass));
  const gl::RayBenchmark rays = tracer.benchmarkRays(camera, s.width, s.height, passes);
  fmt::print("primary rays: {:.1f} Mrays/s ({} passes of {})\n",
             rays.primaryRays * double(rays.passes) / rays.primarySeconds * 1e-6, rays.passes, rays.primaryRays);
  fmt::print("bounce rays:  {:.1f} Mrays/s ({} passes of {})\n",
             rays.bounceRays * double(rays.passes) / rays.bounceSeconds * 1e-6, rays.passes, rays.bounceRays);

  // Full samples: physical mode, `bounces` bounces. One timed sample sizes a batch that fills
  // the remaining third; the batch runs without a sync per sample (as the viewer would).
  start = Clock::now();
  tracer.renderBeauty(camera, oneSample);
  const double perSample = std::max(secondsSince(start), 1e-4);
  gl::BeautySettings settings = oneSample;
  settings.spp = std::max(1, static_cast<int>(s.seconds / 3.0 / perSample));
  start = Clock::now();
  const gl::BeautyImage image = tracer.renderBeauty(camera, settings);
  const double seconds = secondsSince(start);
  fmt::print("samples: {:.2f} full samples/s at {}x{}, {} bounces, {} ({} spp in {:.2f} s, {:.1f} Msamples/s)\n",
             image.samples / seconds, s.width, s.height, s.bounces, (s.physical ? "physical" : "faithful"), image.samples, seconds,
             image.samples * double(s.width) * s.height / seconds * 1e-6);
  return context->debugErrorCount() == 0 ? 0 : 1;
}

} // namespace bt::gl
