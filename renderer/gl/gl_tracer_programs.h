// The tracer's compute programs: which variants exist (lighting mode, faithful features, texture
// path, trace layout), the #defines each is built with, and when each is started and finished.
#pragma once

#include "lighting/lights.h"
#include "lighting/render_scene.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_program_cache.h"
#include "renderer/gl/gl_textures.h"
#include "scene/gpu_structs.h"

#include <memory>
#include <string>
#include <vector>

namespace bt::gl {

// The faithful program's parts that only some levels need. Each is compiled only into the
// programs of the levels that use it, so every other level's program stays as small, as fast to
// run and as quick to compile as without it (the bounce draw compiled into every program cost a
// level without bounce lights nearly a third of its faithful samples/s: bench/README.md).
// Physical programs have all of them.
struct FaithfulFeatures {
  bool dirt = false;       // BT_FAITHFUL_DIRT: dirt's occlusion rays (worldspawn _dirt)
  bool bounceDraw = false; // BT_FAITHFUL_BOUNCE_DRAW: a cell's many bounce lights drawn among
  bool sky = false;        // BT_FAITHFUL_SKY: suns and sky domes, and their rays to the sky
  bool jitter = false;     // BT_FAITHFUL_JITTER: point lights' _deviance (jittered copies)
  bool negative = false;   // BT_FAITHFUL_NEGATIVE: negative lights, taken off after the floors
  bool filter = false;     // BT_FAITHFUL_FILTER: Quake 3 blendFunc filter surfaces, which tint what lies behind them
  // BT_LIQUID_CSG: qbsp's CSG of overlapping liquids (lighting/liquid_csg.h), in the surface rays
  // of both lighting modes and the AOVs: the one part physical programs take too. Known from the
  // level's brushes (LevelParts), before it is prepared.
  bool liquidCsg = false;
  // BT_BLOCKS_FROM_INSIDE: faithful shadow rays leaving a brush of RenderScene::blocksFromInside
  // are blocked (shaders/trace.glsl), in the faithful path tracer and the bake; known, as the
  // liquid CSG, from the level's brushes.
  bool blocksFromInside = false;
  // BT_QUAKE2_GLASS: Quake 2's glass drawn as ref_gl draws it (lighting/game_rules.h
  // engineGlassAlpha): unlit, blended at its alpha (GpuFace::pad) over what lies behind, in the
  // faithful path tracer and its shade kernel; known, as the liquid CSG, from the level's faces.
  bool glass = false;
  // A baked face's luxels read (shaders/lightmaps.glsl), in the faithful wavefront shade kernel:
  // a level with no baked face (a .map before its bake) has its first image drawn by a kernel
  // without it (BT_NO_LUXELS), whose loops took a quarter to a half of NVIDIA's part of that
  // kernel's compile (bench/README.md, session 27). Known from the luxels uploaded
  // (GlLighting::lightmaps, GlTracer::setLightmaps), not from the level's parts; the megakernel
  // always reads them.
  bool luxels = false;
  bool operator==(const FaithfulFeatures&) const = default;
  // Both sets' parts.
  FaithfulFeatures operator|(const FaithfulFeatures& o) const {
    return {dirt || o.dirt,
            bounceDraw || o.bounceDraw,
            sky || o.sky,
            jitter || o.jitter,
            negative || o.negative,
            filter || o.filter,
            liquidCsg || o.liquidCsg,
            blocksFromInside || o.blocksFromInside,
            glass || o.glass,
            luxels || o.luxels};
  }
};

// What a level needs, known as soon as its lights are collected and its parts found
// (lighting/lights.h LightKinds, lighting/render_scene.h LevelParts), long before its
// preparation ends: the front ends start the compile with this. A level that bounces
// gets the bounce draw whatever its count of bounce lights, which is known only at the end (the
// draw is used only in cells that list more bounce lights than its rays, so the image is the same).
FaithfulFeatures faithfulFeatures(const LightKinds& kinds, const LevelParts& parts);
// What lights as uploaded need at least: dirt where it is enabled; the bounce draw where there
// are more bounce lights than the draw's rays (lighting/faithful_light.h kBounceShadowRays), as no cell can
// list more bounce lights than the level has; the sky with a sun or dome; jitter with a point
// light's _deviance; negative with a light that faithful::subtractedLight takes off after the floors. The tracer renders with this and the LightKinds' features together.
FaithfulFeatures faithfulFeatures(const DirtSettings& dirt, const std::vector<GpuLight>& lights);

// The two forms of the path tracer; both draw the same image for the same settings.
//   Megakernel: shaders/pathtrace.comp, one program that runs each path to its end, the
//               fastest, but the slowest to compile (seconds on NVIDIA without its cache).
//   Wavefront:  pathtrace.comp's shade kernel and shaders/wavefront_trace.comp, two smaller
//               programs the driver compiles in parallel (shaders/wavefront.glsl), dispatched
//               by turns, one ray per path each turn: for the first images while the
//               megakernel compiles.
//   Auto:       each sample with the megakernel once the driver has it, else with the wavefront
//               kernels where TracerPrograms started them for this (never waits for the megakernel).
enum class PathTracerForm { Auto, Megakernel, Wavefront };

// Where the traversal reads the scene and keeps its stack (shaders/trace.glsl): Software for GL
// emulated on the CPU (Mesa's llvmpipe), Hardware for GPUs; Auto picks from GL_RENDERER, and
// BT_GL_TRACE_LAYOUT=software|hardware in the environment overrides Auto (to compare them).
enum class TraceLayout { Auto, Software, Hardware };

// The #defines every program of the tracer is built with: the texture path (Bindless or
// Arrays), the trace layout (BT_TRACE_SOFTWARE) and BT_BVH_MAX_DEPTH, the traversal stack size
// (scene/gpu_structs.h kBvhMaxDepth).
std::vector<std::string> shaderDefines(TextureMode mode, TraceLayout layout = TraceLayout::Hardware);

// The programs TracerPrograms builds (shader_switches.def BT_PROGRAM), in the list's order.
enum class TracerProgram {
#define BT_SWITCH(axis, define)
#define BT_PROGRAM(name, shader, axes) name,
#include "renderer/gl/shader_switches.def"
#undef BT_PROGRAM
#undef BT_SWITCH
};
inline constexpr int kTracerProgramCount = 0
#define BT_SWITCH(axis, define)
#define BT_PROGRAM(name, shader, axes) +1
#include "renderer/gl/shader_switches.def"
#undef BT_PROGRAM
#undef BT_SWITCH
    ;
const char* shaderFile(TracerProgram program); // "pathtrace.comp", ...

// The #defines `program` is built with: shaderDefines(), then, from shader_switches.def, the
// lighting mode and faithful mode's optional parts where the program takes them (a physical
// program ignores `features` but liquidCsg), the wavefront form's switch, the liquid CSG's and,
// in faithful programs, the rule from inside, the glass and, in the faithful shade kernel, the
// luxels' read left out (BT_NO_LUXELS) where `features` has no luxels.
std::vector<std::string> programDefines(TracerProgram program, TextureMode mode, TraceLayout layout, bool physical = false,
                                        FaithfulFeatures features = {});

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
  void startAovs(bool liquidCsg = false);
  // The finished program, built now if it was not started.
  ComputeProgram& pathTracer(bool physical, FaithfulFeatures features = {});
  ComputeProgram& wavefrontShade(bool physical, FaithfulFeatures features = {});
  ComputeProgram& wavefrontTrace();
  // Both wavefront kernels finished, the trace kernel first. NVIDIA finishes each program on
  // the thread that waits for it, after its own threads report the compile complete, one
  // program at a time. The trace kernel's compile ends first, so waiting for it first does its
  // part while the shade kernel still compiles instead of after it.
  struct WavefrontKernels {
    ComputeProgram& shade;
    ComputeProgram& trace;
  };
  WavefrontKernels wavefront(bool physical, FaithfulFeatures features = {});
  ComputeProgram& aovs(bool liquidCsg = false);
  ComputeProgram& rayBench();
  // raybench.comp with measurement switches added (RayBenchVariant), built on the first call.
  ComputeProgram& rayBenchVariant(const std::vector<std::string>& defines);
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
  // The programs of the first images as started (nullptr where not), for a timeline; no wait.
  struct Started {
    const ComputeProgram* shade = nullptr;
    const ComputeProgram* trace = nullptr;
    const ComputeProgram* megakernel = nullptr;
  };
  Started started(bool physical, FaithfulFeatures features = {});

private:
  ComputeProgram& finished(std::unique_ptr<ComputeProgram>& slot);
  void start(std::unique_ptr<ComputeProgram>& slot, const char* shader, const std::vector<std::string>& defines, bool cached = true);
  void start(std::unique_ptr<ComputeProgram>& slot, const char* shader, const std::string& source, bool cached = true);
  void startWavefrontTrace();
  static size_t variantIndex(bool physical, FaithfulFeatures features);
  std::unique_ptr<ComputeProgram>& pathSlot(bool physical, FaithfulFeatures features);
  std::unique_ptr<ComputeProgram>& shadeSlot(bool physical, FaithfulFeatures features);
  std::unique_ptr<ComputeProgram>& bakeSlot(FaithfulFeatures features);

  TextureMode mode_;
  TraceLayout layout_;
  ProgramCache cache_;
  ShaderSources sources_;
  bool wavefrontFirst_; // startPathTracer starts the wavefront kernels too (driver compiles in parallel, a GPU)
  // One program per lighting mode (BT_LIGHTING_PHYSICAL chosen at build), so each compiles
  // only its own integrator, and per set of faithful features (variantIndex: physical, then
  // faithful with each of the 64 sets without and with the rule from inside and Quake 2's glass,
  // each without and with the liquid CSG); the same for the wavefront form's shade kernels,
  // which trace nothing (the rule from inside is the trace kernel's). Its trace kernel serves
  // every mode and level; the bake takes no CSG and no glass (it stores luxels, not the view).
  // Faithful shade kernels come without and with the luxels' read (shade_[luxels]).
  static constexpr size_t kPathVariants = 514;
  std::unique_ptr<ComputeProgram> path_[kPathVariants], shade_[2][kPathVariants], bake_[kPathVariants], trace_, aov_[2], rayBench_,
      rayBenchVariant_;
  std::vector<std::string> rayBenchVariantDefines_; // rayBenchVariant_'s
};

} // namespace bt::gl
