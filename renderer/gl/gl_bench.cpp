#include "renderer/gl/gl_bench.h"

#include "renderer/view_lightmaps.h"

#include "renderer/camera.h"
#include "renderer/time_to_converged.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_bake.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_denoise.h"
#include "renderer/gl/gl_level.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <random>

namespace bt::gl {

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}
} // namespace

namespace {

// Faithful mode's bake on the GPU (gl_bake.h) of `what`: the layout and sample points on the
// CPU, then every pass on the GPU (the program built first, timed apart).
void benchGpuBake(gl::GlTracer& tracer, const RenderScene& rs, const Camera* camera, const GlBenchSettings& s, const char* what) {
  const auto start = Clock::now();
  const Lightmaps layout = layoutFaithfulLightmaps(rs, camera, s.width, s.height);
  const double layoutSeconds = secondsSince(start);
  const auto samplesStart = Clock::now();
  const LuxelBakeJob job = luxelBakeJob(rs, layout);
  const double samplesSeconds = secondsSince(samplesStart);
  tracer.setLightmaps(packLightmaps(layout));
  const auto buildStart = Clock::now();
  gl::GlLightmapBake bake(tracer, job);
  const double buildSeconds = secondsSince(buildStart);
  // The visapprox boxes the level's preparation left to the GPU, before the first pass (gl_bake.h).
  const auto boxStart = Clock::now();
  const size_t boxes = job.lightBoxes.empty() ? bake.lightBoxes().size() : 0;
  const double boxSeconds = secondsSince(boxStart);
  const auto gpuStart = Clock::now();
  bake.finish();
  const double gpuSeconds = secondsSince(gpuStart);
  fmt::print("faithful bake on the GPU, {}: {} luxels, {} passes; CPU layout {:.3f} s + sample points {:.3f} s, visapprox boxes of "
             "{} lights {:.3f} s, GPU passes {:.3f} s (program build {:.2f} s)\n",
             what, layout.luxels.size(), job.passes, layoutSeconds, samplesSeconds, boxes, boxSeconds, gpuSeconds, buildSeconds);
  tracer.setLightmaps({});
}

// Faithful mode as `render` shows it: the faces the camera sees baked on the CPU (timed), then
// frames that each look up the luxels: what a camera move costs once the bake is done.
void benchBakedLuxels(gl::GlTracer& tracer, RenderScene& rs, const CameraPose& pose, const gl::CameraBasis& camera,
                      gl::BeautySettings settings, const GlBenchSettings& s) {
  const auto bakeStart = Clock::now();
  const Camera cpuCamera(pose, s.width, s.height);
  bakeFaithfulLightmaps(rs, &cpuCamera, s.width, s.height, {});
  const double bakeSeconds = secondsSince(bakeStart);
  tracer.setLightmaps(packLightmaps(rs.lightmaps));
  fmt::print("faithful luxels: {} faces seen, {} luxels baked on the CPU in {:.2f} s\n",
             rs.lightmaps.faceRanges.size() -
                 size_t(std::count(rs.lightmaps.faceRanges.begin(), rs.lightmaps.faceRanges.end(), glm::uvec2(0))),
             rs.lightmaps.luxels.size(), bakeSeconds);
  settings.physical = false;
  settings.form = gl::PathTracerForm::Megakernel;
  tracer.renderBeauty(camera, settings);
  const auto start = Clock::now();
  settings.spp = 512; // about 0.3 s on an H100: 64 took 0.04 s, whose timing moved by 12 % from run to run
  const gl::BeautyImage image = tracer.renderBeauty(camera, settings);
  const double seconds = secondsSince(start);
  fmt::print("samples: {:.2f} full samples/s at {}x{}, faithful, baked luxels ({} spp in {:.2f} s)\n", image.samples / seconds, s.width,
             s.height, image.samples, seconds);
  rs.lightmaps = {};
  tracer.setLightmaps({});
  benchGpuBake(tracer, rs, &cpuCamera, s, "the camera's faces");
  benchGpuBake(tracer, rs, nullptr, s, "the whole level");
}

// What one first-image run leaves for the measurements after it.
struct BenchRun {
  std::unique_ptr<gl::GlContext> context;
  std::unique_ptr<gl::GlLevel> level;
  CameraPose pose;
};

gl::BeautySettings oneSampleSettings(const GlBenchSettings& s) {
  return {.width = s.width, .height = s.height, .spp = 1, .physical = s.physical, .bounces = s.bounces, .clampIndirect = s.clampIndirect};
}

// The level's import started on a worker thread, the context made meanwhile, the path tracer's
// compile started (it runs on the driver's threads where the driver has them) once the level's
// lights are known, the level prepared meanwhile, then uploaded: as `render` gets there.
gl::GlLevelTimes loadLevel(BenchRun& run, const LevelImport& importLevel, const GlBenchSettings& s, const std::filesystem::path& cacheDir) {
  run.level = std::make_unique<gl::GlLevel>();
  gl::GlLevelTimes times;
  const std::unique_ptr<gl::LevelPreparation> preparation = gl::prepareGlLevel(*run.level, importLevel);
  run.context = gl::GlContext::createHeadless();
  times.contextMade = Clock::now();
  auto programs = std::make_shared<gl::TracerPrograms>(*run.context, s.textures);
  programs->setCache(gl::ProgramCache(cacheDir));
  gl::loadGlLevel(*run.level, *preparation, *run.context, programs, s.physical, &times);
  return times;
}

// One sample with the given form; its seconds.
double timeOneSample(gl::GlTracer& tracer, const gl::CameraBasis& camera, const GlBenchSettings& s, gl::PathTracerForm form) {
  gl::BeautySettings settings = oneSampleSettings(s);
  settings.form = form;
  const auto sampleStart = Clock::now();
  tracer.renderBeauty(camera, settings);
  return secondsSince(sampleStart);
}

// `render` and the viewer draw their first images with the wavefront kernels while the
// megakernel compiles (gl::PathTracerForm::Auto), where they were started for it.
void wavefrontFirstImage(gl::GlTracer& tracer, const gl::CameraBasis& camera, const GlBenchSettings& s, const char* label,
                         Clock::time_point start, const gl::GlLevelTimes& times) {
  auto at = [&](Clock::time_point t) { return std::chrono::duration<double>(t - start).count(); };
  const gl::ProgramBuild build = tracer.buildWavefront(s.width, s.height, s.physical);
  const double waitSeconds = secondsSince(times.uploaded);
  const double readySeconds = secondsSince(start);
  const double sample = timeOneSample(tracer, camera, s, gl::PathTracerForm::Wavefront);
  const double total = secondsSince(start);
  const bool megakernelReady = !tracer.programs().wavefrontWhileCompiling(s.physical, tracer.faithfulFeatures());
  fmt::print("time to first image, wavefront kernels ({}): {:.3f} s at {}x{}: their compile {:.0f} ms of which {:.0f} ms "
             "after the upload (ready at {:.3f} s), 1 spp {:.3f} s; the megakernel {}\n",
             label, total, s.width, s.height, build.milliseconds, waitSeconds * 1000.0, readySeconds, sample,
             megakernelReady ? "was ready before" : "still compiling");
  // Each step's end, in seconds from the start, to see which one the first image waits for.
  fmt::print("  timeline: context {:.3f}, lights collected {:.3f} (worker thread), compiles started {:.3f} (the main "
             "thread's share of starting them), trace kernel linked {:.3f}, level prepared {:.3f} (worker thread), "
             "uploaded {:.3f}, shade kernel linked {:.3f}, first dispatches done {:.3f}, first sample read back {:.3f}\n",
             at(times.contextMade), at(times.lightsCollected), at(times.programsStarted), at(times.traceLinked), at(times.prepared),
             at(times.uploaded), at(times.shadeLinked), readySeconds, total);
  // What the main thread's share of the starts is made of, and the first dispatches'.
  const gl::TracerPrograms::Started started = tracer.programs().started(s.physical, tracer.faithfulFeatures());
  auto queued = [&](const gl::ComputeProgram* p) {
    return p ? fmt::format("queued {:.3f} ({:.1f} ms, the driver's calls {:.1f}, glLinkProgram {:.1f})", at(p->queuedAt()),
                           p->startMilliseconds(), p->startDriverMilliseconds(), p->startLinkMilliseconds())
             : std::string("not started");
  };
  fmt::print("  starts: shade kernel {}, trace kernel {}, megakernel {}; first dispatches {:.1f} ms (calls {:.1f}, glFinish {:.1f})\n",
             queued(started.shade), queued(started.trace), queued(started.megakernel), build.dispatchMilliseconds,
             build.dispatchCallsMilliseconds, build.dispatchMilliseconds - build.dispatchCallsMilliseconds);
}

// Time to first image: the level loaded (loadLevel), then the wait for the compile and one
// sample: with the wavefront kernels where they were started (TracerPrograms::startPathTracer
// says where), and with the megakernel.
void firstImage(BenchRun& run, const LevelImport& importLevel, const GlBenchSettings& s, const std::filesystem::path& cacheDir,
                const char* label) {
  run.level.reset();
  run.context.reset();
  const auto start = Clock::now();
  const gl::GlLevelTimes times = loadLevel(run, importLevel, s, cacheDir);
  gl::GlTracer& tracer = *run.level->tracer;
  const double importSeconds = std::chrono::duration<double>(times.prepared - start).count();
  const double uploadSeconds = std::chrono::duration<double>(times.uploaded - times.uploadStarted).count();
  const double contextSeconds = std::chrono::duration<double>(times.contextMade - start).count();
  // The default view (info_intermission, info_player_start, else the whole level), so the
  // rays see what a user first sees.
  run.pose = defaultCameraPose(run.level->scene);
  const gl::CameraBasis camera = gl::cameraFrom(run.pose, s.width, s.height);
  if (tracer.programs().wavefrontState(s.physical, tracer.faithfulFeatures()).started)
    wavefrontFirstImage(tracer, camera, s, label, start, times);
  // The megakernel's first image: the wait for its compile, then one sample.
  const gl::ProgramBuild build = tracer.buildPathTracer(s.width, s.height, s.physical);
  const double readySeconds = secondsSince(start);
  const double waitSeconds = secondsSince(times.uploaded);
  const double sample = timeOneSample(tracer, camera, s, gl::PathTracerForm::Megakernel);
  fmt::print("time to first image ({}): {:.3f} s at {}x{}: context {:.3f} s, level prepared at {:.3f} s, upload {:.3f} s, "
             "compile {:.0f} ms of which {:.0f} ms after the upload{}, 1 spp {:.3f} s (megakernel ready at {:.3f} s)\n",
             label, secondsSince(start), s.width, s.height, contextSeconds, importSeconds, uploadSeconds, build.milliseconds,
             waitSeconds * 1000.0, build.fromCache ? " (program binary from the cache)" : "", sample, readySeconds);
}

struct RayRates {
  double primary = 0.0, bounce = 0.0, shadow = 0.0; // Mrays/s
};

// Ray rates: enough passes to fill about a third of the time budget each. The first probe
// also builds the program, so the second one sizes the run. `label` goes before each line.
RayRates benchRays(gl::GlTracer& tracer, const gl::CameraBasis& camera, const GlBenchSettings& s, const char* label = "") {
  const gl::RayBenchVariant variant{.defines = s.rayBenchDefines, .binaryPath = s.rayBenchBinary};
  tracer.benchmarkRays(camera, s.width, s.height, 1, variant);
  gl::RayBenchmark probe = tracer.benchmarkRays(camera, s.width, s.height, 1, variant);
  fmt::print("{}ray results of one pass: primary {:016x}, bounce {:016x}, shadow {:016x}\n", label, probe.primaryHash, probe.bounceHash,
             probe.shadowHash);
  if (!variant.defines.empty())
    fmt::print("{}timed: raybench.comp with {}; its results of one pass: primary {:016x}, bounce {:016x}, shadow {:016x}\n", label,
               fmt::join(variant.defines, " "), probe.variantHashes[0], probe.variantHashes[1], probe.variantHashes[2]);
  if (probe.counted) {
    const char* kinds[] = {"primary", "bounce", "shadow"};
    const char* counts[] = {"nodes", "brush boxes", "brushes past their box", "planes", "deepest stack"};
    for (int mode = 0; mode < 3; ++mode) {
      const double rays = double(mode == 0 ? probe.primaryRays : probe.bounceRays);
      std::string line = fmt::format("{}per {} ray (one pass):", label, kinds[mode]);
      for (int i = 0; i < 5; ++i)
        line += fmt::format(" {} {:.2f} (max {})", counts[i], probe.walkCounts[16 * mode + 2 * i] / std::max(rays, 1.0),
                            probe.walkCounts[16 * mode + 2 * i + 1]);
      fmt::print("{}\n", line);
    }
  }
  const double perPass = std::max(probe.primarySeconds + probe.bounceSeconds + probe.shadowSeconds, 1e-4);
  const int passes = std::max(1, static_cast<int>(s.seconds / 3.0 / perPass));
  const gl::RayBenchmark rays = tracer.benchmarkRays(camera, s.width, s.height, passes, {.defines = s.rayBenchDefines});
  const RayRates rates{rays.primaryRays * double(rays.passes) / rays.primarySeconds * 1e-6,
                       rays.bounceRays * double(rays.passes) / rays.bounceSeconds * 1e-6,
                       rays.bounceRays * double(rays.passes) / rays.shadowSeconds * 1e-6};
  fmt::print("{}primary rays: {:.2f} Mrays/s ({} passes of {})\n", label, rates.primary, rays.passes, rays.primaryRays);
  fmt::print("{}bounce rays:  {:.2f} Mrays/s ({} passes of {})\n", label, rates.bounce, rays.passes, rays.bounceRays);
  fmt::print("{}shadow rays:  {:.2f} Mrays/s ({} passes of {}: the bounce rays as any-hit queries of at most {:.0f} units, their "
             "median length)\n",
             label, rates.shadow, rays.passes, rays.bounceRays, rays.shadowLength);
  return rates;
}

// The level with its Quake 3 patches left out: their faces hidden as the engine hides a nodraw
// surface, so the tracers' triangle BVH holds the other meshes only (soups, models), if any.
Scene withoutCurves(Scene scene) {
  for (const Mesh& mesh : scene.meshes)
    if (mesh.kind == MeshKind::Curve)
      for (uint32_t f = mesh.firstFace; f < mesh.firstFace + mesh.faceCount; ++f) scene.faces[f].texture = "common/nodraw";
  return scene;
}

// Issue 16's curve cost per ray: the same level without its curves, from the same camera, on
// the same context; then each rate with the curves as a share of the rate without them.
void benchRaysWithoutCurves(BenchRun& run, const LevelImport& importLevel, const GlBenchSettings& s, const RayRates& withCurves) {
  const auto curves = std::count_if(run.level->scene.meshes.begin(), run.level->scene.meshes.end(),
                                    [](const Mesh& m) { return m.kind == MeshKind::Curve; });
  if (curves == 0) return;
  gl::GlLevel flat;
  auto programs = std::make_shared<gl::TracerPrograms>(*run.context, s.textures);
  programs->setCache(gl::ProgramCache{});
  gl::loadGlLevel(flat, *run.context, programs, s.physical, [&](const gl::EntitiesRead& read) { return withoutCurves(importLevel(read)); });
  const RayRates rates = benchRays(*flat.tracer, gl::cameraFrom(run.pose, s.width, s.height), s, "without its curves: ");
  fmt::print("with its {} curves, per ray: primary {:.1f} %, bounce {:.1f} %, shadow {:.1f} % of the rate without them\n", curves,
             100.0 * withCurves.primary / rates.primary, 100.0 * withCurves.bounce / rates.bounce,
             100.0 * withCurves.shadow / rates.shadow);
}

// Full samples in one lighting mode with one form of the path tracer. A sample's cost varies
// with the dispatch queue's state, so the batch doubles until one takes at least a second (and
// a sixth of the budget); renderBeauty reads the image back at the end, which waits for every
// dispatch.
void benchSamples(gl::GlTracer& tracer, const gl::CameraBasis& camera, const GlBenchSettings& s, bool physical, gl::PathTracerForm form) {
  gl::BeautySettings settings = oneSampleSettings(s);
  settings.physical = physical;
  settings.form = form;
  tracer.renderBeauty(camera, settings); // builds the programs; this warms the queue
  const double minimum = std::max(1.0, s.seconds / 6.0);
  double seconds = 0.0;
  gl::BeautyImage image;
  for (;;) {
    const auto start = Clock::now();
    image = tracer.renderBeauty(camera, settings);
    seconds = secondsSince(start);
    if (seconds >= minimum) break;
    // Aim past the minimum from the rate so far, at least doubling.
    settings.spp = std::max(settings.spp * 2, static_cast<int>(settings.spp * 1.2 * minimum / std::max(seconds, 1e-4)));
  }
  fmt::print("samples: {:.2f} full samples/s at {}x{}, {}{} ({} spp in {:.2f} s, {:.1f} Msamples/s)\n", image.samples / seconds, s.width,
             s.height, physical ? fmt::format("physical, {} bounces", s.bounces) : std::string("faithful"),
             form == gl::PathTracerForm::Wavefront ? ", wavefront kernels" : "", image.samples, seconds,
             image.samples * double(s.width) * s.height / seconds * 1e-6);
}

// Issue 18's time to converged on the GPU: renderBeauty at 1, 2, 4, ... spp (read back, as the
// measure needs the image) and the denoiser's passes on it (gl_denoise.h); the AOVs, which the
// viewer has before its first sample, are rendered once outside the timing.
void benchTimeToConverged(gl::GlTracer& tracer, const gl::CameraBasis& camera, const GlBenchSettings& s) {
  const AovImages aov = tracer.renderAovs(camera, s.width, s.height);
  const auto render = [&](int spp, uint32_t seed) {
    gl::BeautySettings settings = oneSampleSettings(s);
    settings.spp = spp, settings.seed = seed, settings.physical = true, settings.bounces = s.bounces;
    const BeautyImage beauty = tracer.renderBeauty(camera, settings);
    RenderImage image;
    image.width = s.width, image.height = s.height, image.samples = beauty.samples, image.beauty = beauty.beauty;
    image.luminanceMoment2 = beauty.luminanceMoment2;
    image.normal = aov.normal, image.depth = aov.depth, image.face = aov.face;
    for (const glm::vec4& a : aov.albedo) image.albedo.emplace_back(a);
    return image;
  };
  // One denoiser program for the sweep, as the viewer keeps one (viewer_display.cpp): each step's
  // time is then the filter's, not its program's build.
  gl::DenoisePass pass;
  printTimeToConverged({.tracer = "gl",
                        .referenceSpp = s.referenceSpp,
                        .bounces = s.bounces,
                        .render = render,
                        .denoiser = [&pass](const RenderImage& image) { return denoiseWithGl(image, pass); },
                        .referenceFloor = s.referenceFloor,
                        .keep = s.keep});
}

} // namespace

