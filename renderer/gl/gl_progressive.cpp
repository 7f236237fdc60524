#include "renderer/gl/gl_progressive.h"

#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_structs.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <cmath>

namespace bt::gl {

// tonemap.comp's `tonemap` uniform takes the enum's values as they are.
static_assert(static_cast<unsigned>(Tonemap::Faithful) == 0 && static_cast<unsigned>(Tonemap::Aces) == 1 &&
              static_cast<unsigned>(Tonemap::Agx) == 2 && static_cast<unsigned>(Tonemap::Linear) == 3);

GlTexture2D::GlTexture2D(unsigned internalFormat, int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw GlError(fmt::format("image size {}x{} is empty", width, height));
  BT_GL(glCreateTextures(GL_TEXTURE_2D, 1, &texture_));
  BT_GL(glTextureStorage2D(texture_, 1, internalFormat, width, height));
  // Drawn scaled to the window by the viewer's overlay.
  BT_GL(glTextureParameteri(texture_, GL_TEXTURE_MIN_FILTER, GL_LINEAR));
  BT_GL(glTextureParameteri(texture_, GL_TEXTURE_MAG_FILTER, GL_LINEAR));
}

GlTexture2D::~GlTexture2D() {
  glDeleteTextures(1, &texture_);
}

ProgressiveImage::ProgressiveImage(int width, int height) : sum_(GL_RGBA32F, width, height) {}

void ProgressiveImage::addSample(GlTracer& tracer, const CameraBasis& camera, const BeautySettings& settings) {
  BeautySettings one = settings;
  one.width = width();
  one.height = height();
  one.spp = 1;
  tracer.addSample(camera, one, sum_.id(), static_cast<uint32_t>(samples_));
  ++samples_;
}

std::vector<glm::vec3> ProgressiveImage::readMean() const {
  const size_t n = static_cast<size_t>(width()) * static_cast<size_t>(height());
  std::vector<glm::vec3> mean(n, glm::vec3(0.0f));
  if (samples_ == 0) return mean;
  std::vector<float> rgba(n * 4);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  BT_GL(glPixelStorei(GL_PACK_ALIGNMENT, 4));
  BT_GL(glGetTextureImage(sum_.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * sizeof(float)), rgba.data()));
  const float scale = 1.0f / static_cast<float>(samples_);
  for (size_t i = 0; i < n; ++i) mean[i] = glm::vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]) * scale;
  return mean;
}

TonemapPass::TonemapPass() : program_("tonemap.comp", {}) {}

void TonemapPass::run(const GlTexture2D& sum, int samples, const GlTexture2D& display, Tonemap tonemap, float exposureEv) {
  if (sum.width() != display.width() || sum.height() != display.height())
    throw GlError(
        fmt::format("tonemap: a {}x{} sum onto a {}x{} display image", sum.width(), sum.height(), display.width(), display.height()));
  const GLuint program = program_.id();
  const float scale = std::exp2(exposureEv) / static_cast<float>(std::max(samples, 1));
  BT_GL(glProgramUniform1f(program, 0, scale));
  BT_GL(glProgramUniform1ui(program, 1, static_cast<GLuint>(tonemap)));
  BT_GL(glBindImageTexture(kImageAccumulation, sum.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(kImageDisplay, display.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8));
  program_.dispatch2d(display.width(), display.height());
  // The overlay samples the display image; readRgba8 reads it back.
  BT_GL(glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT));
}

std::vector<uint8_t> readRgba8(const GlTexture2D& texture) {
  std::vector<uint8_t> rgba(static_cast<size_t>(texture.width()) * static_cast<size_t>(texture.height()) * 4);
  BT_GL(glPixelStorei(GL_PACK_ALIGNMENT, 4));
  BT_GL(glGetTextureImage(texture.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(rgba.size()), rgba.data()));
  return rgba;
}

} // namespace bt::gl
