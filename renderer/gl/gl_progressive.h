// Progressive rendering kept on the GPU, for the viewer: one RGBA32F sum that takes one more
// sample per frame, and a tonemap pass (shaders/tonemap.comp) that turns sum / samples into
// the RGBA8 image on screen. Nothing is read back per frame; readMean() and readRgba8() are
// for screenshots and tests.
#pragma once

#include "renderer/tonemap.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_tracer.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace bt::gl {

// A 2D texture with one level of immutable storage (glTextureStorage2D), deleted with it.
class GlTexture2D {
public:
  GlTexture2D(unsigned internalFormat, int width, int height);
  ~GlTexture2D();
  GlTexture2D(const GlTexture2D&) = delete;
  GlTexture2D& operator=(const GlTexture2D&) = delete;

  unsigned id() const { return texture_; }
  int width() const { return width_; }
  int height() const { return height_; }

private:
  unsigned texture_ = 0;
  int width_ = 0;
  int height_ = 0;
};

// The running sum of one view's samples. restart() when the view changes: the next sample
// then overwrites the sum instead of adding to it (pathtrace.comp `accumulate`, firstFrame).
// Sample n draws pixelRng's stream n, as GlTracer::renderBeauty's sample n does, so n calls
// of addSample sum the image renderBeauty gives for spp = n.
class ProgressiveImage {
public:
  ProgressiveImage(int width, int height);

  void restart() { samples_ = 0; }
  // One more sample of `camera` by `tracer`; settings.spp, width and height are ignored (one
  // sample, at this image's size).
  void addSample(GlTracer& tracer, const CameraBasis& camera, const BeautySettings& settings);

  int samples() const { return samples_; }
  int width() const { return sum_.width(); }
  int height() const { return sum_.height(); }
  const GlTexture2D& sum() const { return sum_; }

  // Mean linear radiance per pixel, top row first (black before the first sample).
  std::vector<glm::vec3> readMean() const;

private:
  GlTexture2D sum_;
  int samples_ = 0;
};

// shaders/tonemap.comp: exposure, scene/color.h's tonemap operator and sRGB encoding on
// the GPU, so the viewer shows the bytes a PNG of the same image would hold.
class TonemapPass {
public:
  TonemapPass(); // builds the program; the context must be current
  // display (RGBA8, the sum's size) = sRGB(tonemap(sum / samples * 2^exposureEv)).
  void run(const GlTexture2D& sum, int samples, const GlTexture2D& display, Tonemap tonemap, float exposureEv = 0.0f);

private:
  ComputeProgram program_;
};

// An RGBA8 texture's bytes, width * height * 4, top row first (the row the shaders write at y = 0).
std::vector<uint8_t> readRgba8(const GlTexture2D& texture);

} // namespace bt::gl
