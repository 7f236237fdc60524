// The preview denoiser on the GPU: shaders/denoise.comp, renderer/denoise.h's filter pass for
// pass, so both tracers' images are denoised alike (tests/gl/gl_denoise_test.cpp).
#pragma once

#include "renderer/render.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_progressive.h"

#include <glm/vec3.hpp>

#include <memory>
#include <vector>

namespace bt::gl {

class DenoisePass {
public:
  DenoisePass(); // builds the program; the context must be current
  // out = the denoised beauty, from `beauty` (RGBA32F) times `scale`, the mean of `samples`
  // samples (a progressive sum with scale 1 / samples, or a mean with 1; with `hasMoment2`, its
  // alpha holds the samples' squared luminance likewise), guided by `albedo` and `normalDepth`
  // (RGBA32F: aov.comp's normal and depth, depth +inf where nothing is hit). `scratch` holds
  // every other step. All five textures are the beauty's size.
  void run(const GlTexture2D& beauty, float scale, int samples, bool hasMoment2, const GlTexture2D& albedo, const GlTexture2D& normalDepth,
           const GlTexture2D& out, const GlTexture2D& scratch);

  // The five images denoiseWithGl fills, filters and reads back, kept from one call to the next
  // while the size stays: the viewer denoises every frame it shows.
  struct Images {
    Images(int width, int height);
    GlTexture2D sum, albedo, normalDepth, out, scratch;
  };
  const Images& imagesOfSize(int width, int height);

private:
  ComputeProgram program_;
  std::unique_ptr<Images> images_;
};

// renderer/denoise.h's denoise(image), on the current GL context: the image and its AOVs
// uploaded, filtered and read back.
std::vector<glm::vec3> denoiseWithGl(const RenderImage& image);
// ... with `pass`, for a caller that denoises every frame: a program that lives on (a deleted
// one left current is freed once another is used, and imgui restores the one it found current).
std::vector<glm::vec3> denoiseWithGl(const RenderImage& image, DenoisePass& pass);

} // namespace bt::gl
