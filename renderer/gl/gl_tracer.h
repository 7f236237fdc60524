// The GL compute tracer: a Scene uploaded once, images rendered from a camera.
#pragma once

#include "bvh/trace_scene.h"
#include "lighting/light_grid.h"
#include "lighting/lights.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_program_cache.h"
#include "renderer/gl/gl_structs.h"
#include "renderer/gl/gl_textures.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace bt::gl {

// A pinhole camera as the shaders take it. right and up are scaled by tan(fov / 2) along
// their axis: the ray through pixel centre (x, y) of a w by h image, y counted from the top,
// is forward + (2 (x + 0.5) / w - 1) right + (1 - 2 (y + 0.5) / h) up, normalised.
struct CameraBasis {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{1.0f, 0.0f, 0.0f};
  glm::vec3 right{0.0f, -1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};

  // Quake's view angles in degrees (pitch positive looks down, yaw counter-clockwise from +X,
  // roll), axes as Quake's AngleVectors like renderer/cpu's Camera, and a horizontal field of
  // view (Quake's default 90) for a width by height image.
  static CameraBasis fromQuakeAngles(const glm::vec3& origin, float pitch, float yaw, float roll, int width, int height,
                                     float horizontalFovDegrees = 90.0f);
};

// Per pixel, rows top to bottom, with the CPU reference's meanings (renderer/cpu RenderImage).
// A pixel that sees nothing has albedo 0, normal 0, depth +infinity and face kNoFace.
struct AovImages {
  static constexpr uint32_t kNoFace = 0;
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> albedo; // linear rgb, a = 1 where something was hit
  std::vector<glm::vec3> normal; // world-space geometric normal (the face plane's)
  std::vector<float> depth;      // distance along the ray
  std::vector<uint32_t> face;    // index into Scene::faces + 1
};

// What the integrator needs beyond geometry and textures: renderer/cpu's classification of
// faces and materials, its light list and emitters, and the worldspawn lighting keys. The
// render command fills it from renderer/cpu's RenderScene, so both tracers light alike.
struct GlLighting {
  std::vector<uint32_t> faceFlags;     // per Scene face: renderer/cpu kFace*; empty = none
  std::vector<uint32_t> materialFlags; // per material: kMaterialGgx / kMaterialHasEmissive overrides; empty = from the images
  std::vector<GpuLight> lights;        // point lights, suns, domes
  LightGrid lightGrid;                 // renderer/cpu's lists over `lights`; no cells = built on upload
  std::vector<GpuLight> surfaceLights; // per material: its _surface template (value 0 = none); empty = none
  std::vector<GpuEmitter> emitters;    // triangles of emitting faces, cdf by area
  float emitterArea = 0.0f;
  glm::vec3 minlight{0.0f};
  float range = 0.5f;     // _range
  float scaledist = 1.0f; // _dist
  float bouncescale = 1.0f;
  int faithfulBounces = 0; // _bounce
  bool litwater = false;
  DirtSettings dirt;               // worldspawn dirt; enabled builds the faithful program with BT_FAITHFUL_DIRT
  LightKinds lightKinds;           // RenderScene::lightKinds: which faithful program the level was started with
  std::vector<uint32_t> lightmaps; // RenderScene::lightmaps packed (lighting/lightmaps.h packLightmaps); empty = none
};

// The faithful program's parts that only some levels need. Each is compiled only into the
// programs of the levels that use it, so every other level's program stays as small, as fast to
// run and as quick to compile as without it: with the bounce draw always compiled in, lq_e4m3
// (not one bounce light) drew 353 faithful samples/s on an H100 instead of 496; without the sky
// and _deviance code its wavefront shade kernel compiled ~40 ms sooner. Physical programs have
// all of them.
struct FaithfulFeatures {
  bool dirt = false;       // BT_FAITHFUL_DIRT: dirt's occlusion rays (worldspawn _dirt)
  bool bounceDraw = false; // BT_FAITHFUL_BOUNCE_DRAW: a cell's many bounce lights drawn among
  bool sky = false;        // BT_FAITHFUL_SKY: suns and sky domes, and their rays to the sky
  bool jitter = false;     // BT_FAITHFUL_JITTER: point lights' _deviance (jittered copies)
  bool operator==(const FaithfulFeatures&) const = default;
  // Both sets' parts.
  FaithfulFeatures operator|(const FaithfulFeatures& o) const {
    return {dirt || o.dirt, bounceDraw || o.bounceDraw, sky || o.sky, jitter || o.jitter};
  }
};

