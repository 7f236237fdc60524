// `brushtrace render`: import a level and path-trace it to a PNG or EXR.
#include "app/commands.h"
#include "app/render_options.h"
#include "app/usage_checks.h"

#include "importers/models/entity_models.h"
#include "lighting/compiled_lightmaps.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/denoise.h"
#include "renderer/difference.h"
#include "renderer/exposure.h"
#include "renderer/image_output.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_denoise.h"
#include "renderer/gl/gl_level.h"
#include "renderer/gl/gl_render.h"
#include "renderer/gl/gl_tracer.h"
#include "renderer/view_lightmaps.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <array>
#include <optional>
#include <utility>
#include <unistd.h>

namespace bt::app {

namespace {

// "N=SCALE" of --style: a style 1-255 and a scale 0-2, the viewer's slider range.
std::optional<std::pair<int, float>> parseStyleScale(const std::string& value) {
  int style = 0;
  float scale = 0.0f;
  char end = 0;
  if (std::sscanf(value.c_str(), "%d=%f%c", &style, &scale, &end) != 2) return std::nullopt;
  if (style < 1 || style > 255 || !(scale >= 0.0f && scale <= 2.0f)) return std::nullopt;
  return std::pair{style, scale};
}

// --style's values as a scale per style (1 where none is given), for the lights
// (LightOptions::styleScale) and the compiled lightmaps alike.
std::array<float, 256> styleScales(const std::vector<std::string>& styles) {
  std::array<float, 256> scale;
  scale.fill(1.0f);
  for (const std::string& style : styles) {
    const auto [n, s] = *parseStyleScale(style); // checked by the option's validator
    scale[size_t(n)] = s;
  }
  return scale;
}

// Quake 3 curves and triangle soups drawn, as `info` counts them, and entity models where any.
std::string meshLine(const Scene& scene) {
  size_t curves = 0, curveTriangles = 0, soups = 0, soupTriangles = 0, models = 0, modelTriangles = 0;
  uint32_t lastModelEntity = ~0u; // a model is one mesh per skin or shader, all of one entity
  for (const Mesh& mesh : scene.meshes) {
    const bool curve = mesh.kind == MeshKind::Curve, model = mesh.kind == MeshKind::Model;
    if (model) models += std::exchange(lastModelEntity, mesh.entity) != mesh.entity;
    if (!model) ++(curve ? curves : soups);
    (curve ? curveTriangles : model ? modelTriangles : soupTriangles) += mesh.faceCount / 2;
  }
  std::string line =
      fmt::format("curves {} ({} triangles), triangle soups {} ({} triangles)", curves, curveTriangles, soups, soupTriangles);
  if (models > 0) line += fmt::format(", entity models {} ({} triangles)", models, modelTriangles);
  return line;
}

std::string formatDuration(double seconds) {
  const long s = std::max(0L, long(seconds + 0.5));
  return fmt::format("{:02}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
}

// Progress lines on stdout. Their fraction is that of whichever limit ends the render (samples
// or --time), so the last line says 100 %. Each line is flushed: piped to a log or a GUI, a
// block-buffered stdout would hold them until the end, and lose them on Ctrl-C.
class ProgressPrinter {
public:
  ProgressPrinter(double timeLimit, bool tty) : timeLimit_(timeLimit), tty_(tty) {}

  void operator()(const RenderProgress& p) {
    // The renderers stop after the pass that reaches a limit, on the same elapsed time.
    const bool sppDone = p.samplesTotal > 0 && p.samplesDone >= p.samplesTotal;
    const bool timeUp = timeLimit_ > 0.0 && p.elapsed >= timeLimit_;
    double fraction = p.samplesTotal > 0 ? double(p.samplesDone) / p.samplesTotal : 0.0;
    if (timeLimit_ > 0.0) fraction = std::max(fraction, p.elapsed / timeLimit_);
    if (sppDone || timeUp) fraction = 1.0;
    const std::string total = p.samplesTotal > 0 ? std::to_string(p.samplesTotal) : "?";
    const std::string line = fmt::format("[{:3.0f}%] spp {}/{} est {}", std::min(fraction, 1.0) * 100.0, p.samplesDone, total,
                                         formatDuration(sppDone || timeUp ? 0.0 : p.estimatedRemaining));
    if (tty_) {
      fmt::print("\r{}{}", line, sppDone || timeUp ? "\n" : "");
    } else if (sppDone || timeUp || p.elapsed - lastPrinted_ >= 5.0) { // plain lines, not one per pass
      fmt::print("{}\n", line);
      lastPrinted_ = p.elapsed;
    }
    std::fflush(stdout);
  }

private:
  double timeLimit_;
  bool tty_;
  double lastPrinted_ = -1e30; // the first pass prints at once
};

// Faces a render can show: none (an empty .map, or only clip and trigger brushes) would give a
// black image that looks like a lighting bug.
bool hasDrawnFace(const RenderScene& scene, bool showHidden) {
  return std::any_of(scene.faceFlags.begin(), scene.faceFlags.end(), [&](uint32_t flags) { return showHidden || !(flags & kFaceHidden); });
}

RenderSettings renderSettings(const RenderOptions& o) {
  RenderSettings settings;
  settings.width = o.size.width;
  settings.height = o.size.height;
  settings.spp = o.spp;
  settings.timeLimit = o.timeLimit;
  settings.threads = o.threads;
  settings.seed = o.seed;
  settings.integrator.mode = o.lighting == "physical" ? LightingMode::Physical : LightingMode::Faithful;
  settings.integrator.bounces = o.bounces;
  settings.integrator.clampIndirect = o.clampIndirect;
  // AOVs other than beauty need no samples beyond the one through each pixel centre.
  if (o.aov != "beauty") settings.spp = 1, settings.timeLimit = 0.0;
  return settings;
}

OutputSettings outputSettings(const RenderOptions& o) {
  OutputSettings output;
  output.exposureEv = o.exposure.value_or(0.0f); // physical mode without --exposure: measured after the render
  const std::string tonemap = o.tonemap.empty() ? (o.lighting == "physical" ? "aces" : "faithful") : o.tonemap;
  output.tonemap = tonemap == "aces" ? Tonemap::Aces
      : tonemap == "agx"             ? Tonemap::Agx
      : tonemap == "linear"          ? Tonemap::Linear
                                     : Tonemap::Faithful;
  output.aov = o.aov == "albedo" ? Aov::Albedo
      : o.aov == "normal"        ? Aov::Normal
      : o.aov == "depth"         ? Aov::Depth
      : o.aov == "face"          ? Aov::Face
                                 : Aov::Beauty;
  return output;
}

// gl and auto render on the GL tracer when a GL 4.5 context can be made; otherwise one line
// says why and the CPU reference renders instead. auto also passes over a software GL
// (Mesa's llvmpipe): the CPU tracer is many times faster than compute shaders emulated on it.
std::unique_ptr<gl::GlContext> makeGlContext(const RenderOptions& o) {
  std::unique_ptr<gl::GlContext> glContext;
  if (o.backend != "cpu") {
    try {
      glContext = gl::GlContext::createHeadless();
    } catch (const std::exception& e) {
      fmt::print(stderr, "brushtrace: no GL 4.5 context ({}); rendering on the CPU\n", e.what());
    }
    if (glContext && o.backend == "auto" && glContext->info().softwareRenderer) {
      if (!o.quiet)
        fmt::print(stderr, "brushtrace: GL context is software ({}); rendering on the CPU (--backend gl forces it)\n",
                   glContext->info().renderer);
      glContext.reset();
    }
  }
  return glContext;
}

// What --lighting asks of the level's compiled lightmaps. `compiled`: they are in rs.lightmaps;
// `difference`: they wait in differenceLightmaps for the second render. A level without any
// gets one warning line and faithful light.
struct LightmapChoice {
  bool compiled = false;
  bool difference = false;
  Lightmaps differenceLightmaps;
};

LightmapChoice chooseLightmaps(const RenderOptions& o, const Scene& scene, RenderScene& rs, const std::string& mapPath, bool beauty) {
  // q3map2 leaves no light entities in a compiled Quake 3 level: only its lightmaps show its light.
  const bool quake3Default = !o.lightingGiven && scene.format == "ibsp46";
  if (quake3Default && !o.quiet)
    fmt::print(stderr, "{}: note: a compiled Quake 3 level keeps no lights; showing its lightmaps (--lighting compiled)\n", mapPath);
  LightmapChoice choice;
  if (!beauty || !(o.lighting == "compiled" || o.lighting == "difference" || quake3Default)) return choice;
  const std::array<float, 256> styleScale = styleScales(o.styles); // on the compiled styles as on the lights
  const std::string why = showCompiledLightmaps(scene, rs, o.import.textures.game.game, &styleScale);
  if (!why.empty()) {
    fmt::print(stderr, "{}: warning: {}; showing faithful lighting\n", mapPath, why);
    return choice;
  }
  choice.difference = o.lighting == "difference";
  choice.compiled = !choice.difference;
  if (choice.difference) choice.differenceLightmaps = std::exchange(rs.lightmaps, Lightmaps{});
  return choice;
}

// Faithful mode's luxels of the faces the camera sees: baked here on all cores for the CPU
// backend; for the GL backend laid out with their sample points, which the GPU lights (gl_bake.h).
std::optional<LuxelBakeJob> bakeFaithful(const RenderOptions& o, RenderScene& rs, const CameraPose& pose, bool onGpu) {
  const Camera camera(pose, o.size.width, o.size.height);
  LightmapBakeOptions bake;
  bake.extra = o.extra;
  bake.threads = unsigned(o.threads);
  if (!onGpu) {
    bakeFaithfulLightmaps(rs, &camera, o.size.width, o.size.height, bake);
    return std::nullopt;
  }
  rs.lightmaps = layoutFaithfulLightmaps(rs, &camera, o.size.width, o.size.height, bake.threads);
  return luxelBakeJob(rs, rs.lightmaps, bake);
}

// The GL programs the render needs, compiling as soon as what they need is known, on the
// driver's threads where it has them: ready, or nearly, once the level is prepared. This thread
// then waits for them while the worker prepares the level: NVIDIA's driver finishes a link on the
// thread that waits for it (see gl::loadGlLevel).
std::shared_ptr<gl::TracerPrograms> startGlPrograms(const RenderOptions& o, gl::GlContext& context, gl::TextureMode textures,
                                                    gl::LevelPreparation& preparation) {
  const bool physical = o.lighting == "physical";
  auto programs = std::make_shared<gl::TracerPrograms>(context, textures);
  programs->startTraceKernel();
  const bool liquidCsg = preparation.levelParts().liquidCsg;
  programs->startAovs(liquidCsg);
  if (o.aov == "beauty") {
    // A faithful beauty shows luxels (baked before it, or the compiled ones) but with --luxels off.
    const bool luxels = !physical && (o.luxels == "on" || o.lighting != "faithful");
    const gl::FaithfulFeatures features = gl::startPathTracerFor(*programs, preparation, physical, luxels);
    programs->aovs(liquidCsg);
    if (programs->wavefrontState(physical, features).started) programs->wavefront(physical, features);
  } else {
    programs->aovs(liquidCsg);
  }
  return programs;
}

// The import's warnings and errors, the light preparation's diagnostics and the meshes' line.
void printPreparation(const Scene& scene, const Diagnostics& lightDiagnostics) {
  for (const Diagnostic& d : scene.diagnostics)
    if (d.severity != Severity::Note) fmt::print(stderr, "{}\n", format(d));
  for (const Diagnostic& d : lightDiagnostics) fmt::print(stderr, "{}\n", format(d));
  if (!scene.meshes.empty()) fmt::print("{}\n", meshLine(scene));
  if (const Diagnostic* missing = models::missingModelsNote(scene)) fmt::print("{}\n", missing->message);
}

std::string writtenLine(const RenderOptions& o, const RenderImage& image, const LightmapChoice& choice, bool aovsOnly,
                        const OutputSettings& written, const std::string& device) {
  const std::string lighting = choice.compiled ? "compiled"
      : choice.difference                      ? "difference"
      : o.lighting == "physical"               ? "physical"
                                               : "faithful";
  std::string rendered = aovsOnly ? fmt::format("--aov {}", o.aov) : fmt::format("{} spp, {} lighting", image.samples, lighting);
  if (!aovsOnly && (written.exposureAuto || o.exposure))
    rendered += fmt::format(", exposure {:+.2f} EV{}", written.exposureEv, written.exposureAuto ? " auto" : "");
  if (!image.denoised.empty()) rendered += ", denoised";
  return fmt::format("wrote {} ({}x{}, {}, {})", o.output, o.size.width, o.size.height, rendered, device);
}

// What the display does with a finished beauty: --denoise (on the tracer that rendered it) and
// physical mode's automatic exposure, measured on the raw beauty (both layers are written with it).
void finishBeauty(const RenderOptions& o, RenderImage& image, OutputSettings& written, gl::GlContext* glContext) {
  if (o.denoise) image.denoised = glContext ? gl::denoiseWithGl(image) : denoise(image, o.threads);
  if (o.lighting == "physical" && !o.exposure) {
    written.exposureEv = autoExposureEv(image.beauty, image.width, image.height);
    written.exposureAuto = true;
  }
}

} // namespace

int runRender(const RenderOptions& o, RenderOutcome* outcome) {
  const int width = o.size.width, height = o.size.height;
  std::string ext = std::filesystem::path(o.output).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  // A PNG of an AOV shows that AOV alone, so the GL backend renders no beauty for it (an EXR
  // always holds the beauty layer too).
  const bool aovsOnly = o.aov != "beauty" && ext == ".png";

  const std::optional<gl::TextureMode> glTextures = gl::parseTextureMode(o.glTextures);
  if (!glTextures) throw std::runtime_error("--gl-textures: expected auto, bindless or arrays");

  // The level is imported and prepared on a worker thread from the start: its import overlaps
  // the GL context's creation, and once its lights are collected the GL programs it needs start
  // compiling while the rest of the preparation runs (gl::LevelPreparation).
  const std::string mapPath = o.map.empty() ? defaultMapPath() : o.map;
  const bool physical = o.lighting == "physical";
  RenderSceneOptions sceneOptions;
  sceneOptions.showHidden = o.showHidden;
  sceneOptions.lights.styleScale = styleScales(o.styles);
  sceneOptions.bounceLights = !physical && o.aov == "beauty"; // faithful _bounce only
  // What faithful luxels read: computed by the GL bake where the GL tracer renders (a CPU bake
  // after a failed context computes them as it starts).
  using VisBoxes = RenderSceneOptions::VisBoxes;
  sceneOptions.visApproxBoxes = physical ? VisBoxes::Off : o.backend == "cpu" ? VisBoxes::Cpu : VisBoxes::Gpu;
  Scene scene;
  RenderScene renderScene;
  Diagnostics lightDiagnostics;
  gl::LevelPreparation preparation(
      scene, renderScene, [&](const gl::EntitiesRead& entitiesRead) { return importScene(mapPath, o.import, entitiesRead); }, sceneOptions,
      &lightDiagnostics);

  std::unique_ptr<gl::GlContext> glContext = makeGlContext(o);

  std::shared_ptr<gl::TracerPrograms> glPrograms;
  if (glContext) glPrograms = startGlPrograms(o, *glContext, *glTextures, preparation);
  preparation.wait();
  if (!o.quiet) printPreparation(scene, lightDiagnostics);

  if (!hasDrawnFace(renderScene, o.showHidden)) {
    fmt::print(stderr, "{}: warning: the level has no face to draw; no image written\n", mapPath);
    return 1;
  }

  const CameraPose pose = o.camera ? *o.camera : defaultCameraPose(scene);
  if (!o.quiet) fmt::print("camera {} ({})\n", formatCameraPose(pose), pose.source);
  std::fflush(stdout); // a pipe reads it now, not when the render ends

  const RenderSettings settings = renderSettings(o);
  const OutputSettings output = outputSettings(o);
  ProgressPrinter printer(settings.timeLimit, isatty(fileno(stdout)));
  std::function<void(const RenderProgress&)> progress;
  if (!o.quiet) progress = std::ref(printer);

  const LightmapChoice choice = chooseLightmaps(o, scene, renderScene, mapPath, output.aov == Aov::Beauty);
  // Faithful mode shows the compiler's luxels as the game does; `--luxels off` evaluates the
  // light at each pixel's own point ("what the light is" rather than "what the game shows").
  std::optional<LuxelBakeJob> gpuBake;
  if (!choice.compiled && settings.integrator.mode == LightingMode::Faithful && output.aov == Aov::Beauty && o.luxels == "on")
    gpuBake = bakeFaithful(o, renderScene, pose, glContext != nullptr);

  const gl::GlRenderParts glParts = aovsOnly ? gl::GlRenderParts::AovsOnly : gl::GlRenderParts::BeautyAndAovs;
  const LuxelBakeJob* bakeFirst = gpuBake ? &*gpuBake : nullptr; // the faithful image's luxels, lit on the GPU
  const auto render = [&] {
    const LuxelBakeJob* bake = std::exchange(bakeFirst, nullptr);
    return glContext ? gl::renderWithGl(*glContext, renderScene, pose, settings, glPrograms, progress, glParts, bake).image
                     : renderCpu(renderScene, Camera(pose, width, height), settings, progress);
  };
  RenderImage image = render();
  OutputSettings written = output;
  if (choice.difference) { // the faithful image first, then the compiled one from the same camera
    renderScene.lightmaps = choice.differenceLightmaps;
    image = differenceImage(render(), image, output);
    written.exposureEv = 0.0f, written.tonemap = Tonemap::Faithful; // the heat map's own colours
  } else if (!aovsOnly) {
    finishBeauty(o, image, written, glContext.get());
  }
  writeImage(o.output, image, written);
  const std::string device = glContext ? "gl " + glContext->info().renderer : std::string("cpu");
  if (!o.quiet) fmt::print("{}\n", writtenLine(o, image, choice, aovsOnly, written, device));
  if (outcome) *outcome = {pose, image.samples, device, written.exposureEv};
  return 0;
}

void addRenderCommand(CLI::App& app, int& exitCode) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Path-trace a level's lighting to an image (PNG or EXR)");
  cmd->add_option("map", options->map,
                  "Level to render (.map, .bsp, ARCHIVE:maps/x.bsp, or a level name with --game/--basedir); default maps/start.map")
      ->type_name("MAP")
      ->check(levelFile());
  cmd->add_option("-o,--output", options->output, "Output image, .png (tonemapped sRGB) or .exr (linear + AOV layers)")
      ->required()
      ->type_name("OUT")
      ->check(imageFile());
  CLI::Option* spp = cmd->add_option("--spp", options->spp, "Samples per pixel")->check(positive())->capture_default_str();
  cmd->add_option("--time", options->timeLimit,
                  "Stop after this many seconds (with --spp: whichever comes first; alone: as many samples as fit)")
      ->type_name("S")
      ->check(positive());
  addSizeOption(*cmd, options->size, "Image size");
  addCameraOption(
      *cmd, options->camera,
      "Camera \"(x y z) pitch yaw roll\" or \"setpos x y z pitch yaw roll\" (roll optional); default from the level's entities");
  cmd->add_option("--backend", options->backend, "auto|gl|cpu")->check(CLI::IsMember({"auto", "gl", "cpu"}))->capture_default_str();
  cmd->add_option("--gl-textures", options->glTextures, "GL texture path: auto|bindless|arrays")
      ->check(CLI::IsMember({"auto", "bindless", "arrays"}))
      ->capture_default_str();
  cmd->add_option("--aov", options->aov, "beauty|albedo|normal|depth|face")
      ->check(CLI::IsMember({"beauty", "albedo", "normal", "depth", "face"}))
      ->capture_default_str();
  cmd->add_option("--exposure", options->exposure,
                  "Exposure in EV (stops); default: automatic for physical lighting (log-average luminance to 0.18), 0 otherwise")
      ->type_name("EV");
  cmd->add_flag(
      "--denoise", options->denoise,
      "Denoise the beauty (a-trous filter guided by the AOVs): the PNG shows it, the EXR keeps the raw beauty and adds it as denoised.*");
  cmd->add_option("--tonemap", options->tonemap, "faithful|aces|agx|linear (default faithful, aces for physical lighting)")
      ->check(CLI::IsMember({"faithful", "aces", "agx", "linear"}));
  cmd->add_option("--lighting", options->lighting,
                  "faithful (ericw-tools light formulas) | physical (radiometric path tracing) | compiled (a .bsp's own "
                  "lightmaps, as its engine shows them) | difference (compiled vs faithful as a heat map)")
      ->check(CLI::IsMember({"faithful", "physical", "compiled", "difference"}))
      ->capture_default_str();
  cmd->add_option("--luxels", options->luxels,
                  "Faithful lighting: on = the compiler's luxels filtered as the engine shows them, off = the light at each pixel")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd->add_option("--style", options->styles,
                  "Light style N's lights (and, with --lighting compiled, its compiled lightmaps) times SCALE, as the viewer's sliders "
                  "(N=SCALE, repeatable)")
      ->check(CLI::Validator(
          [](std::string& value) { return parseStyleScale(value) ? std::string() : "expected N=SCALE, N 1-255, SCALE 0-2: " + value; },
          "N=SCALE"));
  cmd->add_option("--extra", options->extra, "Faithful luxels: sample points per luxel along each axis (light -extra: 1, 2 or 4)")
      ->check(CLI::IsMember({1, 2, 4}))
      ->capture_default_str();
  cmd->add_option("--bounces", options->bounces, "Physical lighting: indirect bounces")->check(CLI::Range(0, 64))->capture_default_str();
  addClampIndirectOption(*cmd, options->clampIndirect);
  cmd->add_option("--threads", options->threads, "Worker threads (0 = all cores)")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--seed", options->seed, "Random seed: same seed and spp give the same image")->capture_default_str();
  cmd->add_flag("--quiet", options->quiet, "No progress or camera lines");
  cmd->add_flag("--show-hidden", options->showHidden, "Draw clip/trigger/skip/hint/origin faces");
  addImportOptions(*cmd, options->import);
  CLI::Option* lighting = cmd->get_option("--lighting");
  cmd->callback([options, spp, lighting, &exitCode] {
    options->lightingGiven = lighting->count() > 0;
    if (options->timeLimit > 0.0 && spp->count() == 0) options->spp = 0; // --time alone: as many samples as fit
    exitCode = runRender(*options);
  });
}

} // namespace bt::app
