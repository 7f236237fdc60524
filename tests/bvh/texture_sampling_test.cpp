// sampleBilinearRepeat against what GL_LINEAR + GL_REPEAT computes, on hand-checked values.
#include "bvh/trace_scene.h"

#include <gtest/gtest.h>

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
