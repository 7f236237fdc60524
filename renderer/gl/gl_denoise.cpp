#include "renderer/gl/gl_denoise.h"

#include "renderer/denoise.h"
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

// A mean and its second moment as RGBA (a 0 without the moment).
std::vector<float> interleaved(const std::vector<glm::vec3>& mean, const std::vector<float>* moment2) {
  std::vector<float> rgba(mean.size() * 4, 0.0f);
  for (size_t i = 0; i < mean.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = mean[i][c];
    if (moment2) rgba[i * 4 + 3] = (*moment2)[i];
  }
  return rgba;
}

} // namespace

DenoisePass::DenoisePass() : program_("denoise.comp", {}) {}

void DenoisePass::run(const GlTexture2D& beauty, float scale, int samples, bool hasMoment2, const GlTexture2D& albedo,
                      const GlTexture2D& normalDepth, const GlTexture2D& out, const GlTexture2D& scratch) {
  checkSizes(beauty, {&albedo, &normalDepth, &out, &scratch});
  bindGuide(albedo, normalDepth);
  samples = std::max(samples, 1);
  filter({beauty, scale, samples}, hasMoment2, hasMoment2 && samples >= BT_DENOISE_SHRINK_FROM, out, scratch);
}

void DenoisePass::runHalves(const Sum& whole, const Sum& even, const Sum& odd, const GlTexture2D& albedo, const GlTexture2D& normalDepth,
                            const Halves& images) {
  checkSizes(whole.image,
             {&even.image, &odd.image, &albedo, &normalDepth, &images.whole, &images.even, &images.odd, &images.scratch, &images.out});
  bindGuide(albedo, normalDepth);
  filter(whole, true, false, images.whole, images.scratch);
  filter(even, true, false, images.even, images.scratch);
  filter(odd, true, false, images.odd, images.scratch);
  const GLuint program = program_.id();
  // The error step: each pixel's estimate into scratch.r.
  BT_GL(glProgramUniform1i(program, 8, 1));
  BT_GL(glProgramUniform1i(program, 1, even.samples));
  BT_GL(glProgramUniform1f(program, 6, even.scale));
  BT_GL(glProgramUniform1i(program, 9, odd.samples));
  BT_GL(glProgramUniform1f(program, 10, odd.scale));
  bindImages(images.even, images.scratch, even.image, images.odd, odd.image);
  program_.dispatch2d(whole.image.width(), whole.image.height());
  BT_GL(glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT));
  // The blend.
  BT_GL(glProgramUniform1i(program, 8, 2));
  BT_GL(glProgramUniform1i(program, 1, whole.samples));
  BT_GL(glProgramUniform1f(program, 6, whole.scale));
  bindImages(images.scratch, images.out, whole.image, images.whole, whole.image);
  program_.dispatch2d(whole.image.width(), whole.image.height());
  BT_GL(glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT));
  BT_GL(glProgramUniform1i(program, 8, 0));
}

void DenoisePass::checkSizes(const GlTexture2D& beauty, std::initializer_list<const GlTexture2D*> others) const {
  for (const GlTexture2D* t : others)
    if (t->width() != beauty.width() || t->height() != beauty.height())
      throw GlError(fmt::format("denoise: a {}x{} image beside a {}x{} beauty", t->width(), t->height(), beauty.width(), beauty.height()));
}

void DenoisePass::bindGuide(const GlTexture2D& albedo, const GlTexture2D& normalDepth) {
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_ALBEDO, albedo.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_NORMAL_DEPTH, normalDepth.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
}

