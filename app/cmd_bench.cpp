// brushtrace bench [MAP]: GL tracer throughput on one level. A benchmark, never a test: the
// numbers depend on the machine. Reports primary and bounce ray rates (closest hits alone),
// full path-traced samples per second at the chosen size and bounce count, and the time from
// the start to the first image as `render` gets there (context, the shader compile started,
// import beside it, upload, the rest of the compile, 1 spp).
#include "app/commands.h"
#include "app/usage_checks.h"
#include "renderer/gl/gl_bench.h"
#include "renderer/gl/gl_error.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

namespace bt::app {

namespace {

struct BenchOptions {
  std::string map;
  ImportOptions import;
  ImageSize size{1280, 720};
  int bounces = 4;
  double seconds = 5.0;
  std::string textures = "auto";
  std::string lighting = "physical";
};

int runBench(const BenchOptions& options) {
  const int width = options.size.width, height = options.size.height;
  const auto textureMode = gl::parseTextureMode(options.textures); // --gl-textures admits only the names it parses
  const auto start = std::chrono::steady_clock::now();
  const Scene scene = importScene(options.map, options.import);
  fmt::print("map: {} ({} brushes, {} faces, {} materials), imported in {:.2f} s\n", options.map, scene.brushes.size(), scene.faces.size(),
             scene.materials.size(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  gl::GlBenchSettings settings{width, height, options.bounces, options.seconds, *textureMode, options.lighting == "physical"};
  // The first image is timed with the import inside it, as `render` gets there.
  return gl::runGlBench([&](const gl::EntitiesRead& entitiesRead) { return importScene(options.map, options.import, entitiesRead); },
                        settings);
}

} // namespace

void addBenchCommand(CLI::App& app, int& exitCode) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* bench = app.add_subcommand("bench", "Measure the GL tracer: ray rates, samples/s, time to first image");
  bench->add_option("map", options->map, "Level to load (.map or .bsp)")->required()->check(levelFile());
  addImportOptions(*bench, options->import);
  addSizeOption(*bench, options->size, "Image size");
  bench->add_option("--bounces", options->bounces, "Bounces of the full samples (physical mode)")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  bench->add_option("--seconds", options->seconds, "Time budget of the measurements")->check(positive())->capture_default_str();
  bench->add_option("--gl-textures", options->textures, "Texture path: auto|bindless|arrays")
      ->check(CLI::IsMember({"auto", "bindless", "arrays"}))
      ->capture_default_str();
  bench->add_option("--lighting", options->lighting, "Lighting of the full samples: physical|faithful")
      ->check(CLI::IsMember({"physical", "faithful"}))
      ->capture_default_str();
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
