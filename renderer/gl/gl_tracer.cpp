#include "renderer/gl/gl_tracer.h"

#include "lighting/faithful_light.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_scene.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <span>
#include <string_view>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cmath>
#include <string>

namespace bt::gl {

namespace {

// An RGBA32F or R32UI image the shaders write, deleted with its owner.
class StorageImage {
public:
  StorageImage(GLenum format, int width, int height) : format_(format) {
    BT_GL(glCreateTextures(GL_TEXTURE_2D, 1, &texture_));
    BT_GL(glTextureStorage2D(texture_, 1, format, width, height));
  }
  ~StorageImage() { glDeleteTextures(1, &texture_); }
  StorageImage(const StorageImage&) = delete;
  StorageImage& operator=(const StorageImage&) = delete;

  void bindImage(GLuint unit, GLenum access) const { BT_GL(glBindImageTexture(unit, texture_, 0, GL_FALSE, 0, access, format_)); }

  // Hands `use` the image's pixels (width * height * components values of T, top row first as
  // the shaders write them), valid during the call. They come through a pixel-pack buffer that
  // the driver fills by a GPU copy and that is then mapped: NVIDIA's glGetTextureImage into
  // client memory moved a 1280x720 RGBA32F image at 0.6 GB/s (25 ms on the H100 machine, half
  // the first image's time after the compile); a buffer copy runs at bus speed.
  template <typename T, typename Use>
  void readMapped(int width, int height, GLenum pixelFormat, GLenum type, int components, const Use& use) const {
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(components);
    const GLsizeiptr bytes = static_cast<GLsizeiptr>(count * sizeof(T));
    GLuint buffer = 0;
    BT_GL(glCreateBuffers(1, &buffer));
    struct Deleter {
      GLuint id;
      ~Deleter() { glDeleteBuffers(1, &id); }
    } deleter{buffer};
    // Client storage: the driver keeps the copy in host memory, where mapping it costs nothing.
    BT_GL(glNamedBufferStorage(buffer, bytes, nullptr, GL_MAP_READ_BIT | GL_CLIENT_STORAGE_BIT));
    BT_GL(glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer));
    glGetTextureImage(texture_, 0, pixelFormat, type, static_cast<GLsizei>(bytes), nullptr); // offset 0 in the buffer
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0); // unbound before any error is thrown: other reads use client memory
    checkGlError("glGetTextureImage", __FILE__, __LINE__);
    const void* mapped = glMapNamedBufferRange(buffer, 0, bytes, GL_MAP_READ_BIT);
    if (!mapped) {
      checkGlError("glMapNamedBufferRange", __FILE__, __LINE__);
      throw GlError("glMapNamedBufferRange returned no memory for the image read back");
    }
    struct Unmapper {
      GLuint id;
      ~Unmapper() { glUnmapNamedBuffer(id); }
    } unmapper{buffer};
    use(std::span<const T>(static_cast<const T*>(mapped), count));
  }

  template <typename T> std::vector<T> read(int width, int height, GLenum pixelFormat, GLenum type, int components) const {
    std::vector<T> pixels;
    readMapped<T>(width, height, pixelFormat, type, components,
                  [&](std::span<const T> mapped) { pixels.assign(mapped.begin(), mapped.end()); });
    return pixels;
  }

private:
  GLenum format_;
  GLuint texture_ = 0;
};

// The per-pixel state of the wavefront form (shaders/wavefront.glsl): the ray each path waits
// for, its hit, the path itself, and the count of paths ended. Sized for the largest image
// drawn so far; the struct strides are the shade kernel's (std430, read from the program).
class WavefrontBuffers {
public:
  WavefrontBuffers() = default;
  ~WavefrontBuffers() {
    for (Buffer& b : buffers_) glDeleteBuffers(1, &b.id);
    glDeleteBuffers(1, &readBack_);
  }
  WavefrontBuffers(const WavefrontBuffers&) = delete;
  WavefrontBuffers& operator=(const WavefrontBuffers&) = delete;

