#include "renderer/gl/gl_wavefront.h"

#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_structs.h"
#include "renderer/gl/gl_tracer.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

namespace bt::gl {

namespace {

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

} // namespace

WavefrontBuffers::~WavefrontBuffers() {
  for (Buffer& b : buffers_) glDeleteBuffers(1, &b.id);
  glDeleteBuffers(1, &readBack_);
}

void WavefrontBuffers::prepare(ComputeProgram& shade, int width, int height) {
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

void WavefrontBuffers::release() {
  for (Buffer& b : buffers_) {
    glDeleteBuffers(1, &b.id);
    b = {};
  }
}

void WavefrontBuffers::bind() const {
  const Binding points[] = {kBindingWavefrontRays, kBindingWavefrontHits, kBindingWavefrontPaths, kBindingWavefrontEndedCount};
  for (int i = 0; i < 4; ++i) BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, points[i], buffers_[i].id));
}

void WavefrontBuffers::drawSample(ComputeProgram& shade, ComputeProgram& trace, int width, int height, const PixelRect& piece) {
  // A slot for every pixel of the image (wavefront.glsl), of which the piece's are used.
  prepare(shade, width, height);
  const size_t paths = piece.pixels();
  bind();
  clearEndedCount();
  const GLuint shadeProgram = shade.id();
  BT_GL(glProgramUniform1ui(shadeProgram, 0, 1u)); // wavefrontStart
  shade.dispatch2d(piece.width, piece.height);
  wavefrontBarrier();
  BT_GL(glProgramUniform1ui(shadeProgram, 0, 0u));
  for (int round = 1;; ++round) {
    trace.dispatch2d(piece.width, piece.height);
    wavefrontBarrier();
    shade.dispatch2d(piece.width, piece.height);
    wavefrontBarrier();
    if (round % kRoundsPerCheck != 0) continue;
    const uint32_t ended = endedCount();
    if (ended >= paths) return;
    if (round >= kWavefrontMaxRounds)
      throw GlError(fmt::format("the wavefront path tracer still has {} of {} paths live after {} rounds", paths - ended, paths, round));
  }
}

void WavefrontBuffers::clearEndedCount() const {
  const uint32_t zero = 0;
  BT_GL(glClearNamedBufferData(buffers_[3].id, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero));
}

uint32_t WavefrontBuffers::endedCount() const {
  BT_GL(glCopyNamedBufferSubData(buffers_[3].id, readBack_, 0, 0, sizeof(uint32_t)));
  uint32_t ended = 0;
  BT_GL(glGetNamedBufferSubData(readBack_, 0, sizeof ended, &ended));
  return ended;
}

size_t WavefrontBuffers::arrayStride(GLuint program, const char* member) {
  const GLuint index = glGetProgramResourceIndex(program, GL_BUFFER_VARIABLE, member);
  if (index == GL_INVALID_INDEX) throw GlError(fmt::format("the wavefront shade kernel has no buffer variable {}", member));
  const GLenum prop = GL_TOP_LEVEL_ARRAY_STRIDE;
  GLint stride = 0;
  BT_GL(glGetProgramResourceiv(program, GL_BUFFER_VARIABLE, index, 1, &prop, 1, nullptr, &stride));
  if (stride <= 0) throw GlError(fmt::format("the wavefront shade kernel's {} has no array stride", member));
  return static_cast<size_t>(stride);
}

void WavefrontBuffers::reserve(Buffer& b, size_t bytes) {
  if (b.id != 0 && b.bytes >= bytes) return;
  glDeleteBuffers(1, &b.id);
  BT_GL(glCreateBuffers(1, &b.id));
  BT_GL(glNamedBufferStorage(b.id, static_cast<GLsizeiptr>(bytes), nullptr, 0));
  b.bytes = bytes;
}

} // namespace bt::gl
