// sampleBilinearRepeat against what GL_LINEAR + GL_REPEAT computes, on hand-checked values.
#include "bvh/trace_scene.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>
#include <utility>

namespace bt {
namespace {

// A 4x2 image whose red channel is 10 * column + 100 * row and green is 255 - red.
Image testImage() {
  Image image{4, 2, {}};
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const uint8_t r = static_cast<uint8_t>(10 * x + 100 * y);
      image.rgba.insert(image.rgba.end(), {r, static_cast<uint8_t>(255 - r), 7, 255});
    }
  return image;
}

float red(const glm::vec4& c) {
  return c.r * 255.0f;
}

TEST(TextureSampling, TexelCentresReturnTheTexel) {
  const Image image = testImage();
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const glm::vec4 c = sampleBilinearRepeat(image, (x + 0.5f) / 4.0f, (y + 0.5f) / 2.0f);
      EXPECT_FLOAT_EQ(red(c), 10.0f * x + 100.0f * y);
      EXPECT_FLOAT_EQ(c.g * 255.0f, 255.0f - (10.0f * x + 100.0f * y));
      EXPECT_FLOAT_EQ(c.b * 255.0f, 7.0f);
      EXPECT_FLOAT_EQ(c.a, 1.0f);
    }
}

TEST(TextureSampling, BlendsBetweenCentres) {
  const Image image = testImage();
  // Halfway between columns 1 and 2 of row 0: u = 2 / 4.
  EXPECT_FLOAT_EQ(red(sampleBilinearRepeat(image, 0.5f, 0.25f)), 15.0f);
  // A quarter of the way from column 0 to 1 and from row 0 to 1.
  EXPECT_NEAR(red(sampleBilinearRepeat(image, (0.5f + 0.25f) / 4.0f, (0.5f + 0.25f) / 2.0f)),
              0.75f * 0.75f * 0 + 0.25f * 0.75f * 10 + 0.75f * 0.25f * 100 + 0.25f * 0.25f * 110, 1e-4f);
}

TEST(TextureSampling, RepeatsAcrossTheEdges) {
  const Image image = testImage();
  // u = 0 lies halfway between the last column (30) and the first (0); v = 0 halfway between
  // the last row and the first, as GL_REPEAT wraps them.
  EXPECT_FLOAT_EQ(red(sampleBilinearRepeat(image, 0.0f, 0.25f)), 15.0f);
  EXPECT_FLOAT_EQ(red(sampleBilinearRepeat(image, 0.125f, 0.0f)), 50.0f);
  EXPECT_FLOAT_EQ(red(sampleBilinearRepeat(image, 0.0f, 0.0f)), (0 + 30 + 100 + 130) / 4.0f);
  // Whole periods, negative ones too, change nothing.
  for (float shift : {-3.0f, -1.0f, 1.0f, 17.0f}) {
    EXPECT_NEAR(red(sampleBilinearRepeat(image, 0.3f + shift, 0.7f + shift)), red(sampleBilinearRepeat(image, 0.3f, 0.7f)), 1e-3f);
  }
}

// The GL rule written out in scalars, as sampleBilinearRepeat computed it before it took the four
// channels in one SSE register: the repeat in double, the texels over 255, then x, then y.
glm::vec4 scalarBilinearRepeat(const Image& image, float u, float v) {
  const auto taps = [](float coordinate, int size, int& first, int& second) {
    double c = static_cast<double>(coordinate);
    c -= std::floor(c);
    const double x = c * size - 0.5;
    const double base = std::floor(x);
    first = static_cast<int>(base), second = first + 1;
    if (first < 0) first += size;
    if (second >= size) second -= size;
    return static_cast<float>(x - base);
  };
  int x0, x1, y0, y1;
  const float wx = taps(u, image.width, x0, x1), wy = taps(v, image.height, y0, y1);
  const auto texel = [&](int x, int y) {
    const uint8_t* t = image.texel(x, y);
    return glm::vec4(t[0], t[1], t[2], t[3]) * (1.0f / 255.0f);
  };
  const glm::vec4 top = texel(x0, y0) * (1.0f - wx) + texel(x1, y0) * wx;
  const glm::vec4 bottom = texel(x0, y1) * (1.0f - wx) + texel(x1, y1) * wx;
  return top * (1.0f - wy) + bottom * wy;
}

// Every channel the scalar rule's float, bit for bit, on random texels and coordinates (the
// images the tracers show and the bake's alpha tests depend on it).
TEST(TextureSampling, EveryChannelIsTheScalarRulesFloat) {
  std::mt19937 gen(3);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_real_distribution<float> coordinate(-40.0f, 40.0f);
  for (const auto& [w, h] : {std::pair{64, 64}, std::pair{16, 128}, std::pair{1, 1}, std::pair{3, 5}}) {
    Image image{w, h, {}};
    for (int i = 0; i < 4 * w * h; ++i) image.rgba.push_back(static_cast<uint8_t>(byte(gen)));
    for (int i = 0; i < 20000; ++i) {
      const float u = coordinate(gen), v = coordinate(gen);
      const glm::vec4 got = sampleBilinearRepeat(image, u, v), expected = scalarBilinearRepeat(image, u, v);
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(std::bit_cast<uint32_t>(got[c]), std::bit_cast<uint32_t>(expected[c]))
            << w << "x" << h << " at " << u << " " << v << " channel " << c << ": " << got[c] << " against " << expected[c];
    }
  }
}

TEST(TextureSampling, EmptyImageIsBlack) {
  EXPECT_EQ(sampleBilinearRepeat(Image{}, 0.5f, 0.5f), glm::vec4(0.0f));
}

TEST(TextureSampling, TextureCoordinatesFollowTheFaceFrame) {
  // A floor face with Quake's floor axes at scale 2 (vectors of length 1/2) and origin (8, 4, 0):
  // s = (x - 8) / 2, t = -(y - 4) / 2.
  GpuFace face{};
  face.origin[0] = 8, face.origin[1] = 4;
  face.tangent[0] = 0.5f;
  face.bitangent[1] = -0.5f;
  const glm::vec2 st = textureCoordinates(face, {20, 10, 0});
  EXPECT_FLOAT_EQ(st.x, 6.0f);
  EXPECT_FLOAT_EQ(st.y, -3.0f);
}

} // namespace
} // namespace bt
