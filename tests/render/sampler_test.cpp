// Physical mode's low-discrepancy sampler (lighting/sampling.h pixelSampler): what makes a
// pixel's mean converge faster than with independent draws is that its first N samples (N a
// power of two) cover the square evenly, one point in each cell of every grid of N equal boxes.
#include "lighting/sampling.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/exposure.h"
#include "renderer/time_to_converged.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace bt {
namespace {

// The 2D draw of sample i of pixel (x, y) at `offset` of surface `depth`'s block, as the
// integrator takes it (Rng::at, then next2).
glm::vec2 draw2(uint32_t x, uint32_t y, uint32_t i, int depth, uint32_t offset) {
  Rng rng = pixelSampler(x, y, i, 5);
  rng.at(depth, offset);
  return rng.next2();
}

// How many of the 2^m grids of 2^m boxes (2^a columns by 2^(m-a) rows, a = 0..m) hold a box
// with no point or more than one: 0 for a (0, m, 2)-net.
int gridsNotStratified(const std::vector<glm::vec2>& points, int m) {
  int bad = 0;
  for (int a = 0; a <= m; ++a) {
    const uint32_t cols = 1u << a, rows = 1u << (m - a);
    std::vector<int> count(size_t(cols) * rows, 0);
    for (const glm::vec2& p : points) ++count[size_t(uint32_t(p.y * float(rows))) * cols + uint32_t(p.x * float(cols))];
    for (int c : count)
      if (c != 1) {
        ++bad;
        break;
      }
  }
  return bad;
}

TEST(Sampler, FirstPowerOfTwoSamplesOfEachPairAreStratified) {
  // Several pixels, surfaces and groups: the BSDF direction at an odd start after a lobe draw
  // (next2 moves to the pair), the emitter point after its 1D pick, the light pick.
  const struct {
    int depth;
    uint32_t offset;
  } groups[] = {{0, BT_DIM_LIGHT_PICK}, {0, BT_DIM_EMITTER}, {1, BT_DIM_BSDF + 1u}, {3, BT_DIM_LIGHT_POINT}};
  for (uint32_t pixel = 0; pixel < 6; ++pixel)
    for (const auto& g : groups)
      for (int m = 1; m <= 8; ++m) {
        std::vector<glm::vec2> points;
        for (uint32_t i = 0; i < (1u << m); ++i) points.push_back(draw2(pixel * 37u, pixel * 11u + 3u, i, g.depth, g.offset));
        EXPECT_EQ(gridsNotStratified(points, m), 0)
            << "pixel " << pixel << ", depth " << g.depth << ", offset " << g.offset << ", " << (1 << m) << " samples";
      }
}

TEST(Sampler, SecondSobolDimensionFollowsItsDirectionNumbers) {
  // Sobol's definition: the XOR of the direction numbers of the index's set bits, v(0) the top
  // bit and v(k+1) = v(k) ^ v(k) >> 1 (the same sequence as its first values, 0, 1/2, 3/4, 1/4).
  const auto byDefinition = [](uint32_t index) {
    uint32_t result = 0u, v = 0x80000000u;
    for (; index != 0u; index >>= 1u, v ^= v >> 1u)
      if (index & 1u) result ^= v;
    return result;
  };
  EXPECT_EQ(sobolSecond(1), 0x80000000u);
  EXPECT_EQ(sobolSecond(2), 0xc0000000u);
  EXPECT_EQ(sobolSecond(3), 0x40000000u);
  Rng any = pixelRng(0, 0, 0, 1);
  for (uint32_t i = 0; i < 100000; ++i) {
    const uint32_t index = i < 50000 ? i : uint32_t(any.next() * 16777216.0f) * 256u + (i & 255u);
    ASSERT_EQ(sobolSecond(index), byDefinition(index)) << "index " << index;
  }
}

TEST(Sampler, APairDrawnAtOnceIsItsTwoDimensionsDrawnOneByOne) {
  // next2 hashes a pair once for both numbers (the GL tracer's cost): the same numbers as
  // next() twice from the pair's first dimension.
  for (uint32_t i = 0; i < 256; ++i)
    for (uint32_t offset : {BT_DIM_LIGHT_PICK, BT_DIM_EMITTER + 1u, BT_DIM_BSDF + 2u}) {
      Rng a = pixelSampler(i % 7u, i / 7u, i, 2), b = a;
      a.at(1, offset), b.at(1, offset);
      const glm::vec2 pair = a.next2();
      const float first = b.next(); // in two statements: drawn in this order
      EXPECT_EQ(pair, glm::vec2(first, b.next())) << "sample " << i << ", offset " << offset;
      EXPECT_EQ(a.next(), b.next()); // and both go on from the same dimension
    }
}

TEST(Sampler, PixelsAndPairsAreScrambledApart) {
  // Two pixels, and two pairs of one pixel, draw different points for the same sample: each
  // has its own scramble, so that neighbours' errors do not line up into patterns.
  int samePixels = 0, samePairs = 0;
  for (uint32_t i = 0; i < 64; ++i) {
    samePixels += draw2(0, 0, i, 0, BT_DIM_BSDF) == draw2(1, 0, i, 0, BT_DIM_BSDF);
    samePairs += draw2(0, 0, i, 0, BT_DIM_BSDF) == draw2(0, 0, i, 1, BT_DIM_BSDF);
  }
  EXPECT_EQ(samePixels, 0);
  EXPECT_EQ(samePairs, 0);
}

TEST(Sampler, PixelRngAndDrawsOutsideTheGroupsArePcg) {
  // Faithful mode, bakes and the draws physical mode does not place keep pixelRng's stream.
  Rng pcg = pixelRng(3, 4, 5, 6), sampler = pixelSampler(3, 4, 5, 6);
  sampler.next2(); // the camera's subpixel
  sampler.atPcg();
  for (int k = 0; k < 4; ++k) EXPECT_EQ(sampler.next(), pcg.next());
  Rng plain = pixelRng(3, 4, 5, 6), placed = plain;
  placed.at(2, BT_DIM_BSDF); // a pixelRng ignores the placement
  for (int k = 0; k < 4; ++k) EXPECT_EQ(placed.next(), plain.next());
}

// The furnished room (tests/render/box_scene.h) with a soft light, `spp` samples of `seed` with
// the Sobol sequence or without (PCG).
RenderImage renderRoom(int spp, uint32_t seed, bool lowDiscrepancy) {
  static const Scene scene = test::furnishedRoom({.softLight = true}); // the RenderScene refers to it
  Diagnostics diagnostics;
  static const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  return test::renderFurnishedRoom(rs, spp, seed, lowDiscrepancy);
}

TEST(Sampler, DisplayedRoomIsCloserToItsReferenceThanWithPcgAtEqualSamples) {
  // What the user sees: the displayed image (auto exposure, ACES, sRGB) against a 1024-spp PCG
  // reference, each sampler's error averaged over three seeds, at 16 spp.
  const RenderImage reference = renderRoom(1024, 99, false);
  const float ev = autoExposureEv(reference.beauty, reference.width, reference.height);
  const std::vector<glm::vec3> shown = displayedImage(reference.beauty, ev);
  double sobol = 0.0, pcg = 0.0;
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    sobol += relativeMse(displayedImage(renderRoom(16, seed, true).beauty, ev), shown) / 3.0;
    pcg += relativeMse(displayedImage(renderRoom(16, seed, false).beauty, ev), shown) / 3.0;
  }
  std::printf("displayed rel. MSE at 16 spp: sobol %.5f, pcg %.5f (%.2fx)\n", sobol, pcg, sobol / pcg);
  EXPECT_LT(sobol, 0.88 * pcg); // 0.79x when written
}

} // namespace
} // namespace bt