  void prepare(ComputeProgram& shade, int width, int height) {
    const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
    const GLuint program = shade.id();
    reserve(buffers_[0], pixels * arrayStride(program, "wavefrontRays[0].origin"));
    reserve(buffers_[1], pixels * arrayStride(program, "wavefrontHits[0].t"));
    reserve(buffers_[2], pixels * arrayStride(program, "wavefrontPaths[0].rng.state"));
    reserve(buffers_[3], sizeof(uint32_t));
    // The count is read through a copy: a buffer read back directly is moved to host memory
    // by NVIDIA's driver, where every shader atomic on it would cross the bus.
    if (readBack_ == 0) {
      BT_GL(glCreateBuffers(1, &readBack_));
      BT_GL(glNamedBufferStorage(readBack_, sizeof(uint32_t), nullptr, GL_CLIENT_STORAGE_BIT));
    }
  }

  // Gives the memory back (at 1280x720 some 300 MB) once the megakernel draws.
  void release() {
    for (Buffer& b : buffers_) {
      glDeleteBuffers(1, &b.id);
      b = {};
    }
  }

  void bind() const {
    const Binding points[] = {kBindingWavefrontRays, kBindingWavefrontHits, kBindingWavefrontPaths, kBindingWavefrontEndedCount};
    for (int i = 0; i < 4; ++i) BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, points[i], buffers_[i].id));
  }

  void clearEndedCount() const {
    const uint32_t zero = 0;
    BT_GL(glClearNamedBufferData(buffers_[3].id, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero));
  }
  uint32_t endedCount() const {
    BT_GL(glCopyNamedBufferSubData(buffers_[3].id, readBack_, 0, 0, sizeof(uint32_t)));
    uint32_t ended = 0;
    BT_GL(glGetNamedBufferSubData(readBack_, 0, sizeof ended, &ended));
    return ended;
  }

private:
  struct Buffer {
    GLuint id = 0;
    size_t bytes = 0;
  };

  static size_t arrayStride(GLuint program, const char* member) {
    const GLuint index = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, member);
    if (index == GL_INVALID_INDEX) throw GlError(fmt::format("the wavefront shade kernel has no buffer variable {}", member));
    const GLenum prop = GL_TOP_LEVEL_ARRAY_STRIDE;
    GLint stride = 0;
    BT_GL(glGetProgramResourceiv(program, GL_BUFFER_VARIABLE, index, 1, &prop, 1, nullptr, &stride));
    if (stride <= 0) throw GlError(fmt::format("the wavefront shade kernel's {} has no array stride", member));
    return static_cast<size_t>(stride);
  }

  static void reserve(Buffer& b, size_t bytes) {
    if (b.id != 0 && b.bytes >= bytes) return;
    glDeleteBuffers(1, &b.id);
    BT_GL(glCreateBuffers(1, &b.id));
    BT_GL(glNamedBufferStorage(b.id, static_cast<GLsizeiptr>(bytes), nullptr, 0));
    b.bytes = bytes;
  }

  Buffer buffers_[4]; // rays, hits, paths, ended count
  GLuint readBack_ = 0;
};

// Shader writes (storage buffers, the image) visible to the next dispatch, and to the ended
// count's copy.
void wavefrontBarrier() {
  BT_GL(glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT));
}

// Each round of trace and shade moves every live path one ray on (a hidden face skipped is a
// ray too): a path ends within (bounces + 1) surfaces x (lights + dirt rays + 1) rays x
// MAX_SKIPS; far beyond that, something is wrong. The count of ended paths is read back every
// few rounds only, as each read waits for the GPU.
constexpr int kWavefrontMaxRounds = 100000;
constexpr int kRoundsPerCheck = 4;

std::vector<GpuMaterial> withShadingFlags(std::vector<GpuMaterial> materials, const GlLighting& lighting) {
  if (lighting.materialFlags.empty()) return materials;
  for (size_t i = 0; i < materials.size() && i < lighting.materialFlags.size(); ++i) {
    materials[i].flags &= ~(kMaterialGgx | kMaterialHasEmissive);
    materials[i].flags |= lighting.materialFlags[i] & (kMaterialGgx | kMaterialHasEmissive);
  }
  return materials;
}

