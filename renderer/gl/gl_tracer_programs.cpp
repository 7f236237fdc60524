#include "renderer/gl/gl_tracer_programs.h"

#include "renderer/cpu/integrator.h"
#include "renderer/gl/gl_error.h"

#include <fmt/format.h>

#include <cstdlib>
#include <string_view>

namespace bt::gl {

std::vector<std::string> shaderDefines(TextureMode mode, TraceLayout layout) {
  std::vector<std::string> defines{mode == TextureMode::Bindless ? "BT_TEXTURES_BINDLESS" : "BT_TEXTURES_ARRAYS",
                                   fmt::format("BT_BVH_MAX_DEPTH {}", kBvhMaxDepth),
                                   fmt::format("BT_TRIANGLE_EDGE_EPSILON_INVERSE {}u", kTriangleEdgeEpsilonInverse)};
  if (layout == TraceLayout::Software) defines.emplace_back("BT_TRACE_SOFTWARE");
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

void TracerPrograms::start(std::unique_ptr<ComputeProgram>& slot, const char* shader, std::vector<std::string> defines, bool cached) {
  if (slot) return;
  slot = std::make_unique<ComputeProgram>(ComputeProgram::Deferred{}, shader, defines, cached ? cache_ : ProgramCache{});
}

FaithfulFeatures faithfulFeatures(const LightKinds& kinds) {
  return {.dirt = kinds.dirt, .bounceDraw = kinds.bounce, .sky = kinds.sky, .jitter = kinds.jitter};
}

FaithfulFeatures faithfulFeatures(const DirtSettings& dirt, const std::vector<GpuLight>& lights) {
  FaithfulFeatures f{.dirt = dirt.enabled};
  size_t bounceLights = 0;
  for (const GpuLight& l : lights) {
    bounceLights += l.formula == uint32_t(LightFormula::Bounce);
    f.sky |= l.type == uint32_t(LightType::Sun) || l.type == uint32_t(LightType::Dome);
    f.jitter |= l.type == uint32_t(LightType::Point) && l.deviance > 0.0f;
  }
  f.bounceDraw = bounceLights > kBounceShadowRays;
  return f;
}

std::vector<std::string> TracerPrograms::pathDefines(bool physical, FaithfulFeatures features) const {
  std::vector<std::string> defines = shaderDefines(mode_, layout_);
  if (physical) {
    defines.emplace_back("BT_LIGHTING_PHYSICAL"); // physical mode has no dirt, no bounce lights
    return defines;
  }
  if (features.dirt) defines.emplace_back("BT_FAITHFUL_DIRT");
  if (features.bounceDraw) defines.emplace_back("BT_FAITHFUL_BOUNCE_DRAW");
  if (features.sky) defines.emplace_back("BT_FAITHFUL_SKY");
  if (features.jitter) defines.emplace_back("BT_FAITHFUL_JITTER");
  return defines;
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

// Physical mode ignores the faithful features, here and in pathDefines().
size_t TracerPrograms::variantIndex(bool physical, FaithfulFeatures features) {
  if (physical) return 0;
  return 1 + (features.dirt ? 1 : 0) + (features.bounceDraw ? 2 : 0) + (features.sky ? 4 : 0) + (features.jitter ? 8 : 0);
}
std::unique_ptr<ComputeProgram>& TracerPrograms::pathSlot(bool physical, FaithfulFeatures features) {
  return path_[variantIndex(physical, features)];
}
std::unique_ptr<ComputeProgram>& TracerPrograms::shadeSlot(bool physical, FaithfulFeatures features) {
  return shade_[variantIndex(physical, features)];
}

void TracerPrograms::startPathTracer(bool physical, FaithfulFeatures features) {
  std::unique_ptr<ComputeProgram>& slot = pathSlot(physical, features);
  if (slot) return;
  // The wavefront kernels are queued first, so that the driver's threads take them first; a
  // megakernel from the program cache needs none.
  const std::vector<std::string> defines = pathDefines(physical, features);
  if (wavefrontFirst_ && !programCached("pathtrace.comp", defines, cache_)) startWavefront(physical, features);
  start(slot, "pathtrace.comp", defines);
  if (wavefrontFirst_ && !slot->loadedFromCache()) startWavefront(physical, features); // the driver refused the cached binary
}

void TracerPrograms::startWavefront(bool physical, FaithfulFeatures features) {
  std::vector<std::string> defines = pathDefines(physical, features);
  defines.emplace_back("BT_WAVEFRONT_SHADE");
  // Not cached: a start that finds the megakernel in the cache needs no wavefront kernels, and
  // storing them would put their binaries' retrieval (NVIDIA: tenths of a second) before the
  // first image they are for.
  start(shadeSlot(physical, features), "pathtrace.comp", std::move(defines), false);
  startWavefrontTrace();
}

void TracerPrograms::startTraceKernel() {
  if (wavefrontFirst_) startWavefrontTrace();
}

// The trace kernel serves every lighting mode; not cached, as the shade kernel.
void TracerPrograms::startWavefrontTrace() {
  start(trace_, "wavefront_trace.comp", shaderDefines(mode_, layout_), false);
}

void TracerPrograms::startAovs() {
  start(aov_, "aov.comp", shaderDefines(mode_, layout_));
}

void TracerPrograms::startBake(FaithfulFeatures features) {
  start(bake_[variantIndex(false, features)], "bake.comp", pathDefines(false, features));
}

bool TracerPrograms::bakeReady(FaithfulFeatures features) {
  startBake(features);
  return bake_[variantIndex(false, features)]->ready();
}

ComputeProgram& TracerPrograms::bake(FaithfulFeatures features) {
  startBake(features);
  return finished(bake_[variantIndex(false, features)]);
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
ComputeProgram& TracerPrograms::aovs() {
  startAovs();
  return finished(aov_);
}
ComputeProgram& TracerPrograms::rayBench() {
  start(rayBench_, "raybench.comp", shaderDefines(mode_, layout_));
  return finished(rayBench_);
}

TracerPrograms::WavefrontState TracerPrograms::wavefrontState(bool physical, FaithfulFeatures features) {
  std::unique_ptr<ComputeProgram>& shade = shadeSlot(physical, features);
  if (!shade || !trace_) return {};
  return {true, shade->ready(), trace_->ready()};
}

bool TracerPrograms::wavefrontWhileCompiling(bool physical, FaithfulFeatures features) {
  const std::unique_ptr<ComputeProgram>& mega = pathSlot(physical, features);
  return shadeSlot(physical, features) && mega && !mega->ready();
}

} // namespace bt::gl
