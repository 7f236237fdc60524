// Progressive rendering kept on the GPU, for the viewer: one RGBA32F sum that takes one more
// sample per frame (rgb the radiance, a its luminance squared), and a tonemap pass (shaders/tonemap.comp) that turns sum / samples into
// the RGBA8 image on screen. Nothing is read back per frame; readMean() and readRgba8() are
// for screenshots and tests.
#pragma once

#include "renderer/tonemap.h"
#include "renderer/gl/gl_program.h"
#include "renderer/gl/gl_tracer.h"

#include <glm/vec3.hpp>

#include <chrono>
#include <cstdint>
#include <functional>
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
//
// A pass (one sample of every pixel) may be drawn in pieces (addPiece), where the GL is too slow
// for a window to wait for a whole one: llvmpipe takes seconds for a sample at 640x360. The
// pieces are runs of kPieceAlignment-square groups of pixels, left to right along a row of groups
// then the rows top to bottom, each drawing what the whole pass draws there: after n passes the
// sum is the same, bit for bit, however they were cut. samples() counts whole passes; the pixels
// the current pass has reached hold one sample more (readMean and donePieces say which).
class ProgressiveImage {
public:
  ProgressiveImage(int width, int height);

  void restart() { samples_ = 0, nextGroup_ = 0; }
  // One more sample of `camera` by `tracer`; settings.spp, width and height are ignored (one
  // sample, at this image's size). A pass under way is finished instead.
  void addSample(GlTracer& tracer, const CameraBasis& camera, const BeautySettings& settings);
  // The next piece of the current pass: at most `maxPixels` (rounded down to whole groups, one at
  // least; not past the pass's end), a dispatch for each rectangle of it (the rest of a row of
  // groups, whole rows, part of a row: three at most). Returns the pixels it drew.
  size_t addPiece(GlTracer& tracer, const CameraBasis& camera, const BeautySettings& settings, size_t maxPixels);

  int samples() const { return samples_; } // whole passes
  int width() const { return sum_.width(); }
  int height() const { return sum_.height(); }
  const GlTexture2D& sum() const { return sum_; }
  // The pixels the current pass has drawn (samples() + 1 samples each): none, or whole rows of
  // groups from the top and then part of the next row, from its left; at most two rectangles.
  std::vector<PixelRect> donePieces() const;

  // Mean linear radiance per pixel, top row first (each pixel's own count: black before its first
  // sample); with `moment2`, the mean of the samples' squared luminance too (the sum's alpha:
  // pathtrace.comp's accumulate, RenderImage::luminanceMoment2).
  std::vector<glm::vec3> readMean(std::vector<float>* moment2 = nullptr) const;

private:
  int groupsX() const { return (width() + kPieceAlignment - 1) / kPieceAlignment; }
  int groupsY() const { return (height() + kPieceAlignment - 1) / kPieceAlignment; }

  GlTexture2D sum_;
  int samples_ = 0;
  int nextGroup_ = 0; // of the current pass, counted along the rows of groups
};

// Sizes the pieces of a pass (ProgressiveImage::addPiece) so that each takes about `budget` of
// the GL's time, from the time its last timed piece took per pixel: a GL_TIME_ELAPSED query, read
// once the driver has its result (never waited for: a GPU runs on while the next frame is
// prepared), or the time the calls took where that is longer. llvmpipe runs a dispatch before
// it returns, and its query times only the rasterizer's work (some pieces of a second read as
// a fraction of a millisecond there). It starts at kFirstPiecePixels and grows at most kGrowth
// times a piece (pixels cost unlike amounts: a wall, the sky), so a fast GL (a GPU) draws whole
// passes, one dispatch each as without pieces, from its first few frames on.
class PieceSizer {
public:
  static constexpr size_t kFirstPiecePixels = 1024;
  static constexpr size_t kGrowth = 4;

  explicit PieceSizer(std::chrono::duration<double> budget); // the context must be current
  ~PieceSizer();
  PieceSizer(const PieceSizer&) = delete;
  PieceSizer& operator=(const PieceSizer&) = delete;

  // The next piece's pixels, at most `whole` (the image's).
  size_t nextPixels(size_t whole);
  // Times `draw` (which draws a piece and returns its pixels) when the last timing has been read.
  size_t timed(const std::function<size_t()>& draw);
  double lastMilliseconds() const { return lastSeconds_ * 1e3; } // the last piece read back; 0 before
  double lastPixelsPerSecond() const { return lastSeconds_ > 0.0 ? double(timedPixels_) / lastSeconds_ : 0.0; }

private:
  void readTiming();

  double budgetSeconds_;
  unsigned query_ = 0;
  bool timing_ = false;      // a query ended whose result has not been read
  size_t timedPixels_ = 0;   // of the piece it timed
  double wallSeconds_ = 0.0; // the calls that drew it took
  double lastSeconds_ = 0.0;
  size_t pixels_ = kFirstPiecePixels;
};

// shaders/tonemap.comp: exposure, scene/color.h's tonemap operator and sRGB encoding on
// the GPU, so the viewer shows the bytes a PNG of the same image would hold.
class TonemapPass {
public:
  TonemapPass(); // builds the program; the context must be current
  // display (RGBA8, the sum's size) = sRGB(tonemap(sum / samples * 2^exposureEv)).
  void run(const GlTexture2D& sum, int samples, const GlTexture2D& display, Tonemap tonemap, float exposureEv = 0.0f);
  // The same for the pixels of `region` only (ProgressiveImage::donePieces: a pass under way).
  void run(const GlTexture2D& sum, int samples, const GlTexture2D& display, Tonemap tonemap, float exposureEv, const PixelRect& region);

private:
  ComputeProgram program_;
};

// An RGBA8 texture's bytes, width * height * 4, top row first (the row the shaders write at y = 0).
std::vector<uint8_t> readRgba8(const GlTexture2D& texture);

} // namespace bt::gl