// What a level needs, known as soon as its lights are collected (renderer/cpu LightKinds), long
// before its preparation ends: the front ends start the compile with this. A level that bounces
// gets the bounce draw whatever its count of bounce lights, which is known only at the end (the
// draw is used only in cells that list more bounce lights than its rays, so the image is the same).
FaithfulFeatures faithfulFeatures(const LightKinds& kinds);
// What lights as uploaded need at least: dirt where it is enabled; the bounce draw where there
// are more bounce lights than the draw's rays (renderer/cpu kBounceShadowRays), as no cell can
// list more bounce lights than the level has; the sky with a sun or dome; jitter with a point
// light's _deviance. The tracer renders with this and the LightKinds' features together.
FaithfulFeatures faithfulFeatures(const DirtSettings& dirt, const std::vector<GpuLight>& lights);

// The two forms of the path tracer; both draw the same image for the same settings.
//   Megakernel: shaders/pathtrace.comp, one program that runs each path to its end, the
//               fastest, but the slowest to compile (NVIDIA: 1.2-1.8 s without its cache).
//   Wavefront:  pathtrace.comp's shade kernel and shaders/wavefront_trace.comp, two smaller
//               programs the driver compiles in parallel (shaders/wavefront.glsl), dispatched
//               by turns, one ray per path each turn: for the first images while the
//               megakernel compiles.
//   Auto:       each sample with the megakernel once the driver has it, else with the wavefront
//               kernels where TracerPrograms started them for this (never waits for the megakernel).
enum class PathTracerForm { Auto, Megakernel, Wavefront };

struct BeautySettings {
  int width = 640;
  int height = 360;
  int spp = 16;
  uint32_t seed = 0;
  bool physical = false; // --lighting physical
  int bounces = 3;       // physical mode
  PathTracerForm form = PathTracerForm::Auto;
};

// Mean linear radiance per pixel, rows top to bottom.
struct BeautyImage {
  int width = 0;
  int height = 0;
  int samples = 0;
  int wavefrontSamples = 0; // of `samples`, those the wavefront kernels drew
  std::vector<glm::vec3> beauty;
};

struct RayBenchmark {
  size_t primaryRays = 0; // per pass
  size_t bounceRays = 0;  // per pass: one for each primary ray that hit something
  int passes = 0;
  double primarySeconds = 0.0; // all passes
  double bounceSeconds = 0.0;
};

// Where the traversal reads the scene and keeps its stack (shaders/trace.glsl): Software for GL
// emulated on the CPU (Mesa's llvmpipe), Hardware for GPUs; Auto picks from GL_RENDERER, and
// BT_GL_TRACE_LAYOUT=software|hardware in the environment overrides Auto (to compare them).
enum class TraceLayout { Auto, Software, Hardware };

// The #defines every program of the tracer is built with: the texture path (Bindless or
// Arrays), the trace layout (BT_TRACE_SOFTWARE) and BT_BVH_MAX_DEPTH, the traversal stack size
// (scene/gpu_structs.h kBvhMaxDepth).
std::vector<std::string> shaderDefines(TextureMode mode, TraceLayout layout = TraceLayout::Hardware);

// The tracer's compute programs for one context and texture path. Each is built on first use,
// or started early: `brushtrace render` starts the path tracer before it imports the level, so
// the driver compiles (on its own threads, GL_KHR_parallel_shader_compile) while the level
// loads, and the viewer keeps one set across reloads of the map. The context must be current.
class TracerPrograms {
public:
  // Throws GlError for TextureMode::Bindless on a context without bindless textures.
  TracerPrograms(GlContext& context, TextureMode textures, TraceLayout layout = TraceLayout::Auto);
  ~TracerPrograms();
  TracerPrograms(const TracerPrograms&) = delete;
  TracerPrograms& operator=(const TracerPrograms&) = delete;