GpuWorld worldBlock(const GlLighting& lighting) {
  GpuWorld w{};
  w.minlight = lighting.minlight;
  w.range = lighting.range;
  w.scaledist = lighting.scaledist;
  w.bouncescale = lighting.bouncescale;
  w.faithfulBounces = lighting.faithfulBounces;
  w.litwater = lighting.litwater ? 1u : 0u;
  w.lightCount = static_cast<uint32_t>(lighting.lights.size());
  w.emitterCount = static_cast<uint32_t>(lighting.emitters.size());
  w.emitterArea = lighting.emitterArea;
  w.dirtMode = uint32_t(lighting.dirt.mode);
  w.dirtDepth = lighting.dirt.depth;
  w.dirtAngle = glm::radians(lighting.dirt.angle);
  w.dirtScale = lighting.dirt.scale;
  w.dirtGain = lighting.dirt.gain;
  w.minlightDirt = lighting.dirt.minlight ? 1u : 0u;
  return w;
}

} // namespace

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

struct GlTracer::Impl {
  GlContext& context;
  std::shared_ptr<TracerPrograms> programs;
  GlTextures textures;
  GlSceneBuffers buffers;
  GpuWorld world;
  FaithfulFeatures features; // of the level: the faithful program's optional parts
  GLuint cameraBuffer = 0;
  GLuint worldBuffer = 0;
  WavefrontBuffers wavefront;

  Impl(GlContext& c, const Scene& scene, const TraceScene& tracer, std::shared_ptr<TracerPrograms> p, const GlLighting& lighting)
      : context(c), programs(std::move(p)), textures(scene, programs->textureMode(), c.info()),
        buffers(tracer, withShadingFlags(textures.materials(), lighting), lighting, scene.materials.size()), world(worldBlock(lighting)),
        features(gl::faithfulFeatures(lighting.lightKinds) | gl::faithfulFeatures(lighting.dirt, lighting.lights)) {
    BT_GL(glCreateBuffers(1, &cameraBuffer));
    BT_GL(glNamedBufferStorage(cameraBuffer, sizeof(GpuCamera), nullptr, GL_DYNAMIC_STORAGE_BIT));
    BT_GL(glCreateBuffers(1, &worldBuffer));
    BT_GL(glNamedBufferStorage(worldBuffer, sizeof(GpuWorld), &world, GL_DYNAMIC_STORAGE_BIT));
  }

  ~Impl() {
    glDeleteBuffers(1, &cameraBuffer);
    glDeleteBuffers(1, &worldBuffer);
  }

  void setWorld(bool physical, int bounces) {
    world.physical = physical ? 1u : 0u;
    world.bounces = bounces;
    BT_GL(glNamedBufferSubData(worldBuffer, 0, sizeof world, &world));
    BT_GL(glBindBufferBase(GL_UNIFORM_BUFFER, 1, worldBuffer));
  }

  void setCamera(const CameraBasis& basis, int width, int height, uint32_t frameIndex, uint32_t seed, uint32_t firstFrame = 0) {
    GpuCamera camera{};
    camera.origin = basis.origin;
    camera.forward = basis.forward;
    camera.right = basis.right;
    camera.up = basis.up;
    camera.imageSize = {width, height};
    camera.frameIndex = frameIndex;
    camera.seed = seed;
    camera.firstFrame = firstFrame;
    BT_GL(glNamedBufferSubData(cameraBuffer, 0, sizeof camera, &camera));
    BT_GL(glBindBufferBase(GL_UNIFORM_BUFFER, 0, cameraBuffer));
    BT_GL(glBindBufferBase(GL_UNIFORM_BUFFER, 1, worldBuffer));
    buffers.bind();
    textures.bind();
  }

  // Drivers may leave the real compile to the first dispatch (llvmpipe does). `dispatch` runs
  // the programs once with nothing to do (image size 0 in the camera block), which makes them
  // finish it now; returns the milliseconds it took. llvmpipe compiles a variant per bound image
  // shape (power-of-two sizes or not), so the image is the size the renders will use.
  double finishWithEmptyDispatch(int width, int height, bool physical, const std::function<void()>& dispatch) {
    const auto start = std::chrono::steady_clock::now();
    StorageImage target(GL_RGBA32F, std::max(width, 1), std::max(height, 1));
    target.bindImage(0, GL_READ_WRITE);
    setWorld(physical, 0);
    setCamera(CameraBasis{}, 0, 0, 0, 0);
    dispatch();
    BT_GL(glFinish());
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }

