// brushtrace bench [MAP]: GL tracer throughput on one level. A benchmark, never a test: the
// numbers depend on the machine. Reports primary and bounce ray rates (closest hits alone),
// full path-traced samples per second at the chosen size and bounce count, and the time from
// a loaded scene to the first image on screen-equivalent (context, upload, shader build, 1 spp).
#include "app/commands.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_tracer.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace bt::app {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

struct BenchOptions {
  std::string map;
  ImportOptions import;
  std::string size = "1280x720";
  int bounces = 4;
  double seconds = 5.0;
  std::string textures = "auto";
};

// A view of the whole level from above one corner, looking at its centre: every benchmark
// run sees the same thing without relying on the map's entities.
gl::CameraBasis overviewCamera(const Scene& scene, int width, int height) {
  const glm::vec3 center(scene.bounds.center());
  const float radius = 0.5f * glm::length(glm::vec3(scene.bounds.extent()));
  const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 1.0f, -0.8f));
  const float yaw = glm::degrees(std::atan2(dir.y, dir.x));
  const float pitch = glm::degrees(std::asin(-dir.z));
  return gl::CameraBasis::fromQuakeAngles(center - dir * radius * 1.6f, pitch, yaw, 0.0f, width, height);
}

int runBench(const BenchOptions& options) {
  int width = 0, height = 0;
  if (std::sscanf(options.size.c_str(), "%dx%d", &width, &height) != 2 || width <= 0 || height <= 0) {
    fmt::print(stderr, "brushtrace: --size '{}' is not WIDTHxHEIGHT\n", options.size);
    return 1;
  }
  const auto textureMode = gl::parseTextureMode(options.textures);
  if (!textureMode) {
    fmt::print(stderr, "brushtrace: --gl-textures '{}' is not bindless, arrays or auto\n", options.textures);
    return 1;
  }

  auto start = Clock::now();
  const Scene scene = importScene(options.map, options.import);
  fmt::print("map: {} ({} brushes, {} faces, {} materials), imported in {:.2f} s\n", options.map, scene.brushes.size(),
             scene.faces.size(), scene.materials.size(), secondsSince(start));

  start = Clock::now();
  auto context = gl::GlContext::createHeadless();
  gl::GlTracer tracer(*context, scene, *textureMode);
  const gl::CameraBasis camera = overviewCamera(scene, width, height);
  const gl::BeautySettings oneSample{.width = width, .height = height, .spp = 1, .physical = true, .bounces = options.bounces};
  tracer.renderBeauty(camera, oneSample);
  const double firstImage = secondsSince(start);
  const auto& info = context->info();
  fmt::print("device: {} ({}, {}), textures: {}\n", info.renderer, info.platform, info.version,
             gl::toString(tracer.textureMode()));
  fmt::print("time to first image: {:.3f} s (context, upload, shader build, 1 spp at {}x{})\n", firstImage, width, height);

  // Ray rates: enough passes to fill about a third of the time budget each.
  gl::RayBenchmark probe = tracer.benchmarkRays(camera, width, height, 1);
  const double perPass = std::max(probe.primarySeconds + probe.bounceSeconds, 1e-4);
  const int passes = std::max(1, static_cast<int>(options.seconds / 3.0 / perPass));
  const gl::RayBenchmark rays = tracer.benchmarkRays(camera, width, height, passes);
  fmt::print("primary rays: {:.1f} Mrays/s ({} passes of {})\n",
             rays.primaryRays * double(rays.passes) / rays.primarySeconds * 1e-6, rays.passes, rays.primaryRays);
  fmt::print("bounce rays:  {:.1f} Mrays/s ({} passes of {})\n",
             rays.bounceRays * double(rays.passes) / rays.bounceSeconds * 1e-6, rays.passes, rays.bounceRays);

  // Full samples: physical mode, `bounces` bounces, as many samples as fit the remaining third.
  start = Clock::now();
  gl::BeautySettings settings = oneSample;
  settings.spp = 1 << 20;
  const double budget = options.seconds / 3.0;
  const gl::BeautyImage image = tracer.renderBeauty(camera, settings, [&](int) { return secondsSince(start) < budget; });
  const double seconds = secondsSince(start);
  fmt::print("samples: {:.2f} full samples/s at {}x{}, {} bounces, physical ({} spp in {:.2f} s, {:.1f} Msamples/s)\n",
             image.samples / seconds, width, height, options.bounces, image.samples, seconds,
             image.samples * double(width) * height / seconds * 1e-6);
  return context->debugErrorCount() == 0 ? 0 : 1;
}

} // namespace

void addBenchCommand(CLI::App& app, int& exitCode) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* bench = app.add_subcommand("bench", "Measure the GL tracer: ray rates, samples/s, time to first image");
  bench->add_option("map", options->map, "Level to load (.map or .bsp)")->required();
  addImportOptions(*bench, options->import);
  bench->add_option("--size", options->size, "Image size WxH")->capture_default_str();
  bench->add_option("--bounces", options->bounces, "Bounces of the full samples (physical mode)")->capture_default_str();
  bench->add_option("--seconds", options->seconds, "Time budget of the measurements")->capture_default_str();
  bench->add_option("--gl-textures", options->textures, "Texture path: auto|bindless|arrays")->capture_default_str();
  bench->callback([options, &exitCode] {
    try {
      exitCode = runBench(*options);
    } catch (const gl::GlError& e) {
      fmt::print(stderr, "brushtrace: {}\n", e.what());
      exitCode = 1;
    }
  });
}

} // namespace bt::app