  TextureMode textureMode() const { return mode_; }   // Bindless or Arrays
  TraceLayout traceLayout() const { return layout_; } // Software or Hardware
  // Where programs built from now on are cached; ProgramCache::fromEnvironment(GL_VENDOR) by default.
  void setCache(ProgramCache cache) { cache_ = std::move(cache); }

  // Start building, without waiting (a no-op when started already). `features`: the faithful
  // program's optional parts the level uses (FaithfulFeatures); physical programs ignore them.
  // The path tracer's wavefront kernels start with the megakernel (queued before it) where they
  // can draw sooner: when the driver compiles on its own threads (a GPU; llvmpipe compiles at
  // the first dispatch whatever the form) and the megakernel is not in the program cache.
  void startPathTracer(bool physical, FaithfulFeatures features = {});
  // The wavefront trace kernel, where startPathTracer() would start it: it serves every
  // lighting mode and feature set, so it can start before the level says which it needs.
  void startTraceKernel();
  void startWavefront(bool physical, FaithfulFeatures features = {});
  void startAovs();
  // The finished program, built now if it was not started.
  ComputeProgram& pathTracer(bool physical, FaithfulFeatures features = {});
  ComputeProgram& wavefrontShade(bool physical, FaithfulFeatures features = {});
  ComputeProgram& wavefrontTrace();
  // Both wavefront kernels finished, the trace kernel first. NVIDIA finishes each program on
  // the thread that waits for it, after its own threads report the compile complete (H100,
  // cold: ~60 ms for the trace kernel, ~190 ms for the shade kernel, one program at a time).
  // The trace kernel's compile ends first (~150 ms, the shade kernel's ~280 ms), so waiting
  // for it first does its part while the shade kernel still compiles instead of after it.
  struct WavefrontKernels {
    ComputeProgram& shade;
    ComputeProgram& trace;
  };
  WavefrontKernels wavefront(bool physical, FaithfulFeatures features = {});
  ComputeProgram& aovs();
  ComputeProgram& rayBench();
  // Faithful mode's light compiler (shaders/bake.comp, gl_bake.h), with the level's features:
  // started, whether the driver has finished it, and finished.
  void startBake(FaithfulFeatures features);
  bool bakeReady(FaithfulFeatures features);
  ComputeProgram& bake(FaithfulFeatures features);
  // PathTracerForm::Auto's choice for the next sample: the wavefront kernels were started and
  // the megakernel is still compiling.
  bool wavefrontWhileCompiling(bool physical, FaithfulFeatures features = {});
  // Where the wavefront kernels' compile stands, without waiting. Callers with other work
  // before the first image (the import) do it on another thread and wait for these kernels
  // meanwhile with wavefront(): NVIDIA's driver does part of a compile on the thread that
  // waits for it (`brushtrace bench`, the viewer).
  struct WavefrontState {
    bool started = false;
    bool shadeReady = false;
    bool traceReady = false;
  };
  WavefrontState wavefrontState(bool physical, FaithfulFeatures features = {});

private:
  ComputeProgram& finished(std::unique_ptr<ComputeProgram>& slot);
  void start(std::unique_ptr<ComputeProgram>& slot, const char* shader, std::vector<std::string> defines, bool cached = true);
  void startWavefrontTrace();
  std::vector<std::string> pathDefines(bool physical, FaithfulFeatures features) const;
  static size_t variantIndex(bool physical, FaithfulFeatures features);
  std::unique_ptr<ComputeProgram>& pathSlot(bool physical, FaithfulFeatures features);
  std::unique_ptr<ComputeProgram>& shadeSlot(bool physical, FaithfulFeatures features);

