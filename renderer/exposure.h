// Automatic exposure for physical mode: the exposure that puts the log-average luminance of the
// image at middle grey, the "key" of Reinhard et al. 2002 ("Photographic Tone Reproduction for
// Digital Images", section 3: Lw = exp(mean(log(delta + L))), scaled by a / Lw with a = 0.18).
// One function for `render` (both tracers: the GL image is read back anyway) and the viewer
// (from a read-back at a low rate, smoothed by ExposureSmoother). Faithful mode is never
// auto-exposed: the game's lightmaps have an absolute brightness.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace bt {

// Reinhard et al. 2002's key for a normal scene (middle grey).
inline constexpr float kExposureKey = 0.18f;
// Luminance is averaged over blocks of this many pixels a side before the log: at a few samples
// per pixel most pixels are noise, and the log of a noisy value is biased low (Jensen's
// inequality: E[log X] < log E[X]); a block's mean of 64 pixels is nearly noise-free, so 4 and
// 64 spp give the same exposure.
inline constexpr int kExposureBlock = 8;
// A block darker than this (linear radiance) is left out: the void outside a level, or a
// camera in a wall, says nothing about how bright the level is.
inline constexpr float kExposureBlack = 1e-6f;
// The exposure is kept within this range of EV, so a nearly black image is not lifted to noise.
inline constexpr float kExposureMinEv = -16.0f;
inline constexpr float kExposureMaxEv = 16.0f;

// Rec. 709 luminance of linear RGB.
float luminance(const glm::vec3& c);

// The EV (scale 2^EV) that maps the log-average luminance of `linear` (width x height, rows
// top first) to kExposureKey. Pixels that are NaN or infinite are left out of their block;
// blocks darker than kExposureBlack are left out. An image with no such block gets 0.
float autoExposureEv(const std::vector<glm::vec3>& linear, int width, int height);

// The viewer's exposure from frame to frame: a new measurement at most every kInterval seconds
// (a read-back of the image costs milliseconds), followed exponentially with time constant
// kTimeConstant so the picture does not pump as samples arrive; the first measurement is taken
// as it is.
class ExposureSmoother {
public:
  static constexpr double kInterval = 0.25;
  static constexpr double kTimeConstant = 0.5;

  bool due(double now) const { return !started_ || now - lastMeasured_ >= kInterval; }
  float update(float targetEv, double now);
  float ev() const { return ev_; }
  void reset() { started_ = false; }

private:
  bool started_ = false;
  double lastMeasured_ = 0.0;
  float ev_ = 0.0f;
};

} // namespace bt
