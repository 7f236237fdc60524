#include "renderer/gl/gl_tracer.h"

#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_scene.h"
#include "renderer/gl/gl_storage_image.h"
#include "renderer/gl/gl_wavefront.h"
#include "renderer/gl/gl_structs.h"

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <optional>
#include <span>

namespace bt::gl {

namespace {

std::vector<GlMaterial> withShadingFlags(std::vector<GlMaterial> materials, const GlLighting& lighting) {
  for (size_t i = 0; i < materials.size(); ++i) {
    materials[i].opacity = i < lighting.materialOpacity.size() ? lighting.materialOpacity[i] : 1.0f;
    materials[i].liquid = i < lighting.materialLiquid.size() ? lighting.materialLiquid[i] : glm::vec4(1.0f);
  }
  if (lighting.materialFlags.empty()) return materials;
  constexpr uint32_t kShading = kMaterialGgx | kMaterialHasEmissive | kMaterialBlendAddGl | kMaterialBlendFilterGl;
  for (size_t i = 0; i < materials.size() && i < lighting.materialFlags.size(); ++i) {
    materials[i].flags &= ~kShading;
    materials[i].flags |= lighting.materialFlags[i] & kShading;
  }
  return materials;
}

GpuWorld worldBlock(const GlLighting& lighting) {
  GpuWorld w{};
  w.minlight = lighting.minlight;
  w.ambient = lighting.ambient;
  w.range = lighting.range;
  w.scaledist = lighting.scaledist;
  w.bouncescale = lighting.bouncescale;
  w.faithfulBounces = lighting.faithfulBounces;
  w.litwater = lighting.litwater ? 1u : 0u;
  w.skySize = uint32_t(lighting.sky.size);
  w.lightCount = static_cast<uint32_t>(lighting.lights.size());
  w.emitterCount = static_cast<uint32_t>(lighting.emitters.size());
  w.emitterArea = lighting.emitterArea;
  w.dirtMode = uint32_t(lighting.dirt.mode);
  w.dirtDepth = lighting.dirt.depth;
  w.dirtAngle = glm::radians(lighting.dirt.angle);
  w.dirtScale = lighting.dirt.scale;
  w.dirtGain = lighting.dirt.gain;
  w.minlightDirt = lighting.dirt.minlight ? 1u : 0u;
  w.overbrightOne = lighting.overbrightOne;
  w.luxelDisplay = lighting.luxelDisplay;
  return w;
}

// `piece` within a width x height image; throws GlError where its groups would not cover it
// exactly (kPieceAlignment).
PixelRect clippedPiece(const PixelRect& piece, int width, int height) {
  const PixelRect clipped{piece.x, piece.y, std::min(piece.width, width - piece.x), std::min(piece.height, height - piece.y)};
  const auto aligned = [](int start, int size, int edge) {
    return start % kPieceAlignment == 0 && (start + size == edge || size % kPieceAlignment == 0);
  };
  if (piece.x < 0 || piece.y < 0 || clipped.width <= 0 || clipped.height <= 0 || !aligned(clipped.x, clipped.width, width) ||
      !aligned(clipped.y, clipped.height, height))
    throw GlError(fmt::format("the piece {}x{} at ({}, {}) of a {}x{} image is empty or not aligned to {} pixels", piece.width,
                              piece.height, piece.x, piece.y, width, height, kPieceAlignment));
  return clipped;
}

// A piece's dispatch covers whole work groups: those of another size would reach into the
// next piece's pixels, which would then take the sample twice.
void checkGroupSide(ComputeProgram& program) {
  if (program.localSize(0) != kPieceAlignment || program.localSize(1) != kPieceAlignment)
    throw GlError(fmt::format("a piece of a sample needs {0}x{0} work groups; the program's are {1}x{2}", kPieceAlignment,
                              program.localSize(0), program.localSize(1)));
}

void waitAndDelete(GLsync fence) {
  // Flushes on the first call, so the fence cannot wait on commands never sent.
  while (glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000) == GL_TIMEOUT_EXPIRED) {}
  glDeleteSync(fence);
}
// The driver's binary of a program (NVIDIA's holds the machine code), written to a temporary
// name and renamed.
void writeProgramBinary(ComputeProgram& program, const std::string& path) {
  const std::vector<uint8_t> data = program.binary().data;
  if (data.empty()) throw GlError(fmt::format("the driver gave no binary of the ray benchmark for {}", path));
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data.data()), std::streamsize(data.size()));
    if (!out) throw GlError(fmt::format("cannot write {}", temporary));
  }
  std::filesystem::rename(temporary, path);
}

} // namespace