  // One sample with the wavefront kernels (camera set): the shade kernel starts every pixel's
  // path at the camera, then trace and shade by turns until every path has ended; each adds its
  // sample to the image as it ends.
  void wavefrontSample(ComputeProgram& shade, ComputeProgram& trace, int width, int height) {
    const size_t paths = static_cast<size_t>(width) * static_cast<size_t>(height);
    wavefront.prepare(shade, width, height);
    wavefront.bind();
    wavefront.clearEndedCount();
    const GLuint shadeProgram = shade.id();
    BT_GL(glProgramUniform1ui(shadeProgram, 0, 1u)); // wavefrontStart
    shade.dispatch2d(width, height);
    wavefrontBarrier();
    BT_GL(glProgramUniform1ui(shadeProgram, 0, 0u));
    for (int round = 1;; ++round) {
      trace.dispatch2d(width, height);
      wavefrontBarrier();
      shade.dispatch2d(width, height);
      wavefrontBarrier();
      if (round % kRoundsPerCheck != 0) continue;
      const uint32_t ended = wavefront.endedCount();
      if (ended >= paths) return;
      if (round >= kWavefrontMaxRounds)
        throw GlError(fmt::format("the wavefront path tracer still has {} of {} paths live after {} rounds", paths - ended, paths, round));
    }
  }

  // Sample `sampleIndex` of `camera` into the image bound at unit 0 (sample 0 overwrites it,
  // later ones add to it): with the wavefront kernels where settings.form asks for them, or for
  // Auto while the megakernel still compiles, else with the megakernel. True where the wavefront
  // kernels drew it.
  bool drawSample(const CameraBasis& camera, const BeautySettings& settings, uint32_t sampleIndex) {
    setCamera(camera, settings.width, settings.height, sampleIndex, settings.seed, 0);
    const bool byWavefront = settings.form == PathTracerForm::Wavefront ||
        (settings.form == PathTracerForm::Auto && programs->wavefrontWhileCompiling(settings.physical, features));
    if (byWavefront) {
      auto [shade, trace] = programs->wavefront(settings.physical, features);
      wavefrontSample(shade, trace, settings.width, settings.height);
    } else {
      if (settings.form == PathTracerForm::Auto) wavefront.release(); // the switch is for good
      programs->pathTracer(settings.physical, features).dispatch2d(settings.width, settings.height);
    }
    // Each sample reads the sum the previous one wrote.
    BT_GL(glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT));
    return byWavefront;
  }
};

GlTracer::GlTracer(GlContext& context, const Scene& scene, const TraceScene& tracer, TextureMode textures, const GlLighting& lighting)
    : GlTracer(context, scene, tracer, std::make_shared<TracerPrograms>(context, textures), lighting) {}

GlTracer::GlTracer(GlContext& context, const Scene& scene, const TraceScene& tracer, std::shared_ptr<TracerPrograms> programs,
                   const GlLighting& lighting)
    : impl_(std::make_unique<Impl>(context, scene, tracer, std::move(programs), lighting)) {}

GlTracer::GlTracer(GlContext& context, const Scene& scene, TextureMode textures, const GlLighting& lighting)
    : GlTracer(context, scene, TraceScene::build(scene), textures, lighting) {}

GlTracer::~GlTracer() = default;

TextureMode GlTracer::textureMode() const {
  return impl_->textures.mode();
}
FaithfulFeatures GlTracer::faithfulFeatures() const {
  return impl_->features;
}

void GlTracer::setProgramCache(ProgramCache cache) {
  impl_->programs->setCache(std::move(cache));
}

TracerPrograms& GlTracer::programs() {
  return *impl_->programs;
}