  TextureMode mode_;
  TraceLayout layout_;
  ProgramCache cache_;
  bool wavefrontFirst_; // startPathTracer starts the wavefront kernels too (driver compiles in parallel, a GPU)
  // One program per lighting mode (BT_LIGHTING_PHYSICAL chosen at build), so each compiles
  // only its own integrator, and per set of faithful features (variantIndex: physical, then
  // faithful with each of the 16 sets); the same for the wavefront form's shade kernels. Its
  // trace kernel serves every mode.
  static constexpr size_t kPathVariants = 17;
  std::unique_ptr<ComputeProgram> path_[kPathVariants], shade_[kPathVariants], bake_[kPathVariants], trace_, aov_, rayBench_;
};

struct ProgramBuild {
  double milliseconds = 0.0; // compile and link (or load) from the start of the build, and the driver's work at the first dispatch
  bool fromCache = false;
};

class GlTracer {
public:
  // Uploads the scene: `tracer`'s BVH, brushes, sides and faces as they are (the CPU
  // reference's RenderScene::tracer, so both trace the same tree), the scene's textures and the
  // lighting. The context must stay current on this thread for the tracer's life.
  GlTracer(GlContext& context, const Scene& scene, const TraceScene& tracer, TextureMode textures, const GlLighting& lighting = {});
  // The same with programs built (or being built) already: their texture path is the tracer's.
  GlTracer(GlContext& context, const Scene& scene, const TraceScene& tracer, std::shared_ptr<TracerPrograms> programs,
           const GlLighting& lighting = {});
  // The same with a TraceScene built here with default options (every brush traceable).
  GlTracer(GlContext& context, const Scene& scene, TextureMode textures, const GlLighting& lighting = {});
  ~GlTracer();
  GlTracer(const GlTracer&) = delete;
  GlTracer& operator=(const GlTracer&) = delete;

  TextureMode textureMode() const; // the path in use: Bindless or Arrays
  // The parts of its faithful programs: the level's LightKinds' and what its lights need.
  FaithfulFeatures faithfulFeatures() const;

  // Where programs are cached; ProgramCache::fromEnvironment(GL_VENDOR) unless set before they
  // are built.
  void setProgramCache(ProgramCache cache);
  TracerPrograms& programs();
  // Builds the path tracer's program for one lighting mode (BeautySettings::physical) now, for
  // images of width x height (renderBeauty otherwise builds it on first use).
  ProgramBuild buildPathTracer(int width, int height, bool physical);
  // The same for the wavefront form's two kernels.
  ProgramBuild buildWavefront(int width, int height, bool physical);

  AovImages renderAovs(const CameraBasis& camera, int width, int height);

  // settings.spp samples per pixel, summed in an RGBA32F image: one dispatch each with the
  // megakernel, or rounds of trace and shade dispatches with the wavefront kernels (settings.form
  // picks; Auto switches to the megakernel at the first sample after its compile ends).
  // progress(n) is called after every sample with the samples done; returning false stops
  // early (--time).
  BeautyImage renderBeauty(const CameraBasis& camera, const BeautySettings& settings, const std::function<bool(int)>& progress = {});

  // One sample of a progressive render into `sum`, an RGBA32F texture of settings.width by
  // settings.height that the caller keeps across calls (settings.spp is ignored): sample
  // `sampleIndex` draws renderBeauty's stream for its sample n, so sampleIndex 0 overwrites the
  // sum (pathtrace.comp `accumulate`) and later ones add to it. Nothing is read back: the
  // viewer tonemaps the sum on the GPU (gl_progressive.h).
  void addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex);

  // Times closest-hit queries alone (shaders/raybench.comp): `passes` frames of primary rays,
  // then `passes` frames of one cosine bounce ray from each primary hit.
  RayBenchmark benchmarkRays(const CameraBasis& camera, int width, int height, int passes);
  // Replaces faithful mode's baked luxels (GlLighting::lightmaps, packed; empty for none): a bake
  // made after the upload (gl_bench, a viewer that bakes as the camera moves).
  void setLightmaps(const std::vector<uint32_t>& packed);
  // For passes of other kernels over the level (gl_bake.h): binds the world block, the scene's
  // buffers and textures as the path tracer sees them; the lightmap buffer's GL name; and its
  // whole packed content, read back (tests).
  void bindLevel();
  unsigned lightmapBuffer() const;
  std::vector<uint32_t> readLightmaps() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace bt::gl
