#include "renderer/gl/gl_denoise.h"

#include "renderer/gl/gl_error.h"
#include "shaders/denoise_constants.glsl"
#include "shaders/gl_bindings.glsl"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <cmath>

namespace bt::gl {

namespace {

void upload(const GlTexture2D& texture, const std::vector<float>& rgba) {
  BT_GL(glPixelStorei(GL_UNPACK_ALIGNMENT, 4));
  BT_GL(glTextureSubImage2D(texture.id(), 0, 0, 0, texture.width(), texture.height(), GL_RGBA, GL_FLOAT, rgba.data()));
}

} // namespace

DenoisePass::DenoisePass() : program_("denoise.comp", {}) {}

DenoisePass::Images::Images(int width, int height)
    : sum(GL_RGBA32F, width, height), albedo(GL_RGBA32F, width, height), normalDepth(GL_RGBA32F, width, height),
      out(GL_RGBA32F, width, height), scratch(GL_RGBA32F, width, height) {}

const DenoisePass::Images& DenoisePass::imagesOfSize(int width, int height) {
  if (!images_ || images_->sum.width() != width || images_->sum.height() != height) {
    images_.reset(); // the old five freed before the new five are made
    images_ = std::make_unique<Images>(width, height);
  }
  return *images_;
}

void DenoisePass::run(const GlTexture2D& beauty, float scale, int samples, bool hasMoment2, const GlTexture2D& albedo,
                      const GlTexture2D& normalDepth, const GlTexture2D& out, const GlTexture2D& scratch) {
  for (const GlTexture2D* t : {&albedo, &normalDepth, &out, &scratch})
    if (t->width() != beauty.width() || t->height() != beauty.height())
      throw GlError(fmt::format("denoise: a {}x{} image beside a {}x{} beauty", t->width(), t->height(), beauty.width(), beauty.height()));
  const GLuint program = program_.id();
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_ALBEDO, albedo.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_NORMAL_DEPTH, normalDepth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  samples = std::max(samples, 1);
  BT_GL(glProgramUniform1i(program, 1, samples));
  BT_GL(glProgramUniform1i(program, 5, hasMoment2 && samples >= BT_DENOISE_TEMPORAL_VARIANCE_FROM));
  BT_GL(glProgramUniform1f(program, 6, scale));
  BT_GL(glProgramUniform1i(program, 7, hasMoment2 && samples >= BT_DENOISE_SHRINK_FROM));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_RAW, beauty.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  // Step 0 prepares, steps 1.. filter (pass = step - 1); they alternate between the two images
  // so that the last one writes `out`.
  for (int step = 0; step <= BT_DENOISE_PASSES; ++step) {
    const bool intoOut = (BT_DENOISE_PASSES - step) % 2 == 0;
    const GlTexture2D& input = step == 0 ? beauty : intoOut ? scratch : out;
    BT_GL(glProgramUniform1i(program, 0, step == 0 ? 1 : 1 << (step - 1)));
    BT_GL(glProgramUniform1f(program, 2, step == 0 ? scale : 1.0f));
    BT_GL(glProgramUniform1i(program, 3, step == 0));
    BT_GL(glProgramUniform1i(program, 4, step == BT_DENOISE_PASSES));
    BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_IN, input.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
    BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_OUT, (intoOut ? out : scratch).id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F));
    program_.dispatch2d(beauty.width(), beauty.height());
    BT_GL(glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT));
  }
}

std::vector<glm::vec3> denoiseWithGl(const RenderImage& image) {
  DenoisePass pass;
  return denoiseWithGl(image, pass);
}

std::vector<glm::vec3> denoiseWithGl(const RenderImage& image, DenoisePass& pass) {
  const int width = image.width, height = image.height;
  const size_t n = size_t(width) * size_t(height);
  std::vector<float> beauty(n * 4), albedo(n * 4), normalDepth(n * 4);
  const bool hasMoment2 = image.luminanceMoment2.size() == n;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      beauty[i * 4 + c] = image.beauty[i][c];
      albedo[i * 4 + c] = image.albedo[i][c];
      normalDepth[i * 4 + c] = image.normal[i][c];
    }
    normalDepth[i * 4 + 3] = image.depth[i];
    if (hasMoment2) beauty[i * 4 + 3] = image.luminanceMoment2[i];
  }
  const DenoisePass::Images& images = pass.imagesOfSize(width, height);
  upload(images.sum, beauty);
  upload(images.albedo, albedo);
  upload(images.normalDepth, normalDepth);
  pass.run(images.sum, 1.0f, image.samples, hasMoment2, images.albedo, images.normalDepth, images.out, images.scratch);
  std::vector<float> rgba(n * 4);
  BT_GL(glPixelStorei(GL_PACK_ALIGNMENT, 4));
  BT_GL(glGetTextureImage(images.out.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * sizeof(float)), rgba.data()));
  std::vector<glm::vec3> result(n);
  for (size_t i = 0; i < n; ++i) result[i] = {rgba[i * 4], rgba[i * 4 + 1], rgba[i * 4 + 2]};
  return result;
}

} // namespace bt::gl
