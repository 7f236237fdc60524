// The preview denoiser on the GPU: shaders/denoise.comp, renderer/denoise.h's filter pass for
// pass, so both tracers' images are denoised alike (tests/gl/gl_denoise_test.cpp).
#pragma once

#include "renderer/render.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_progressive.h"

#include <glm/vec3.hpp>

#include <initializer_list>
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

  // A sum (or mean) of samples with its second moment in alpha: times `scale` the mean of `samples`.
  struct Sum {
    const GlTexture2D& image;
    float scale;
    int samples;
  };
  // What runHalves writes: each mean filtered, every other step, and the result.
  struct Halves {
    const GlTexture2D &whole, &even, &odd, &scratch, &out;
  };
  // out = renderer/denoise.h's denoise of an image with its halves (BT_DENOISE_HALVES_FROM):
  // `whole` the mean of all the samples, `even` and `odd` of each half, all with their second moment.
  void runHalves(const Sum& whole, const Sum& even, const Sum& odd, const GlTexture2D& albedo, const GlTexture2D& normalDepth,
                 const Halves& images);

private:
  void checkSizes(const GlTexture2D& beauty, std::initializer_list<const GlTexture2D*> others) const;
  void bindGuide(const GlTexture2D& albedo, const GlTexture2D& normalDepth);
  void bindImages(const GlTexture2D& input, const GlTexture2D& output, const GlTexture2D& raw, const GlTexture2D& other,
                  const GlTexture2D& rawOther);
  // The prepare step and the filter's passes of `beauty` into `out`.
  void filter(const Sum& beauty, bool hasMoment2, bool shrink, const GlTexture2D& out, const GlTexture2D& scratch);

  ComputeProgram program_;
};

// renderer/denoise.h's denoise(image), on the current GL context: the image and its AOVs
// uploaded, filtered and read back.
std::vector<glm::vec3> denoiseWithGl(const RenderImage& image);
// ... with `pass`, for a caller that denoises every frame: a program that lives on (a deleted
// one left current is freed once another is used, and imgui restores the one it found current).
std::vector<glm::vec3> denoiseWithGl(const RenderImage& image, DenoisePass& pass);

} // namespace bt::gl
