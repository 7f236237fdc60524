#include "renderer/gl/gl_bake.h"

#include "lighting/faithful.h"
#include "lighting/vis_approx.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_structs.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>

namespace bt::gl {

namespace {

// Items per dispatch: a pass over a whole level is split so that no one dispatch holds the GPU
// (or llvmpipe's threads) for long.
constexpr uint32_t kItemsPerDispatch = 1u << 16;
constexpr uint32_t kGroupSize = 64;               // bake.comp: trace.glsl's 8 x 8
constexpr uint32_t kMaxGroupsPerDispatch = 65535; // GL's least GL_MAX_COMPUTE_WORK_GROUP_COUNT along x
// Passes one invocation runs in a row: up to 8 where there are samples enough to fill the GPU
// without them; fewer samples run faster one pass at a time (bench/README.md).
int passesPerDispatch(uint32_t samples) {
  return int(std::clamp<uint32_t>(samples / 32768u, 1u, 8u));
}

GLuint storage(const void* data, size_t bytes) {
  GLuint buffer = 0;
  BT_GL(glCreateBuffers(1, &buffer));
  BT_GL(glNamedBufferStorage(buffer, GLsizeiptr(std::max<size_t>(bytes, 16)), data, data ? 0 : GL_DYNAMIC_STORAGE_BIT));
  return buffer;
}

} // namespace

GlLightmapBake::GlLightmapBake(GlTracer& tracer, const LuxelBakeJob& job)
    : tracer_(tracer), features_(tracer.faithfulFeatures()), sampleCount_(uint32_t(job.samples.size())),
      luxelCount_(uint32_t(job.samples.size() / std::max(job.samplesPerLuxel, 1u))), samplesPerLuxel_(std::max(job.samplesPerLuxel, 1u)),
      softSamples_(job.softSamples), passes_(job.passes), seed_(job.seed) {
  samples_ = storage(job.samples.empty() ? nullptr : job.samples.data(), job.samples.size() * sizeof(GpuLuxelSample));
  sums_ = storage(nullptr, size_t(sampleCount_) * 4 * sizeof(glm::vec4));
  std::vector<glm::vec4> dome;
  for (const glm::vec3& d : faithful::skyDomeDirections()) dome.emplace_back(d, 0.0f);
  domeSuns_ = int(dome.size());
  for (const glm::vec3& d : job.sunTable) dome.emplace_back(d, 0.0f);
  // Then the visapprox boxes (lighting/vis_approx.h), two rows each: the lights', the compiled faces'.
  // Where the job has no boxes for its lights, the rows hold each light's origin until the first
  // run() computes the boxes over them, from the ray directions after the faces' boxes: the level's
  // preparation leaves the 1,024 rays a light to the GPU (RenderSceneOptions::VisBoxes::Gpu).
  lightBoxes_ = int(dome.size());
  lightBoxCount_ = uint32_t(job.boxedLights.size());
  if (job.lightBoxes.size() == job.boxedLights.size()) {
    for (const GpuVisBox& b : job.lightBoxes) dome.push_back(b.mins), dome.push_back(b.maxs);
  } else {
    for (const glm::vec3& origin : job.boxedLights) dome.emplace_back(origin, 0.0f), dome.emplace_back(origin, 0.0f);
    boxesToCompute_ = lightBoxCount_;
  }
  receiverBoxes_ = job.receiverBoxes.empty() ? -1 : int(dome.size());
  for (const GpuVisBox& b : job.receiverBoxes) dome.push_back(b.mins), dome.push_back(b.maxs);
  visRays_ = int(dome.size());
  if (boxesToCompute_ > 0)
    for (const glm::vec3& d : visRayDirections()) dome.emplace_back(d, 0.0f);
  dome_ = storage(dome.data(), dome.size() * sizeof(glm::vec4));
  tracer_.programs().bake(features_); // built now, not in the middle of the first pass
}

GlLightmapBake::~GlLightmapBake() {
  const GLuint buffers[] = {samples_, sums_, dome_};
  glDeleteBuffers(3, buffers);
}

void GlLightmapBake::dispatch(int firstPass, int passCount, uint32_t items) {
  ComputeProgram& program = tracer_.programs().bake(features_);
  const GLuint id = program.id();
  BT_GL(glProgramUniform1i(id, 2, firstPass));
  BT_GL(glProgramUniform1i(id, 7, passCount));
  BT_GL(glProgramUniform1i(id, 3, done_));
  BT_GL(glProgramUniform1i(id, 4, softSamples_));
  BT_GL(glProgramUniform1ui(id, 5, samplesPerLuxel_));
  BT_GL(glProgramUniform1ui(id, 6, seed_));
  BT_GL(glProgramUniform1i(id, 8, domeSuns_));
  BT_GL(glProgramUniform1i(id, 9, lightBoxes_));
  BT_GL(glProgramUniform1i(id, 10, receiverBoxes_));
  BT_GL(glProgramUniform1i(id, 11, visRays_));
  if (firstPass == BT_BAKE_VIS_BOX_PASS) { // one workgroup per box
    for (uint32_t first = 0; first < items; first += kMaxGroupsPerDispatch) {
      const uint32_t count = std::min(kMaxGroupsPerDispatch, items - first);
      BT_GL(glProgramUniform1ui(id, 0, first));
      BT_GL(glProgramUniform1ui(id, 1, count));
      program.dispatch2d(int(count * 8), 8);
    }
    BT_GL(glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT));
    return;
  }
  for (uint32_t first = 0; first < items; first += kItemsPerDispatch) {
    const uint32_t count = std::min(kItemsPerDispatch, items - first);
    BT_GL(glProgramUniform1ui(id, 0, first));
    BT_GL(glProgramUniform1ui(id, 1, count));
    const uint32_t groups = (count + kGroupSize - 1) / kGroupSize;
    program.dispatch2d(int(groups * 8), 8); // a row of 8 x 8 groups
  }
  BT_GL(glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT));
}

