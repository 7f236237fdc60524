#include "renderer/exposure.h"

#include "shaders/denoise_constants.glsl" // BT_LUMINANCE_*: shared with shaders/denoise.comp

#include <algorithm>
#include <cmath>

namespace bt {

float luminance(const glm::vec3& c) {
  return BT_LUMINANCE_R * c.x + BT_LUMINANCE_G * c.y + BT_LUMINANCE_B * c.z;
}

float autoExposureEv(const std::vector<glm::vec3>& linear, int width, int height) {
  double logSum = 0.0;
  long blocks = 0;
  for (int by = 0; by < height; by += kExposureBlock) {
    for (int bx = 0; bx < width; bx += kExposureBlock) {
      double sum = 0.0;
      int count = 0;
      for (int y = by; y < std::min(by + kExposureBlock, height); ++y) {
        for (int x = bx; x < std::min(bx + kExposureBlock, width); ++x) {
          const float l = luminance(linear[size_t(y) * size_t(width) + size_t(x)]);
          if (!std::isfinite(l)) continue;
          sum += std::max(l, 0.0f);
          ++count;
        }
      }
      if (count == 0 || sum / count <= kExposureBlack) continue;
      logSum += std::log(sum / count);
      ++blocks;
    }
  }
  if (blocks == 0) return 0.0f;
  const double logAverage = std::exp(logSum / double(blocks));
  return std::clamp(float(std::log2(kExposureKey / logAverage)), kExposureMinEv, kExposureMaxEv);
}

float ExposureSmoother::update(float targetEv, double now) {
  if (!started_) {
    ev_ = targetEv;
  } else {
    const double blend = 1.0 - std::exp(-(now - lastMeasured_) / kTimeConstant);
    ev_ += float(blend) * (targetEv - ev_);
  }
  started_ = true;
  lastMeasured_ = now;
  return ev_;
}

} // namespace bt