ProgramBuild GlTracer::buildPathTracer(int width, int height, bool physical) {
  ComputeProgram& program = impl_->programs->pathTracer(physical, impl_->features);
  const double dispatchMs = impl_->finishWithEmptyDispatch(width, height, physical, [&] { program.dispatch2d(1, 1); });
  return {program.buildMilliseconds() + dispatchMs, program.loadedFromCache()};
}

ProgramBuild GlTracer::buildWavefront(int width, int height, bool physical) {
  auto [shade, trace] = impl_->programs->wavefront(physical, impl_->features);
  // The per-pixel buffers are made here too.
  const double dispatchMs = impl_->finishWithEmptyDispatch(width, height, physical, [&] {
    impl_->wavefront.prepare(shade, width, height);
    impl_->wavefront.bind();
    shade.dispatch2d(1, 1);
    trace.dispatch2d(1, 1);
  });
  return {std::max(shade.buildMilliseconds(), trace.buildMilliseconds()) + dispatchMs, shade.loadedFromCache() && trace.loadedFromCache()};
}

AovImages GlTracer::renderAovs(const CameraBasis& camera, int width, int height) {
  if (width <= 0 || height <= 0) throw GlError(fmt::format("image size {}x{} is empty", width, height));
  StorageImage albedo(GL_RGBA32F, width, height);
  StorageImage normalDepth(GL_RGBA32F, width, height);
  StorageImage face(GL_R32UI, width, height);
  impl_->setCamera(camera, width, height, 0, 0);
  albedo.bindImage(0, GL_WRITE_ONLY);
  normalDepth.bindImage(1, GL_WRITE_ONLY);
  face.bindImage(2, GL_WRITE_ONLY);
  impl_->programs->aovs().dispatch2d(width, height);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));

  AovImages out;
  out.width = width;
  out.height = height;
  // GL's image rows go up from row 0; the shaders put the top row at y = 0 already.
  const size_t n = static_cast<size_t>(width) * height;
  albedo.readMapped<float>(width, height, GL_RGBA, GL_FLOAT, 4, [&](std::span<const float> rgba) {
    out.albedo.resize(n);
    for (size_t i = 0; i < n; ++i) out.albedo[i] = {rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2], rgba[4 * i + 3]};
  });
  normalDepth.readMapped<float>(width, height, GL_RGBA, GL_FLOAT, 4, [&](std::span<const float> nd) {
    out.normal.resize(n);
    out.depth.resize(n);
    for (size_t i = 0; i < n; ++i) {
      out.normal[i] = {nd[4 * i], nd[4 * i + 1], nd[4 * i + 2]};
      out.depth[i] = nd[4 * i + 3];
    }
  });
  out.face = face.read<uint32_t>(width, height, GL_RED_INTEGER, GL_UNSIGNED_INT, 1);
  return out;
}

BeautyImage GlTracer::renderBeauty(const CameraBasis& camera, const BeautySettings& settings, const std::function<bool(int)>& progress) {
  if (settings.width <= 0 || settings.height <= 0) throw GlError(fmt::format("image size {}x{} is empty", settings.width, settings.height));
  StorageImage accumulation(GL_RGBA32F, settings.width, settings.height);
  accumulation.bindImage(0, GL_READ_WRITE);
  impl_->setWorld(settings.physical, settings.bounces);
  BeautyImage out;
  out.width = settings.width;
  out.height = settings.height;
  if (settings.form == PathTracerForm::Auto) impl_->programs->startPathTracer(settings.physical, impl_->features);
  for (int sample = 0; sample < settings.spp; ++sample) {
    if (impl_->drawSample(camera, settings, static_cast<uint32_t>(sample))) ++out.wavefrontSamples;
    out.samples = sample + 1;
    if (progress) {
      BT_GL(glFinish()); // so the callback sees real progress and timing
      if (!progress(out.samples)) break;
    }
  }
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  const float scale = 1.0f / static_cast<float>(std::max(out.samples, 1));
  accumulation.readMapped<float>(settings.width, settings.height, GL_RGBA, GL_FLOAT, 4, [&](std::span<const float> sum) {
    out.beauty.resize(sum.size() / 4);
    for (size_t i = 0; i < out.beauty.size(); ++i) out.beauty[i] = glm::vec3(sum[4 * i], sum[4 * i + 1], sum[4 * i + 2]) * scale;
  });
  return out;
}

