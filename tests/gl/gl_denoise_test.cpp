// The denoiser's GLSL pass (shaders/denoise.comp, gl::DenoisePass) against the C++ one
// (renderer/denoise.h) on the same image: the hand-built room's AOVs as the tracer gives them,
// and a noisy beauty made from them, every pixel in colour.
#include "renderer/denoise.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_denoise.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

namespace bt::gl {
namespace {

constexpr int kWidth = 80, kHeight = 60;

// The room's AOVs, and a beauty of albedo x a light falling off across the image x noise in
// 0..2 (as a few samples per pixel give), with a hole of sky (nothing hit) and a NaN sample; its
// second moment (the samples' squared luminance) noisier on the right half.
RenderImage noisyRoom(int samples) {
  const Scene scene = test::makeTestRoom();
  GlTracer tracer(test::sharedGlContext(), scene, test::textureModeUnderTest(), GlLighting{});
  const AovImages aov = tracer.renderAovs(test::testCamera(kWidth, kHeight), kWidth, kHeight);
  RenderImage image;
  image.width = kWidth, image.height = kHeight, image.samples = samples;
  image.normal = aov.normal, image.depth = aov.depth, image.face = aov.face;
  for (size_t i = 0; i < aov.face.size(); ++i) {
    const int x = int(i % kWidth), y = int(i / kWidth);
    image.albedo.push_back(glm::vec3(aov.albedo[i]));
    const float noise = float((uint32_t(i) * 2654435761u >> 8) % 1000) / 500.0f;
    const float light = 4.0f / (1.0f + 0.002f * float((x - 20) * (x - 20) + (y - 15) * (y - 15)));
    image.beauty.push_back(image.albedo.back() * light * noise);
    // The samples' squared luminance: the mean's square and a spread that varies over the room.
    const float l = 0.2126f * image.beauty.back().x + 0.7152f * image.beauty.back().y + 0.0722f * image.beauty.back().z;
    image.luminanceMoment2.push_back(l * l * (1.0f + 0.5f * noise + 4.0f * float(x > 40)));
  }
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) image.depth[size_t(y) * kWidth + size_t(x)] = INFINITY, image.beauty[size_t(y) * kWidth + size_t(x)] = {};
  image.beauty[size_t(30) * kWidth + 40] = glm::vec3(NAN);
  return image;
}

TEST(GlDenoise, TheShaderGivesTheCpuFiltersImage) {
  GlContext& context = test::sharedGlContext();
  // 2 spp: the variance from the neighbours' spread; 16 and 256: from each pixel's own moment.
  for (int samples : {2, 16, 256}) {
    SCOPED_TRACE(testing::Message() << samples << " spp");
    const RenderImage image = noisyRoom(samples);
    const int errorsBefore = context.debugErrorCount();
    const std::vector<glm::vec3> gpu = denoiseWithGl(image);
    EXPECT_EQ(context.debugErrorCount(), errorsBefore);
    const std::vector<glm::vec3> cpu = denoise(image);
    ASSERT_EQ(gpu.size(), cpu.size());
    // Stated tolerance: 1e-4 of the value (float exp and pow may differ in the last bits between
    // drivers and libm), every channel of every pixel.
    size_t off = 0, changed = 0;
    for (size_t i = 0; i < cpu.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const bool close = std::abs(gpu[i][c] - cpu[i][c]) <= 1e-4f * std::max(1.0f, std::abs(cpu[i][c]));
        if (!close && off++ < 5) ADD_FAILURE() << "pixel " << i << " channel " << c << ": gl " << gpu[i][c] << ", cpu " << cpu[i][c];
      }
      changed += std::abs(cpu[i].x - image.beauty[i].x) > 1e-3f;
    }
    EXPECT_EQ(off, 0u);
    EXPECT_GT(changed, cpu.size() / 2) << "the filter changed the image";
  }
}

// The top-left w x h of `image`, every per-pixel array cut alike.
RenderImage cropped(const RenderImage& image, int w, int h) {
  RenderImage out;
  out.width = w, out.height = h, out.samples = image.samples;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(image.width) + size_t(x);
      out.beauty.push_back(image.beauty[i]), out.albedo.push_back(image.albedo[i]), out.normal.push_back(image.normal[i]);
      out.depth.push_back(image.depth[i]), out.face.push_back(image.face[i]), out.luminanceMoment2.push_back(image.luminanceMoment2[i]);
    }
  return out;
}

// The viewer denoises every frame with one pass, whose images live from one frame to the next:
// each frame must come out as from a pass of its own, after frames of other counts and sizes.
TEST(GlDenoise, AKeptPassGivesEachFrameWhatAFreshOneGives) {
  test::sharedGlContext(); // made current before the pass builds its program
  DenoisePass kept;
  for (const auto& [samples, width, height] :
       {std::tuple{16, kWidth, kHeight}, {2, kWidth, kHeight}, {256, 40, 30}, {16, kWidth, kHeight}}) {
    SCOPED_TRACE(testing::Message() << samples << " spp at " << width << "x" << height);
    const RenderImage image = cropped(noisyRoom(samples), width, height);
    const std::vector<glm::vec3> fresh = denoiseWithGl(image);
    const std::vector<glm::vec3> reused = denoiseWithGl(image, kept);
    ASSERT_EQ(reused.size(), size_t(width) * size_t(height));
    size_t differ = 0;
    for (size_t i = 0; i < fresh.size(); ++i) differ += fresh[i] != reused[i];
    EXPECT_EQ(differ, 0u) << "of " << fresh.size() << " pixels";
  }
}

} // namespace
} // namespace bt::gl