int runGlBench(const LevelImport& importLevel, const GlBenchSettings& s) {
  // Cold with an empty program cache (every shader compiled, as on a first start), then warm
  // from the binaries that run stored. A private cache directory keeps the user's cache out of it.
  const std::filesystem::path cacheDir =
      std::filesystem::temp_directory_path() / fmt::format("brushtrace-bench-{:08x}", std::random_device{}());
  BenchRun run;
  firstImage(run, importLevel, s, cacheDir, "cold, empty program cache");
  const auto& info = run.context->info();
  gl::GlTracer& tracer = *run.level->tracer;
  fmt::print("device: {} ({}, {}), textures: {}, trace layout: {}, parallel shader compile: {}\n", info.renderer, info.platform,
             info.version, gl::toString(tracer.textureMode()),
             tracer.programs().traceLayout() == gl::TraceLayout::Software ? "software" : "hardware",
             info.parallelShaderCompile ? "yes" : "no");
  fmt::print("camera: {} ({}), {} lights, {} emitter triangles\n", formatCameraPose(run.pose), run.pose.source,
             run.level->render.lights.size(), run.level->render.emitters.size());
  if (s.raysOnly) {
    run.level->tracer->setProgramCache(gl::ProgramCache{});
    std::error_code ignored;
    std::filesystem::remove_all(cacheDir, ignored);
    const RayRates rates = benchRays(*run.level->tracer, gl::cameraFrom(run.pose, s.width, s.height), s);
    benchRaysWithoutCurves(run, importLevel, s, rates);
    return run.context->debugErrorCount() == 0 ? 0 : 1;
  }
  if (s.timeToConverged) {
    std::error_code ignored;
    std::filesystem::remove_all(cacheDir, ignored);
    benchTimeToConverged(tracer, gl::cameraFrom(run.pose, s.width, s.height), s);
    return run.context->debugErrorCount() == 0 ? 0 : 1;
  }
  firstImage(run, importLevel, s, cacheDir, "warm");
  gl::GlTracer& warm = *run.level->tracer;
  // The programs built from here on (ray bench, the other lighting mode) are not stored: the
  // private directory would otherwise be created again and left behind.
  warm.setProgramCache(gl::ProgramCache{});
  std::error_code ignored;
  std::filesystem::remove_all(cacheDir, ignored);
  const gl::CameraBasis camera = gl::cameraFrom(run.pose, s.width, s.height);
  const RayRates rays = benchRays(warm, camera, s);
  for (const bool physical : {s.physical, !s.physical})
    for (const gl::PathTracerForm form : {gl::PathTracerForm::Megakernel, gl::PathTracerForm::Wavefront})
      benchSamples(warm, camera, s, physical, form);
  benchBakedLuxels(warm, run.level->render, run.pose, camera, oneSampleSettings(s), s);
  benchRaysWithoutCurves(run, importLevel, s, rays); // last: its upload rebinds the context's buffers
  return run.context->debugErrorCount() == 0 ? 0 : 1;
}

} // namespace bt::gl
