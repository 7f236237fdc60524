// The documented ranges (lighting/README.md, "Liquids") of the mean displayed colour (sRGB,
// auto-exposed, the default tonemap) of each liquid of maps/liquids/pools.map in physical mode,
// 16 samples: the CPU tracer's (tests/render/liquids_test.cpp) and the GL tracer's
// (tests/gl/gl_liquids_test.cpp).
#pragma once

#include "renderer/exposure.h"
#include "renderer/render.h"
#include "renderer/tonemap.h"
#include "scene/color.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string_view>

namespace bt::test {

// The engine's blend: alpha x water + (1 - alpha) x behind, in the framebuffer's gamma space.
inline glm::vec3 engineBlend(float alpha, const glm::vec3& waterSrgb, const glm::vec3& behindLinear) {
  return srgbToLinear(alpha * waterSrgb + (1.0f - alpha) * linearToSrgb(behindLinear));
}

// Whether got is within tolerance of want in every channel; a failure names the pixel.
inline bool expectNear(const glm::vec3& got, const glm::vec3& want, float tolerance, size_t pixel, const char* what) {
  for (int c = 0; c < 3; ++c)
    if (std::abs(got[c] - want[c]) > tolerance * want[c] + 1e-3f) {
      ADD_FAILURE() << what << " at pixel " << pixel << " channel " << c << ": " << got[c] << ", the rule gives " << want[c];
      return false;
    }
  return true;
}

struct LiquidRange {
  const char* texture;
  glm::vec3 lo, hi;
};

// Measured (CPU, 96x64, 16 spp): water (0.12, 0.26, 0.53), slime (0.24, 0.50, 0.12), lava
// (1.00, 0.45, 0.11). A black water, a flat neon slime (green near 1) or a flat yellow lava
// (green near 1) falls outside.
inline constexpr LiquidRange kLiquidRanges[] = {
    {"*water_blue", glm::vec3(0.03f, 0.10f, 0.30f), glm::vec3(0.30f, 0.45f, 0.80f)},
    {"*slime_green", glm::vec3(0.10f, 0.30f, 0.03f), glm::vec3(0.40f, 0.70f, 0.30f)},
    {"*lava_glow", glm::vec3(0.85f, 0.25f, 0.00f), glm::vec3(1.00f, 0.70f, 0.30f)},
};

// The mean displayed colour of the pixels that see faces of `texture`; count: how many.
inline glm::vec3 displayedMean(const Scene& scene, const RenderImage& image, std::string_view texture, size_t& count) {
  const float scale = std::exp2(autoExposureEv(image.beauty, image.width, image.height));
  glm::dvec3 sum(0.0);
  count = 0;
  for (size_t i = 0; i < image.face.size(); ++i) {
    if (image.face[i] == 0 || scene.faces[image.face[i] - 1].texture != texture) continue;
    sum += glm::dvec3(linearToSrgb(glm::clamp(applyTonemap(Tonemap::Faithful, image.beauty[i] * scale), 0.0f, 1.0f)));
    ++count;
  }
  return count ? glm::vec3(sum / double(count)) : glm::vec3(0.0f);
}

// Each liquid in view (over 50 pixels) and its mean within its range, channel by channel.
inline void expectLiquidsInRange(const Scene& scene, const RenderImage& image, const char* tracer) {
  for (const LiquidRange& r : kLiquidRanges) {
    size_t count = 0;
    const glm::vec3 mean = displayedMean(scene, image, r.texture, count);
    ASSERT_GT(count, size_t(50)) << r.texture << " should be in view";
    std::cout << tracer << " " << r.texture << " mean displayed colour " << mean.x << " " << mean.y << " " << mean.z << "\n";
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(mean[c], r.lo[c]) << tracer << " " << r.texture << " channel " << c << ": mean " << mean.x << " " << mean.y << " "
                                  << mean.z;
      EXPECT_LE(mean[c], r.hi[c]) << tracer << " " << r.texture << " channel " << c << ": mean " << mean.x << " " << mean.y << " "
                                  << mean.z;
    }
  }
}

} // namespace bt::test