void DenoisePass::bindImages(const GlTexture2D& input, const GlTexture2D& output, const GlTexture2D& raw, const GlTexture2D& other,
                             const GlTexture2D& rawOther) {
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_IN, input.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_OUT, output.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_RAW, raw.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_OTHER, other.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(BT_IMAGE_DENOISE_RAW_OTHER, rawOther.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
}

void DenoisePass::filter(const Sum& beauty, bool hasMoment2, bool shrink, const GlTexture2D& out, const GlTexture2D& scratch) {
  const GLuint program = program_.id();
  BT_GL(glProgramUniform1i(program, 1, beauty.samples));
  BT_GL(glProgramUniform1i(program, 5, hasMoment2 && beauty.samples >= BT_DENOISE_TEMPORAL_VARIANCE_FROM));
  BT_GL(glProgramUniform1f(program, 6, beauty.scale));
  BT_GL(glProgramUniform1i(program, 7, shrink));
  BT_GL(glProgramUniform1i(program, 8, 0));
  // Step 0 prepares, steps 1.. filter (pass = step - 1); they alternate between the two images
  // so that the last one writes `out`.
  for (int step = 0; step <= BT_DENOISE_PASSES; ++step) {
    const bool intoOut = (BT_DENOISE_PASSES - step) % 2 == 0;
    const GlTexture2D& input = step == 0 ? beauty.image : intoOut ? scratch : out;
    BT_GL(glProgramUniform1i(program, 0, step == 0 ? 1 : 1 << (step - 1)));
    BT_GL(glProgramUniform1f(program, 2, step == 0 ? beauty.scale : 1.0f));
    BT_GL(glProgramUniform1i(program, 3, step == 0));
    BT_GL(glProgramUniform1i(program, 4, step == BT_DENOISE_PASSES));
    bindImages(input, intoOut ? out : scratch, beauty.image, input, beauty.image);
    program_.dispatch2d(beauty.image.width(), beauty.image.height());
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
  std::vector<float> albedo(n * 4), normalDepth(n * 4);
  const bool hasMoment2 = image.luminanceMoment2.size() == n;
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      albedo[i * 4 + c] = image.albedo[i][c];
      normalDepth[i * 4 + c] = image.normal[i][c];
    }
    normalDepth[i * 4 + 3] = image.depth[i];
  }
  GlTexture2D sum(GL_RGBA32F, width, height), albedoTexture(GL_RGBA32F, width, height), normalDepthTexture(GL_RGBA32F, width, height);
  GlTexture2D out(GL_RGBA32F, width, height), scratch(GL_RGBA32F, width, height);
  upload(sum, interleaved(image.beauty, hasMoment2 ? &image.luminanceMoment2 : nullptr));
  upload(albedoTexture, albedo);
  upload(normalDepthTexture, normalDepth);
  if (denoisesByHalves(image)) {
    const HalfMeans odd = oddHalf(image);
    GlTexture2D even(GL_RGBA32F, width, height), oddTexture(GL_RGBA32F, width, height);
    upload(even, interleaved(image.evenBeauty, &image.evenMoment2));
    upload(oddTexture, interleaved(odd.beauty, &odd.moment2));
    GlTexture2D wholeFiltered(GL_RGBA32F, width, height), evenFiltered(GL_RGBA32F, width, height), oddFiltered(GL_RGBA32F, width, height);
    pass.runHalves({sum, 1.0f, image.samples}, {even, 1.0f, evenSamples(image.samples)}, {oddTexture, 1.0f, odd.samples}, albedoTexture,
                   normalDepthTexture, {wholeFiltered, evenFiltered, oddFiltered, scratch, out});
  } else {
    pass.run(sum, 1.0f, image.samples, hasMoment2, albedoTexture, normalDepthTexture, out, scratch);
  }
  std::vector<float> rgba(n * 4);
  BT_GL(glPixelStorei(GL_PACK_ALIGNMENT, 4));
  BT_GL(glGetTextureImage(out.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * sizeof(float)), rgba.data()));
  std::vector<glm::vec3> result(n);
  for (size_t i = 0; i < n; ++i) result[i] = {rgba[i * 4], rgba[i * 4 + 1], rgba[i * 4 + 2]};
  return result;
}

} // namespace bt::gl
