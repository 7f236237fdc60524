// Physical mode's firefly clamp (IntegratorSettings::clampIndirect, `--clamp-indirect`;
// lighting/README.md "Fireflies") on a room whose light sits 8 units from a wall: what it
// removes (the per-pixel variance), what it costs (the mean, against the unclamped estimate) and
// what it leaves alone (the light the camera's surfaces receive directly). Every pixel in colour.
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/denoise.h"
#include "renderer/exposure.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace bt {
namespace {

constexpr int kWidth = 40, kHeight = 30;

// The far corner looks at the floor, the pillar and the wall beside the light.
const CameraPose kPose{{110.0f, 100.0f, 100.0f}, 30.0f, -150.0f, 0.0f, "test"};

RenderImage renderRoom(const RenderScene& rs, float clampIndirect, int bounces, int spp, uint32_t seed) {
  RenderSettings s;
  s.width = kWidth;
  s.height = kHeight;
  s.spp = spp;
  s.seed = seed;
  s.integrator.mode = LightingMode::Physical;
  s.integrator.bounces = bounces;
  s.integrator.clampIndirect = clampIndirect;
  return renderCpu(rs, Camera(kPose, kWidth, kHeight), s);
}

const RenderScene& room() {
  static const Scene scene = test::lightNearWallRoom();
  static const RenderScene rs = [] {
    Diagnostics diagnostics;
    return buildRenderScene(scene, {}, diagnostics);
  }();
  return rs;
}

// The variance of a 4-spp pixel, per channel, measured over `runs` renders of other seeds and
// summed over every channel of every pixel.
double summedVariance(float clampIndirect, int runs) {
  std::vector<glm::dvec3> sum(kWidth * kHeight, glm::dvec3(0.0)), sum2(kWidth * kHeight, glm::dvec3(0.0));
  for (int run = 0; run < runs; ++run) {
    const RenderImage image = renderRoom(room(), clampIndirect, 1, 4, 100 + run);
    for (size_t i = 0; i < sum.size(); ++i) {
      const glm::dvec3 x(image.beauty[i]);
      sum[i] += x, sum2[i] += x * x;
    }
  }
  double variance = 0.0;
  for (size_t i = 0; i < sum.size(); ++i) {
    const glm::dvec3 mean = sum[i] / double(runs);
    const glm::dvec3 v = (sum2[i] / double(runs) - mean * mean) * (double(runs) / (runs - 1));
    variance += v.x + v.y + v.z;
  }
  return variance;
}

glm::dvec3 imageMean(const RenderImage& image) {
  glm::dvec3 sum(0.0);
  for (const glm::vec3& p : image.beauty) sum += glm::dvec3(p);
  return sum / double(image.beauty.size());
}

TEST(Fireflies, ClampIndirectCutsThePixelVariance) {
  const double off = summedVariance(0.0f, 12), on = summedVariance(kClampIndirectDefault, 12);
  std::printf("summed per-pixel variance at 4 spp: clamp off %.4g, clamp %.0f units %.4g (%.1fx less)\n", off, kClampIndirectDefault, on,
              off / on);
  EXPECT_GT(off, 5.0 * on);
}

// The clamp's bias: the light it takes away, each channel of the image's mean, against
// unclamped references (another seed each, so their own noise counts too). This room is the
// worst case, its only light 8 units from a wall: measured -12.8 % at the default 32 units
// (lighting/README.md, "Fireflies"); the bar is 15 %.
TEST(Fireflies, ClampIndirectMovesTheMeanLittle) {
  const glm::dvec3 off = imageMean(renderRoom(room(), 0.0f, 1, 512, 7));
  const glm::dvec3 on = imageMean(renderRoom(room(), kClampIndirectDefault, 1, 512, 8));
  for (int c = 0; c < 3; ++c) {
    std::printf("channel %d: mean clamp off %.5f, on %.5f (%+.2f %%)\n", c, off[c], on[c], 100.0 * (on[c] / off[c] - 1.0));
    EXPECT_LE(on[c], off[c] * 1.01) << "the clamp only takes light away; channel " << c;
    EXPECT_GE(on[c], off[c] * 0.85) << "channel " << c;
  }
}

// What the camera's own surfaces receive from the lights directly is never clamped: with no
// bounce, the clamped image is the unclamped one, bit for bit (the same random numbers).
TEST(Fireflies, ClampIndirectLeavesDirectLightAlone) {
  const RenderImage off = renderRoom(room(), 0.0f, 0, 4, 3), on = renderRoom(room(), kClampIndirectDefault, 0, 4, 3);
  ASSERT_EQ(off.beauty.size(), on.beauty.size());
  for (size_t i = 0; i < off.beauty.size(); ++i) ASSERT_EQ(off.beauty[i], on.beauty[i]) << "pixel " << i;
  EXPECT_GT(imageMean(off).x, 0.0) << "a black image proves nothing";
}

// The denoiser on what the clamp leaves (the light beside the wall is still the noisiest of any
// test room): the variance-guided filter against the one it replaced (noise assumed 1 / sqrt(spp)
// everywhere, which spread the bright pixels into blobs), the mean relative MSE of three 4-spp
// renders (seeds 1-3), denoised, against a 1024-spp reference, every channel of every pixel.
TEST(Fireflies, VarianceGuidedDenoiserIsCloserThanTheOldFilter) {
  const RenderImage reference = renderRoom(room(), kClampIndirectDefault, 1, 1024, 99);
  const float scale = std::exp2(autoExposureEv(reference.beauty, kWidth, kHeight));
  const auto relativeMse = [&](const std::vector<glm::vec3>& image) {
    double sum = 0.0;
    for (size_t i = 0; i < image.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double x = image[i][c] * scale, r = reference.beauty[i][c] * scale;
        sum += (x - r) * (x - r) / (r * r + 0.01);
      }
    return sum / double(image.size() * 3);
  };
  double raw = 0.0, denoised = 0.0;
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const RenderImage noisy = renderRoom(room(), kClampIndirectDefault, 1, 4, seed);
    raw += relativeMse(noisy.beauty) / 3.0;
    denoised += relativeMse(denoise(noisy)) / 3.0;
  }
  std::printf("light-near-wall room, 4 spp: raw %.4f, denoised %.4f\n", raw, denoised);
  // Stated: below the old filter's 0.0336 (measured on these renders at fd4f78d; here 0.026).
  EXPECT_LT(denoised, 0.0336) << "raw " << raw;
}

} // namespace
} // namespace bt