void GlLightmapBake::bind() {
  tracer_.bindLevel();
  BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingBakeSamples, samples_));
  BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingBakeSums, sums_));
  BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingBakeSkyDome, dome_));
  BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBindingLightmaps, tracer_.lightmapBuffer()));
}

void GlLightmapBake::computeLightBoxes() {
  if (boxesToCompute_ == 0) return;
  dispatch(BT_BAKE_VIS_BOX_PASS, 0, boxesToCompute_);
  boxesToCompute_ = 0;
}

std::vector<GpuVisBox> GlLightmapBake::lightBoxes() {
  bind();
  computeLightBoxes();
  std::vector<GpuVisBox> boxes(lightBoxCount_);
  BT_GL(glGetNamedBufferSubData(dome_, GLintptr(size_t(lightBoxes_) * sizeof(glm::vec4)), GLsizeiptr(boxes.size() * sizeof(GpuVisBox)),
                                boxes.data()));
  return boxes;
}

void GlLightmapBake::run(int passes) {
  if (sampleCount_ == 0) {
    done_ = passes_;
    return;
  }
  bind();
  computeLightBoxes(); // before the first pass reads them
  // Pass 0 (every fixed light) alone, then the rest several at once: each invocation then loads
  // its sample and sums once for all of them.
  const int last = std::min(passes_, done_ + std::max(passes, 1));
  while (done_ < last) {
    const int count = done_ == 0 ? 1 : std::min(passesPerDispatch(sampleCount_), last - done_);
    dispatch(done_, count, sampleCount_);
    done_ += count;
  }
  dispatch(-1, 0, luxelCount_); // the resolve: the luxels of the passes done
}

void GlLightmapBake::finish() {
  run(passes_ - done_);
  BT_GL(glFinish());
}

ProgressiveLevelBake::ProgressiveLevelBake(const RenderScene& rs, LightmapBakeOptions options)
    : worker_(std::async(std::launch::async, [&rs, options] {
        Work w;
        w.layout = layoutLightmaps(rs, options.threads);
        w.job = luxelBakeJob(rs, w.layout, options);
        return w;
      })) {}

ProgressiveLevelBake::~ProgressiveLevelBake() {
  if (worker_.valid()) worker_.wait();
}

bool ProgressiveLevelBake::step(GlTracer& tracer, double milliseconds) {
  if (!bake_) {
    // The program compiles on the driver's threads meanwhile (seconds on a GPU from cold).
    if (!tracer.programs().bakeReady(tracer.faithfulFeatures())) return false;
    if (!worker_.valid() || worker_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
    const Work work = worker_.get();
    if (work.layout.empty()) return false; // nothing to bake: the level stays lit at each point
    tracer.setLightmaps(packLightmaps(work.layout));
    bake_ = std::make_unique<GlLightmapBake>(tracer, work.job);
    passes_ = work.job.passes;
  }
  if (bake_->done()) return false;
  const auto start = std::chrono::steady_clock::now();
  do {
    bake_->run(1);
    BT_GL(glFinish()); // to know what the pass cost
  } while (!bake_->done() && std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() < milliseconds);
  return true;
}

} // namespace bt::gl