struct GlTracer::Impl {
  GlContext& context;
  std::shared_ptr<TracerPrograms> programs;
  GlTextures textures;
  GlSceneBuffers buffers;
  GpuWorld world;
  FaithfulFeatures features; // of the level: the faithful program's optional parts, and its liquid CSG
  GLuint cameraBuffer = 0;
  GLuint worldBuffer = 0;
  WavefrontBuffers wavefront;

  Impl(GlContext& c, const Scene& scene, const TraceScene& tracer, std::shared_ptr<TracerPrograms> p, const GlLighting& lighting)
      : context(c), programs(std::move(p)), textures(scene, programs->textureMode(), c.info()),
        buffers(tracer, withShadingFlags(textures.materials(), lighting), lighting, scene.materials.size()), world(worldBlock(lighting)),
        features(gl::faithfulFeatures(lighting)) {
    BT_GL(glCreateBuffers(1, &cameraBuffer));
    BT_GL(glNamedBufferStorage(cameraBuffer, sizeof(GpuCamera), nullptr, GL_DYNAMIC_STORAGE_BIT));
    BT_GL(glCreateBuffers(1, &worldBuffer));
    BT_GL(glNamedBufferStorage(worldBuffer, sizeof(GpuWorld), &world, GL_DYNAMIC_STORAGE_BIT));
  }

  ~Impl() {
    glDeleteBuffers(1, &cameraBuffer);
    glDeleteBuffers(1, &worldBuffer);
  }

  // The faithful shade kernel with the luxels' read, where the first images' has none: started
  // once they are drawn (behind them on the driver's threads), so that a bake that lands while
  // the megakernel still compiles (the viewer's) finds it compiled, or nearly, and Auto's
  // samples do not wait for the megakernel. A no-op once started.
  void startLuxelsKernel() {
    if (features.luxels) return;
    FaithfulFeatures withLuxels = features;
    withLuxels.luxels = true;
    programs->startWavefront(false, withLuxels);
  }

  // Baked faces came or went (setLightmaps): the faithful shade kernel with or without their
  // read from now on; started here too where the one without it stands in for the megakernel
  // before any sample was drawn.
  void setLuxels(bool luxels) {
    if (features.luxels == luxels) return;
    if (luxels && programs->wavefrontWhileCompiling(false, features)) startLuxelsKernel();
    features.luxels = luxels;
  }

  void setWorld(const BeautySettings& settings) {
    world.physical = settings.physical ? 1u : 0u;
    world.bounces = settings.bounces;
    world.clampIndirect = settings.clampIndirect;
    BT_GL(glNamedBufferSubData(worldBuffer, 0, sizeof world, &world));
    BT_GL(glBindBufferBase(GL_UNIFORM_BUFFER, kUniformWorld, worldBuffer));
  }

  void setCamera(const CameraBasis& basis, int width, int height, uint32_t frameIndex, uint32_t seed, uint32_t firstFrame = 0,
                 glm::ivec2 pixelOffset = {0, 0}) {
    GpuCamera camera{};
    camera.origin = basis.origin;
    camera.forward = basis.forward;
    camera.right = basis.right;
    camera.up = basis.up;
    camera.imageSize = {width, height};
    camera.frameIndex = frameIndex;
    camera.seed = seed;
    camera.firstFrame = firstFrame;
    camera.pixelOffset = pixelOffset;
    BT_GL(glNamedBufferSubData(cameraBuffer, 0, sizeof camera, &camera));
    BT_GL(glBindBufferBase(GL_UNIFORM_BUFFER, kUniformCamera, cameraBuffer));
    BT_GL(glBindBufferBase(GL_UNIFORM_BUFFER, kUniformWorld, worldBuffer));
    buffers.bind();
    textures.bind();
  }

  // Drivers may leave the real compile to the first dispatch (llvmpipe does). `dispatch` runs
  // the programs once with nothing to do (image size 0 in the camera block), which makes them
  // finish it now; returns the milliseconds it took. llvmpipe compiles a variant per bound image
  // shape (power-of-two sizes or not), so the image is the size the renders will use.
  // The time to glFinish's return, and the calls' before it (ms).
  std::pair<double, double> finishWithEmptyDispatch(int width, int height, bool physical, const std::function<void()>& dispatch) {
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    StorageImage target(GL_RGBA32F, std::max(width, 1), std::max(height, 1));
    target.bindImage(kImageAccumulation, GL_READ_WRITE);
    setWorld(BeautySettings{.physical = physical, .bounces = 0});
    setCamera(CameraBasis{}, 0, 0, 0, 0);
    dispatch();
    const auto called = Clock::now();
    BT_GL(glFinish());
    const auto ms = [&](Clock::time_point t) { return std::chrono::duration<double, std::milli>(t - start).count(); };
    return {ms(Clock::now()), ms(called)};
  }

