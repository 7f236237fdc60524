// brushtrace bench [MAP]: GL tracer throughput on one level. A benchmark, never a test: the
// numbers depend on the machine. Reports primary and bounce ray rates (closest hits alone),
// full path-traced samples per second at the chosen size and bounce count, and the time from
// the start to the first image as `render` gets there (context, the shader compile started,
// import beside it, upload, the rest of the compile, 1 spp).
#include "app/commands.h"
#include "app/usage_checks.h"
#include "lighting/render_scene.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/denoise.h"
#include "renderer/gl/gl_bench.h"
#include "renderer/gl/gl_error.h"
#include "renderer/image_output.h"
#include "renderer/time_to_converged.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <thread>

namespace bt::app {

namespace {

struct BenchOptions {
  std::string map;
  ImportOptions import;
  ImageSize size{1280, 720};
  int bounces = 4;
  float clampIndirect = kClampIndirectDefault;
  double seconds = 5.0;
  std::string textures = "auto";
  std::string lighting = "physical";
  std::string backend = "gl";
  bool timeToConverged = false;
  int referenceSpp = 4096;
  int maxSpp = 0;                // --max-spp
  bool referenceFloor = false;   // --reference-floor
  std::string reference;         // --reference: a stored reference EXR (the CPU tracer's time to converged)
  std::string dump;              // --dump: a folder for the time to converged's images
  std::string sampler = "sobol"; // --sampler: the CPU tracer's physical random numbers
  bool raysOnly = false;
};

// --dump DIR: each image of the time to converged as DIR/NAME.exr (ConvergeRun::keep), or none.
std::function<void(const RenderImage&, const std::string&)> keepIn(const std::string& dump) {
  if (dump.empty()) return {};
  std::filesystem::create_directories(dump);
  return [dir = std::filesystem::path(dump)](const RenderImage& image, const std::string& name) {
    writeImage((dir / (name + ".exr")).string(), image, {});
  };
}

// The CPU tracer's time to converged (the GL tracer's is part of runGlBench): physical light at
// --size with --bounces, denoiser off and on, against a --reference-spp render of another seed.
int runCpuTimeToConverged(const BenchOptions& options) {
  const Scene scene = importScene(options.map, options.import);
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  const CameraPose pose = defaultCameraPose(scene);
  const Camera camera(pose, options.size.width, options.size.height);
  const auto render = [&](int spp, uint32_t seed) {
    RenderSettings settings;
    settings.width = options.size.width, settings.height = options.size.height, settings.spp = spp, settings.seed = seed;
    settings.integrator.mode = LightingMode::Physical;
    settings.integrator.bounces = options.bounces;
    settings.integrator.clampIndirect = options.clampIndirect;
    settings.integrator.lowDiscrepancy = options.sampler == "sobol";
    return renderCpu(rs, camera, settings);
  };
  fmt::print("cpu, {} threads; camera {} ({})\n", std::thread::hardware_concurrency(), formatCameraPose(pose), pose.source);
  // A stored reference (rendered once, for as long as it took: bench/README.md) instead of
  // --reference-spp samples rendered here, which the CPU would take hours over.
  std::optional<RenderImage> stored;
  if (!options.reference.empty()) stored = readExrImage(options.reference);
  printTimeToConverged({.tracer = "cpu",
                        .referenceSpp = stored && stored->samples > 0 ? stored->samples : options.referenceSpp,
                        .bounces = options.bounces,
                        .render = render,
                        .denoiser = [](const RenderImage& image) { return denoise(image); },
                        .storedReference = stored ? &*stored : nullptr,
                        .maxSpp = options.maxSpp,
                        .referenceFloor = options.referenceFloor,
                        .keep = keepIn(options.dump)});
  return 0;
}

int runBench(const BenchOptions& options) {
  if (options.backend == "cpu") return runCpuTimeToConverged(options); // the CPU tracer has only this measure
  if (!options.reference.empty()) throw std::runtime_error("--reference is the CPU tracer's (--backend cpu); the GL one renders its own");
  if (options.sampler != "sobol") throw std::runtime_error("--sampler is the CPU tracer's (--backend cpu); the GL one has only sobol");
  const int width = options.size.width, height = options.size.height;
  const auto textureMode = gl::parseTextureMode(options.textures); // --gl-textures admits only the names it parses
  const auto start = std::chrono::steady_clock::now();
  const Scene scene = importScene(options.map, options.import);
  fmt::print("map: {} ({} brushes, {} faces, {} materials), imported in {:.2f} s\n", options.map, scene.brushes.size(), scene.faces.size(),
             scene.materials.size(), std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  gl::GlBenchSettings settings{width,
                               height,
                               options.bounces,
                               options.seconds,
                               *textureMode,
                               options.lighting == "physical",
                               options.timeToConverged,
                               options.referenceSpp,
                               options.raysOnly,
                               options.clampIndirect,
                               options.referenceFloor,
                               keepIn(options.dump)};
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
  addClampIndirectOption(*bench, options->clampIndirect);
  bench->add_option("--seconds", options->seconds, "Time budget of the measurements")->check(positive())->capture_default_str();
  bench->add_option("--gl-textures", options->textures, "Texture path: auto|bindless|arrays")
      ->check(CLI::IsMember({"auto", "bindless", "arrays"}))
      ->capture_default_str();
  bench->add_option("--lighting", options->lighting, "Lighting of the full samples: physical|faithful")
      ->check(CLI::IsMember({"physical", "faithful"}))
      ->capture_default_str();
  bench->add_flag("--time-to-converged", options->timeToConverged,
                  "Measure only the time until the displayed physical image is within rel. MSE 0.01 of a --reference-spp render, "
                  "denoiser off and on");
  bench->add_flag("--reference-floor", options->referenceFloor,
                  "With --time-to-converged: also render a second reference of another seed and print how far apart the two are "
                  "(the measure's floor)");
  bench->add_flag("--rays-only", options->raysOnly,
                  "Measure only the ray rates (after the cold first image); a level with Quake 3 curves also without them");
  bench->add_option("--backend", options->backend, "gl: the GL tracer; cpu: the CPU tracer (its time to converged only)")
      ->check(CLI::IsMember({"gl", "cpu"}))
      ->capture_default_str();
  bench
      ->add_option("--reference-spp", options->referenceSpp,
                   "Samples per pixel of the time-to-converged reference (of a --reference that does not record them)")
      ->check(positive())
      ->capture_default_str();
  bench
      ->add_option("--max-spp", options->maxSpp,
                   "With --backend cpu: the time-to-converged sweep's last step at most (default: a quarter of the reference's spp)")
      ->check(positive());
  bench
      ->add_option("--reference", options->reference,
                   "With --backend cpu: a stored reference EXR (`render --backend cpu --lighting physical --exposure 0 --seed 24301 "
                   "... -o ref.exr`, same level, camera, size and bounces) instead of rendering one")
      ->check(CLI::ExistingFile);
  bench
      ->add_option("--sampler", options->sampler,
                   "With --backend cpu: physical mode's random numbers, sobol (the pixel's scrambled Sobol sequence for the main "
                   "decisions) or pcg (all from the PCG stream, as before session 24), to measure the two against each other")
      ->check(CLI::IsMember({"sobol", "pcg"}))
      ->capture_default_str();
  bench->add_option("--dump", options->dump,
                    "With --time-to-converged: write the reference and each step's raw image (AOVs, second moment) as DIR/NAME.exr, "
                    "to denoise again");
  bench->callback([options, &exitCode] {
    try {
      exitCode = runBench(*options);
    } catch (const gl::GlError& e) {
      fmt::print(stderr, "brushtrace: {}\n", e.what());
      exitCode = 1;
    } catch (const std::runtime_error& e) { // a stored reference unreadable or of another view
      fmt::print(stderr, "brushtrace: bench: {}\n", e.what());
      exitCode = 1;
    }
  });
}

} // namespace bt::app