void GlTracer::addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex) {
  if (settings.width <= 0 || settings.height <= 0) throw GlError(fmt::format("image size {}x{} is empty", settings.width, settings.height));
  BT_GL(glBindImageTexture(0, sum, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F));
  impl_->setWorld(settings.physical, settings.bounces);
  if (settings.form == PathTracerForm::Auto) impl_->programs->startPathTracer(settings.physical, impl_->features);
  impl_->drawSample(camera, settings, sampleIndex);
  // The tonemap pass and a read-back see the sum this sample wrote.
  BT_GL(glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT));
}

CameraBasis CameraBasis::fromQuakeAngles(const glm::vec3& origin, float pitch, float yaw, float roll, int width, int height,
                                         float horizontalFovDegrees) {
  const float p = glm::radians(pitch), y = glm::radians(yaw), r = glm::radians(roll);
  const float sp = std::sin(p), cp = std::cos(p), sy = std::sin(y), cy = std::cos(y), sr = std::sin(r), cr = std::cos(r);
  const float tanHalfX = std::tan(glm::radians(horizontalFovDegrees) * 0.5f);
  const float tanHalfY = tanHalfX * static_cast<float>(height) / static_cast<float>(std::max(width, 1));
  CameraBasis c;
  c.origin = origin;
  // Quake's AngleVectors (mathlib.c): at zero angles forward = +X, right = -Y, up = +Z.
  c.forward = {cp * cy, cp * sy, -sp};
  c.right = glm::vec3(-sr * sp * cy + cr * sy, -sr * sp * sy - cr * cy, -sr * cp) * tanHalfX;
  c.up = glm::vec3(cr * sp * cy + sr * sy, cr * sp * sy - sr * cy, cr * cp) * tanHalfY;
  return c;
}

void GlTracer::setLightmaps(const std::vector<uint32_t>& packed) {
  impl_->buffers.setLightmaps(packed);
}

void GlTracer::bindLevel() {
  impl_->setWorld(false, 0);
  impl_->buffers.bind();
  impl_->textures.bind();
}

unsigned GlTracer::lightmapBuffer() const {
  return impl_->buffers.lightmapBuffer();
}

std::vector<uint32_t> GlTracer::readLightmaps() const {
  GLint64 bytes = 0;
  BT_GL(glGetNamedBufferParameteri64v(lightmapBuffer(), GL_BUFFER_SIZE, &bytes));
  std::vector<uint32_t> data(size_t(bytes) / sizeof(uint32_t));
  BT_GL(glGetNamedBufferSubData(lightmapBuffer(), 0, GLsizeiptr(data.size() * sizeof(uint32_t)), data.data()));
  return data;
}

RayBenchmark GlTracer::benchmarkRays(const CameraBasis& camera, int width, int height, int passes) {
  using Clock = std::chrono::steady_clock;
  StorageImage hits(GL_RGBA32F, width, height);
  StorageImage bounceT(GL_R32F, width, height);
  hits.bindImage(0, GL_READ_WRITE);
  bounceT.bindImage(1, GL_WRITE_ONLY);
  ComputeProgram& bench = impl_->programs->rayBench();
  const GLuint program = bench.id();
  RayBenchmark result;
  result.passes = passes;
  result.primaryRays = static_cast<size_t>(width) * height;

  auto run = [&](GLuint mode) {
    BT_GL(glProgramUniform1ui(program, 0, mode));
    BT_GL(glFinish());
    const auto start = Clock::now();
    for (int pass = 0; pass < passes; ++pass) {
      impl_->setCamera(camera, width, height, static_cast<uint32_t>(pass), 0);
      bench.dispatch2d(width, height);
      BT_GL(glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT));
    }
    BT_GL(glFinish());
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  result.primarySeconds = run(0);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  const auto primary = hits.read<float>(width, height, GL_RGBA, GL_FLOAT, 4);
  for (size_t i = 0; i < result.primaryRays; ++i) result.bounceRays += primary[4 * i + 3] != 0.0f;
  result.bounceSeconds = run(1);
  return result;
}

} // namespace bt::gl
