#include "renderer/gl/gl_tracer_programs.h"

#include "lighting/faithful.h"
#include "lighting/faithful_light.h"
#include "renderer/gl/gl_error.h"

#include <fmt/format.h>

#include <cstdlib>
#include <iterator>
#include <string_view>

namespace bt::gl {

namespace {

// shader_switches.def as tables.
struct SwitchEntry {
  std::string_view axis, define;
};
constexpr SwitchEntry kSwitches[] = {
#define BT_SWITCH(axis, define) {#axis, #define},
#define BT_PROGRAM(name, shader, axes)
#include "renderer/gl/shader_switches.def"
#undef BT_PROGRAM
#undef BT_SWITCH
};
struct ProgramEntry {
  const char* shader;
  std::string_view axes;
};
constexpr ProgramEntry kPrograms[] = {
#define BT_SWITCH(axis, define)
#define BT_PROGRAM(name, shader, axes) {#shader, #axes},
#include "renderer/gl/shader_switches.def"
#undef BT_PROGRAM
#undef BT_SWITCH
};
static_assert(std::size(kPrograms) == size_t(kTracerProgramCount));

// The switches of one axis, in the list's order.
std::vector<std::string_view> switchesOf(std::string_view axis) {
  std::vector<std::string_view> out;
  for (const SwitchEntry& s : kSwitches)
    if (s.axis == axis) out.push_back(s.define);
  return out;
}

bool takes(TracerProgram program, std::string_view axis) {
  return kPrograms[size_t(program)].axes.find(axis) != std::string_view::npos;
}

} // namespace

const char* shaderFile(TracerProgram program) {
  return kPrograms[size_t(program)].shader;
}

std::vector<std::string> shaderDefines(TextureMode mode, TraceLayout layout) {
  const std::vector<std::string_view> textures = switchesOf("Textures"); // bindless, arrays
  std::vector<std::string> defines{std::string(textures.at(mode == TextureMode::Bindless ? 0 : 1)),
                                   fmt::format("BT_BVH_MAX_DEPTH {}", kBvhMaxDepth),
                                   fmt::format("BT_TRIANGLE_EDGE_EPSILON_INVERSE {}u", kTriangleEdgeEpsilonInverse)};
  if (layout == TraceLayout::Software) defines.emplace_back(switchesOf("Layout").at(0));
  return defines;
}

std::vector<std::string> programDefines(TracerProgram program, TextureMode mode, TraceLayout layout, bool physical,
                                        FaithfulFeatures features) {
  std::vector<std::string> defines = shaderDefines(mode, layout);
  if (physical && takes(program, "Physical")) {
    defines.emplace_back(switchesOf("Physical").at(0)); // physical mode has no dirt, no bounce lights
  } else if (takes(program, "Faithful")) {
    const std::vector<std::string_view> parts = switchesOf("Faithful");
    const bool on[] = {features.dirt, features.bounceDraw, features.sky, features.jitter, features.negative, features.filter};
    if (parts.size() != std::size(on)) throw GlError("shader_switches.def: FaithfulFeatures has 6 parts");
    for (size_t i = 0; i < parts.size(); ++i)
      if (on[i]) defines.emplace_back(parts[i]);
  }
  if (takes(program, "Wavefront")) defines.emplace_back(switchesOf("Wavefront").at(0));
  if (features.liquidCsg && takes(program, "Csg")) defines.emplace_back(switchesOf("Csg").at(0));
  if (features.blocksFromInside && !physical && takes(program, "Inside")) defines.emplace_back(switchesOf("Inside").at(0));
  if (features.glass && !physical && takes(program, "Glass")) defines.emplace_back(switchesOf("Glass").at(0));
  if (!features.luxels && !physical && takes(program, "NoLuxels")) defines.emplace_back(switchesOf("NoLuxels").at(0));
  return defines;
}

namespace {

TraceLayout resolveTraceLayout(TraceLayout layout, const GlContextInfo& context) {
  if (layout != TraceLayout::Auto) return layout;
  if (const char* env = std::getenv("BT_GL_TRACE_LAYOUT")) {
    if (std::string_view(env) == "software") return TraceLayout::Software;
    if (std::string_view(env) == "hardware") return TraceLayout::Hardware;
  }
  return context.softwareRenderer ? TraceLayout::Software : TraceLayout::Hardware;
}

} // namespace

TracerPrograms::TracerPrograms(GlContext& context, TextureMode textures, TraceLayout layout)
    : mode_(resolveTextureMode(textures, context.info())), layout_(resolveTraceLayout(layout, context.info())),
      cache_(ProgramCache::fromEnvironment(context.info().vendor)),
      wavefrontFirst_(context.info().parallelShaderCompile && !context.info().softwareRenderer) {}

TracerPrograms::~TracerPrograms() = default;

void TracerPrograms::start(std::unique_ptr<ComputeProgram>& slot, const char* shader, const std::vector<std::string>& defines,
                           bool cached) {
  if (slot) return;
  start(slot, shader, sources_.assemble(shader, defines), cached);
}

void TracerPrograms::start(std::unique_ptr<ComputeProgram>& slot, const char* shader, const std::string& source, bool cached) {
  if (slot) return;
  slot = std::make_unique<ComputeProgram>(ComputeProgram::Deferred{}, shader, source, cached ? cache_ : ProgramCache{});
}

FaithfulFeatures faithfulFeatures(const LightKinds& kinds, const LevelParts& parts) {
  return {.dirt = kinds.dirt,
          .bounceDraw = kinds.bounce,
          .sky = kinds.sky,
          .jitter = kinds.jitter,
          .negative = kinds.negative,
          .filter = kinds.filter,
          .liquidCsg = parts.liquidCsg,
          .blocksFromInside = parts.blocksFromInside,
          .glass = parts.glass};
}

FaithfulFeatures faithfulFeatures(const DirtSettings& dirt, const std::vector<GpuLight>& lights) {
  FaithfulFeatures f{.dirt = dirt.enabled};
  size_t bounceLights = 0;
  for (const GpuLight& l : lights) {
    bounceLights += l.formula == uint32_t(LightFormula::Bounce);
    f.sky |= l.type == uint32_t(LightType::Sun) || l.type == uint32_t(LightType::Dome);
    f.jitter |= l.type == uint32_t(LightType::Point) && l.deviance > 0.0f;
    f.negative |= faithful::subtractedLight(l);
  }
  f.bounceDraw = bounceLights > kBounceShadowRays;
  return f;
}

ComputeProgram& TracerPrograms::finished(std::unique_ptr<ComputeProgram>& slot) {
  try {
    slot->finish();
  } catch (const GlError&) {
    slot.reset(); // the next use tries again, and reports again
    throw;
  }
  return *slot;
}

// Physical mode ignores the faithful features but the liquid CSG, here and in programDefines().
size_t TracerPrograms::variantIndex(bool physical, FaithfulFeatures features) {
  const size_t csg = features.liquidCsg ? kPathVariants / 2 : 0;
  if (physical) return csg;
  return csg + 1 + (features.dirt ? 1 : 0) + (features.bounceDraw ? 2 : 0) + (features.sky ? 4 : 0) + (features.jitter ? 8 : 0) +
      (features.negative ? 16 : 0) + (features.filter ? 32 : 0) + (features.blocksFromInside ? 64 : 0) + (features.glass ? 128 : 0);
}
std::unique_ptr<ComputeProgram>& TracerPrograms::pathSlot(bool physical, FaithfulFeatures features) {
  return path_[variantIndex(physical, features)];
}
std::unique_ptr<ComputeProgram>& TracerPrograms::shadeSlot(bool physical, FaithfulFeatures features) {
  features.blocksFromInside = false;                                             // the shade kernel traces nothing
  return shade_[!physical && features.luxels][variantIndex(physical, features)]; // physical reads no luxels
}

void TracerPrograms::startPathTracer(bool physical, FaithfulFeatures features) {
  std::unique_ptr<ComputeProgram>& slot = pathSlot(physical, features);
  if (slot) return;
  // The wavefront kernels are queued first, so that the driver's threads take them first; a
  // megakernel from the program cache needs none.
  const char* shader = shaderFile(TracerProgram::PathTracer);
  const std::string source = sources_.assemble(shader, programDefines(TracerProgram::PathTracer, mode_, layout_, physical, features));
  if (wavefrontFirst_ && !programCachedSource(shader, source, cache_)) startWavefront(physical, features);
  start(slot, shader, source);
  if (wavefrontFirst_ && !slot->loadedFromCache()) startWavefront(physical, features); // the driver refused the cached binary
}

void TracerPrograms::startWavefront(bool physical, FaithfulFeatures features) {
  const std::vector<std::string> defines = programDefines(TracerProgram::WavefrontShade, mode_, layout_, physical, features);
  // Not cached: a start that finds the megakernel in the cache needs no wavefront kernels, and
  // storing them would put their binaries' retrieval (NVIDIA: tenths of a second) before the
  // first image they are for.
  start(shadeSlot(physical, features), shaderFile(TracerProgram::WavefrontShade), defines, false);
  startWavefrontTrace();
}

void TracerPrograms::startTraceKernel() {
  if (wavefrontFirst_) startWavefrontTrace();
}

// The trace kernel serves every lighting mode; not cached, as the shade kernel.
void TracerPrograms::startWavefrontTrace() {
  start(trace_, shaderFile(TracerProgram::WavefrontTrace), programDefines(TracerProgram::WavefrontTrace, mode_, layout_), false);
}

void TracerPrograms::startAovs(bool liquidCsg) {
  start(aov_[liquidCsg], shaderFile(TracerProgram::Aovs),
        programDefines(TracerProgram::Aovs, mode_, layout_, false, FaithfulFeatures{.liquidCsg = liquidCsg}));
}

// The bake traces no surface rays: one program whatever the level's liquids.
std::unique_ptr<ComputeProgram>& TracerPrograms::bakeSlot(FaithfulFeatures features) {
  features.liquidCsg = false;
  features.glass = false; // the bake stores luxels; glass is the view's
  return bake_[variantIndex(false, features)];
}

void TracerPrograms::startBake(FaithfulFeatures features) {
  start(bakeSlot(features), shaderFile(TracerProgram::Bake), programDefines(TracerProgram::Bake, mode_, layout_, false, features));
}

bool TracerPrograms::bakeReady(FaithfulFeatures features) {
  startBake(features);
  return bakeSlot(features)->ready();
}

ComputeProgram& TracerPrograms::bake(FaithfulFeatures features) {
  startBake(features);
  return finished(bakeSlot(features));
}

ComputeProgram& TracerPrograms::pathTracer(bool physical, FaithfulFeatures features) {
  startPathTracer(physical, features);
  return finished(pathSlot(physical, features));
}
ComputeProgram& TracerPrograms::wavefrontShade(bool physical, FaithfulFeatures features) {
  startWavefront(physical, features);
  return finished(shadeSlot(physical, features));
}
ComputeProgram& TracerPrograms::wavefrontTrace() {
  startWavefrontTrace();
  return finished(trace_);
}
TracerPrograms::WavefrontKernels TracerPrograms::wavefront(bool physical, FaithfulFeatures features) {
  startWavefront(physical, features);
  ComputeProgram& trace = wavefrontTrace();
  return {wavefrontShade(physical, features), trace};
}
ComputeProgram& TracerPrograms::aovs(bool liquidCsg) {
  startAovs(liquidCsg);
  return finished(aov_[liquidCsg]);
}
ComputeProgram& TracerPrograms::rayBench() {
  start(rayBench_, shaderFile(TracerProgram::RayBench), programDefines(TracerProgram::RayBench, mode_, layout_));
  return finished(rayBench_);
}
ComputeProgram& TracerPrograms::rayBenchVariant(const std::vector<std::string>& defines) {
  std::vector<std::string> all = programDefines(TracerProgram::RayBench, mode_, layout_);
  all.emplace_back("BT_RB_VARIANT");
  all.insert(all.end(), defines.begin(), defines.end());
  if (all != rayBenchVariantDefines_) rayBenchVariant_.reset(); // one variant at a time
  rayBenchVariantDefines_ = all;
  start(rayBenchVariant_, shaderFile(TracerProgram::RayBench), all, false);
  return finished(rayBenchVariant_);
}

TracerPrograms::WavefrontState TracerPrograms::wavefrontState(bool physical, FaithfulFeatures features) {
  std::unique_ptr<ComputeProgram>& shade = shadeSlot(physical, features);
  if (!shade || !trace_) return {};
  return {true, shade->ready(), trace_->ready()};
}

TracerPrograms::Started TracerPrograms::started(bool physical, FaithfulFeatures features) {
  return {shadeSlot(physical, features).get(), trace_.get(), pathSlot(physical, features).get()};
}

bool TracerPrograms::wavefrontWhileCompiling(bool physical, FaithfulFeatures features) {
  const std::unique_ptr<ComputeProgram>& mega = pathSlot(physical, features);
  return shadeSlot(physical, features) && mega && !mega->ready();
}

} // namespace bt::gl