  // Sample `sampleIndex` of `camera` into the image bound at unit 0 (sample 0 overwrites it,
  // later ones add to it), the pixels of `piece` (clipped to the image) or all of them: with the
  // wavefront kernels where settings.form asks for them, or for Auto while the megakernel still
  // compiles, else with the megakernel. True where the wavefront kernels drew it.
  // GlTracer::addSample, of the whole image or of `piece`.
  void addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex,
                 std::optional<PixelRect> piece) {
    if (settings.width <= 0 || settings.height <= 0)
      throw GlError(fmt::format("image size {}x{} is empty", settings.width, settings.height));
    BT_GL(glBindImageTexture(kImageAccumulation, sum, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F));
    setWorld(settings);
    if (settings.form == PathTracerForm::Auto) programs->startPathTracer(settings.physical, features);
    drawSample(camera, settings, sampleIndex, piece);
    // The tonemap pass and a read-back see the sum this sample wrote.
    BT_GL(glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT));
  }

  bool drawSample(const CameraBasis& camera, const BeautySettings& settings, uint32_t sampleIndex, std::optional<PixelRect> piece = {}) {
    const PixelRect rect = piece ? clippedPiece(*piece, settings.width, settings.height) : PixelRect{0, 0, settings.width, settings.height};
    setCamera(camera, settings.width, settings.height, sampleIndex, settings.seed, 0, {rect.x, rect.y});
    const bool byWavefront = settings.form == PathTracerForm::Wavefront ||
        (settings.form == PathTracerForm::Auto && programs->wavefrontWhileCompiling(settings.physical, features));
    if (byWavefront) {
      auto [shade, trace] = programs->wavefront(settings.physical, features);
      if (piece) checkGroupSide(shade), checkGroupSide(trace);
      wavefront.drawSample(shade, trace, settings.width, settings.height, rect);
      if (settings.form == PathTracerForm::Auto && !settings.physical) startLuxelsKernel();
    } else {
      if (settings.form == PathTracerForm::Auto) wavefront.release(); // the switch is for good
      ComputeProgram& program = programs->pathTracer(settings.physical, features);
      if (piece) checkGroupSide(program);
      program.dispatch2d(rect.width, rect.height);
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
bool showsLuxels(const std::vector<uint32_t>& packed) {
  const size_t faces = packed.size() > 3 ? packed[3] : 0; // packLightmaps' header: [3] the face count
  for (size_t f = 0; f < faces && 9 + 2 * f < packed.size(); ++f)
    if (packed[9 + 2 * f] > 0) return true; // the face's fragment count
  return false;
}

FaithfulFeatures faithfulFeatures(const GlLighting& lighting) {
  const LevelParts parts{.liquidCsg = !lighting.liquidCsg.empty(),
                         .blocksFromInside = !lighting.blocksFromInside.empty(),
                         .glass = !lighting.glassAlpha.empty()};
  FaithfulFeatures features = faithfulFeatures(lighting.lightKinds, parts) | faithfulFeatures(lighting.dirt, lighting.lights);
  features.luxels = showsLuxels(lighting.lightmaps);
  return features;
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
  const auto [dispatchMs, callsMs] = impl_->finishWithEmptyDispatch(width, height, physical, [&] { program.dispatch2d(1, 1); });
  return {program.buildMilliseconds() + dispatchMs, program.loadedFromCache(), dispatchMs, callsMs};
}

ProgramBuild GlTracer::buildWavefront(int width, int height, bool physical) {
  auto [shade, trace] = impl_->programs->wavefront(physical, impl_->features);
  // The per-pixel buffers are made here too.
  const auto [dispatchMs, callsMs] = impl_->finishWithEmptyDispatch(width, height, physical, [&] {
    impl_->wavefront.prepare(shade, width, height);
    impl_->wavefront.bind();
    shade.dispatch2d(1, 1);
    trace.dispatch2d(1, 1);
  });
  return {std::max(shade.buildMilliseconds(), trace.buildMilliseconds()) + dispatchMs, shade.loadedFromCache() && trace.loadedFromCache(),
          dispatchMs, callsMs};
}

AovImages GlTracer::renderAovs(const CameraBasis& camera, int width, int height) {
  if (width <= 0 || height <= 0) throw GlError(fmt::format("image size {}x{} is empty", width, height));
  StorageImage albedo(GL_RGBA32F, width, height);
  StorageImage normalDepth(GL_RGBA32F, width, height);
  StorageImage face(GL_R32UI, width, height);
  impl_->setCamera(camera, width, height, 0, 0);
  albedo.bindImage(kImageAlbedo, GL_WRITE_ONLY);
  normalDepth.bindImage(kImageNormalDepth, GL_WRITE_ONLY);
  face.bindImage(kImageFace, GL_WRITE_ONLY);
  impl_->programs->aovs(impl_->features.liquidCsg).dispatch2d(width, height);
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
  accumulation.bindImage(kImageAccumulation, GL_READ_WRITE);
  impl_->setWorld(settings);
  BeautyImage out;
  out.width = settings.width;
  out.height = settings.height;
  if (settings.form == PathTracerForm::Auto) impl_->programs->startPathTracer(settings.physical, impl_->features);
  // Thousands of samples queued without a wait made NVIDIA's driver return after 16 s at
  // 1280x720 with most of them lost (bench/README.md, session 13), so the queue is kept to two
  // batches: each fence waits for the batch before the last one, and the GPU never runs dry.
  constexpr int kSamplesPerFence = 16;
  GLsync previousBatch = nullptr;
  for (int sample = 0; sample < settings.spp; ++sample) {
    if (impl_->drawSample(camera, settings, static_cast<uint32_t>(sample))) ++out.wavefrontSamples;
    out.samples = sample + 1;
    if (progress) {
      BT_GL(glFinish()); // so the callback sees real progress and timing
      if (!progress(out.samples)) break;
    } else if (out.samples % kSamplesPerFence == 0) {
      if (previousBatch) waitAndDelete(previousBatch);
      previousBatch = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    }
  }
  if (previousBatch) waitAndDelete(previousBatch);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  const float scale = 1.0f / static_cast<float>(std::max(out.samples, 1));
  accumulation.readMapped<float>(settings.width, settings.height, GL_RGBA, GL_FLOAT, 4, [&](std::span<const float> sum) {
    out.beauty.resize(sum.size() / 4);
    out.luminanceMoment2.resize(out.beauty.size());
    for (size_t i = 0; i < out.beauty.size(); ++i) {
      out.beauty[i] = glm::vec3(sum[4 * i], sum[4 * i + 1], sum[4 * i + 2]) * scale;
      out.luminanceMoment2[i] = sum[4 * i + 3] * scale;
    }
  });
  return out;
}

void GlTracer::addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex) {
  impl_->addSample(camera, settings, sum, sampleIndex, std::nullopt);
}

void GlTracer::addSample(const CameraBasis& camera, const BeautySettings& settings, unsigned sum, uint32_t sampleIndex,
                         const PixelRect& piece) {
  impl_->addSample(camera, settings, sum, sampleIndex, piece);
}

void GlTracer::setLightmaps(const std::vector<uint32_t>& packed) {
  impl_->buffers.setLightmaps(packed);
  impl_->setLuxels(showsLuxels(packed));
}

void GlTracer::setLights(const std::vector<GpuLight>& lights, const LightGrid& grid, float scaledist) {
  impl_->buffers.setLights(lights, grid, scaledist);
}

void GlTracer::setSurfaceLights(const std::vector<GpuLight>& surfaceLights) {
  impl_->buffers.setSurfaceLights(surfaceLights);
}

void GlTracer::bindLevel() {
  impl_->setWorld(BeautySettings{.physical = false, .bounces = 0});
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

RayBenchmark GlTracer::benchmarkRays(const CameraBasis& camera, int width, int height, int passes, const RayBenchVariant& variant) {
  using Clock = std::chrono::steady_clock;
  StorageImage hits(GL_RGBA32F, width, height);
  StorageImage bounceT(GL_R32F, width, height);
  hits.bindImage(kImagePrimaryHits, GL_READ_WRITE);
  bounceT.bindImage(kImageBounceT, GL_WRITE_ONLY);
  ComputeProgram& bench = impl_->programs->rayBench();
  // A variant is timed; the plain program makes what the variant's modes start from.
  ComputeProgram* timed = &bench;
  if (!variant.defines.empty()) timed = &impl_->programs->rayBenchVariant(variant.defines);
  const bool counting = std::ranges::find(variant.defines, "BT_RB_COUNT") != variant.defines.end();
  RayBenchmark result;
  result.passes = passes;
  result.primaryRays = static_cast<size_t>(width) * height;
  GLuint counts = 0;
  if (counting) {
    BT_GL(glCreateBuffers(1, &counts));
    BT_GL(glNamedBufferStorage(counts, sizeof(result.walkCounts), nullptr, GL_DYNAMIC_STORAGE_BIT));
    // Where raybench.comp binds it, from the program: the point is named in that shader only.
    const GLuint block = glGetProgramResourceIndex(timed->id(), GL_SHADER_STORAGE_BLOCK, "RayBenchCounts");
    if (block == GL_INVALID_INDEX) throw GlError("raybench.comp with BT_RB_COUNT has no RayBenchCounts buffer");
    const GLenum property = GL_BUFFER_BINDING;
    GLint binding = 0;
    BT_GL(glGetProgramResourceiv(timed->id(), GL_SHADER_STORAGE_BLOCK, block, 1, &property, 1, nullptr, &binding));
    BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(binding), counts));
    result.counted = true;
  }

  // FNV-1a over the results' bytes (RayBenchmark::primaryHash).
  const auto fnv = [](std::span<const float> values) {
    uint64_t h = 1469598103934665603ull;
    for (float v : values) {
      uint32_t bits = 0;
      std::memcpy(&bits, &v, 4);
      for (int i = 0; i < 4; ++i) h = (h ^ ((bits >> (8 * i)) & 0xffu)) * 1099511628211ull;
    }
    return h;
  };
  auto dispatch = [&](ComputeProgram& program, int count) {
    for (int pass = 0; pass < count; ++pass) {
      impl_->setCamera(camera, width, height, static_cast<uint32_t>(pass), 0);
      program.dispatch2d(width, height);
      BT_GL(glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT));
    }
  };
  // The plain program's results of one pass (modes 0 .. last), after a variant's: the hits and
  // the bounce rays' t the next mode and the hashes read.
  auto plainResults = [&](GLuint last) {
    for (GLuint mode = 0; mode <= last; ++mode) {
      BT_GL(glProgramUniform1ui(bench.id(), 0, mode));
      BT_GL(glProgramUniform1f(bench.id(), 1, result.shadowLength));
      dispatch(bench, 1);
    }
  };
  auto run = [&](GLuint mode) {
    BT_GL(glProgramUniform1ui(timed->id(), 0, mode));
    BT_GL(glProgramUniform1f(timed->id(), 1, result.shadowLength));
    if (counting) {
      const std::array<uint32_t, 16> zero{};
      BT_GL(glNamedBufferSubData(counts, GLintptr(mode * sizeof(zero)), sizeof(zero), zero.data()));
    }
    BT_GL(glFinish());
    const auto start = Clock::now();
    dispatch(*timed, passes);
    BT_GL(glFinish());
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (timed != &bench) {
      BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
      result.variantHashes[mode] = fnv(bounceT.read<float>(width, height, GL_RED, GL_FLOAT, 1));
      plainResults(mode);
    }
    return seconds;
  };
  result.primarySeconds = run(0);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  const auto primary = hits.read<float>(width, height, GL_RGBA, GL_FLOAT, 4);
  for (size_t i = 0; i < result.primaryRays; ++i) result.bounceRays += primary[4 * i + 3] != 0.0f;
  result.primaryHash = fnv(primary);
  result.bounceSeconds = run(1);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  std::vector<float> lengths = bounceT.read<float>(width, height, GL_RED, GL_FLOAT, 1);
  result.bounceHash = fnv(lengths);
  std::erase_if(lengths, [](float t) { return !(t > 0.0f && t < 1e30f); }); // misses and pixels without a bounce ray
  if (!lengths.empty()) {
    std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
    result.shadowLength = lengths[lengths.size() / 2];
  }
  result.shadowSeconds = run(2);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  result.shadowHash = fnv(bounceT.read<float>(width, height, GL_RED, GL_FLOAT, 1));
  if (counting) {
    BT_GL(glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT));
    BT_GL(glGetNamedBufferSubData(counts, 0, sizeof(result.walkCounts), result.walkCounts.data()));
    BT_GL(glDeleteBuffers(1, &counts));
  }
  if (!variant.binaryPath.empty()) writeProgramBinary(*timed, variant.binaryPath);
  return result;
}

} // namespace bt::gl
