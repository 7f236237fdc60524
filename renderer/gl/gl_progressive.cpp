#include "renderer/gl/gl_progressive.h"

#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_structs.h"

#include <epoxy/gl.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

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
  const int pass = samples_;
  while (samples_ == pass) addPiece(tracer, camera, settings, std::numeric_limits<size_t>::max());
}

size_t ProgressiveImage::addPiece(GlTracer& tracer, const CameraBasis& camera, const BeautySettings& settings, size_t maxPixels) {
  constexpr size_t kGroupPixels = size_t(kPieceAlignment) * kPieceAlignment;
  int groups = int(std::clamp<size_t>(maxPixels / kGroupPixels, 1, size_t(groupsX()) * size_t(groupsY())));
  BeautySettings one = settings;
  one.width = width();
  one.height = height();
  one.spp = 1;
  const int pass = samples_;
  size_t drawn = 0;
  // A rectangle at a time: the rest of the row of groups under way, whole rows, part of a row.
  while (groups > 0 && samples_ == pass) {
    const int gx = nextGroup_ % groupsX(), gy = nextGroup_ / groupsX();
    const bool rows = gx == 0 && groups >= groupsX();
    const int across = rows ? groupsX() : std::min(groups, groupsX() - gx);
    const int down = rows ? std::min(groups / groupsX(), groupsY() - gy) : 1;
    PixelRect piece{gx * kPieceAlignment, gy * kPieceAlignment, across * kPieceAlignment, down * kPieceAlignment};
    piece.width = std::min(piece.width, width() - piece.x);
    piece.height = std::min(piece.height, height() - piece.y);
    if (piece.width == width() && piece.height == height())
      tracer.addSample(camera, one, sum_.id(), static_cast<uint32_t>(samples_)); // the whole pass: as without pieces
    else
      tracer.addSample(camera, one, sum_.id(), static_cast<uint32_t>(samples_), piece);
    drawn += piece.pixels();
    groups -= across * down;
    nextGroup_ += across * down;
    if (nextGroup_ == groupsX() * groupsY()) nextGroup_ = 0, ++samples_;
  }
  return drawn;
}

std::vector<PixelRect> ProgressiveImage::donePieces() const {
  std::vector<PixelRect> done;
  const int rows = nextGroup_ / groupsX(), across = nextGroup_ % groupsX();
  if (rows > 0) done.push_back({0, 0, width(), std::min(rows * kPieceAlignment, height())});
  if (across > 0)
    done.push_back({0, rows * kPieceAlignment, across * kPieceAlignment, std::min(kPieceAlignment, height() - rows * kPieceAlignment)});
  return done;
}

std::vector<glm::vec3> ProgressiveImage::readMean(std::vector<float>* moment2) const {
  const size_t n = static_cast<size_t>(width()) * static_cast<size_t>(height());
  std::vector<glm::vec3> mean(n, glm::vec3(0.0f));
  if (moment2) moment2->assign(n, 0.0f);
  if (samples_ == 0 && nextGroup_ == 0) return mean;
  std::vector<float> rgba(n * 4);
  BT_GL(glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT));
  BT_GL(glPixelStorei(GL_PACK_ALIGNMENT, 4));
  BT_GL(glGetTextureImage(sum_.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * sizeof(float)), rgba.data()));
  for (int y = 0; y < height(); ++y)
    for (int x = 0; x < width(); ++x) {
      const int group = (y / kPieceAlignment) * groupsX() + x / kPieceAlignment;
      const int count = samples_ + (group < nextGroup_ ? 1 : 0);
      if (count == 0) continue; // not drawn since the restart: what is there is another view's
      const size_t i = size_t(y) * size_t(width()) + size_t(x);
      mean[i] = glm::vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]) / static_cast<float>(count);
      if (moment2) (*moment2)[i] = rgba[4 * i + 3] / static_cast<float>(count);
    }
  return mean;
}

PieceSizer::PieceSizer(std::chrono::duration<double> budget) : budgetSeconds_(budget.count()) {
  BT_GL(glCreateQueries(GL_TIME_ELAPSED, 1, &query_));
}

PieceSizer::~PieceSizer() {
  glDeleteQueries(1, &query_);
}

void PieceSizer::readTiming() {
  if (!timing_) return;
  GLint available = 0;
  BT_GL(glGetQueryObjectiv(query_, GL_QUERY_RESULT_AVAILABLE, &available));
  if (!available) return;
  GLuint64 nanoseconds = 0;
  BT_GL(glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &nanoseconds));
  timing_ = false;
  lastSeconds_ = std::max({double(nanoseconds) * 1e-9, wallSeconds_, 1e-9});
  // The budget at the rate measured, but not more than kGrowth times the piece: the next may
  // cost more a pixel (the sky is cheap, a room full of lights is not).
  const double fits = budgetSeconds_ / lastSeconds_ * double(timedPixels_);
  pixels_ = std::max<size_t>(1, size_t(std::min(fits, double(timedPixels_) * double(kGrowth))));
}

size_t PieceSizer::nextPixels(size_t whole) {
  readTiming();
  return std::min(pixels_, whole);
}

size_t PieceSizer::timed(const std::function<size_t()>& draw) {
  if (timing_) return draw(); // the last one's time is not back yet: this one goes untimed
  const auto start = std::chrono::steady_clock::now();
  BT_GL(glBeginQuery(GL_TIME_ELAPSED, query_));
  const size_t pixels = draw();
  BT_GL(glEndQuery(GL_TIME_ELAPSED));
  wallSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  timing_ = pixels > 0;
  timedPixels_ = pixels;
  return pixels;
}

TonemapPass::TonemapPass() : program_("tonemap.comp", {}) {}

void TonemapPass::run(const GlTexture2D& sum, int samples, const GlTexture2D& display, Tonemap tonemap, float exposureEv) {
  run(sum, samples, display, tonemap, exposureEv, PixelRect{0, 0, display.width(), display.height()});
}

void TonemapPass::run(const GlTexture2D& sum, int samples, const GlTexture2D& display, Tonemap tonemap, float exposureEv,
                      const PixelRect& region) {
  if (sum.width() != display.width() || sum.height() != display.height())
    throw GlError(
        fmt::format("tonemap: a {}x{} sum onto a {}x{} display image", sum.width(), sum.height(), display.width(), display.height()));
  const GLuint program = program_.id();
  const float scale = std::exp2(exposureEv) / static_cast<float>(std::max(samples, 1));
  BT_GL(glProgramUniform1f(program, 0, scale));
  BT_GL(glProgramUniform1ui(program, 1, static_cast<GLuint>(tonemap)));
  BT_GL(glProgramUniform4i(program, 2, region.x, region.y, region.x + region.width, region.y + region.height));
  BT_GL(glBindImageTexture(kImageAccumulation, sum.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F));
  BT_GL(glBindImageTexture(kImageDisplay, display.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8));
  program_.dispatch2d(region.width, region.height);
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
