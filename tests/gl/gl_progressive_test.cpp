// The viewer's GPU side: the progressive sum kept on the GPU and the tonemap pass that turns it
// into the displayed RGBA8 image, against renderBeauty and the CPU's PNG bytes.
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_progressive.h"
#include "tests/gl/test_scenes.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <cstdlib>

namespace bt::gl {
namespace {

// Linear radiance from black through the sRGB toe (below 0.0031308) to 16x overbright, on a
// log scale, each channel its own phase so that the operators' channel mixing (AgX) is seen.
std::vector<glm::vec3> radianceRamp(int width, int height) {
  std::vector<glm::vec3> pixels(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < pixels.size(); ++i) {
    const float t = static_cast<float>(i) / static_cast<float>(pixels.size() - 1);
    auto ev = [](float u) { return u <= 0.02f ? 0.0f : std::exp2(-14.0f + 18.0f * u); };
    pixels[i] = {ev(t), ev(std::fmod(t + 0.37f, 1.0f)), ev(std::fmod(t + 0.71f, 1.0f))};
  }
  return pixels;
}

TEST(GlTonemap, EqualsTheCpusPngBytesForEveryOperatorWithin1Of255) {
  test::sharedGlContext();
  constexpr int kWidth = 64, kHeight = 32, kSamples = 5;
  const std::vector<glm::vec3> mean = radianceRamp(kWidth, kHeight);
  // The sum of kSamples samples, as the path tracer leaves it.
  std::vector<float> sum(mean.size() * 4);
  for (size_t i = 0; i < mean.size(); ++i)
    for (int c = 0; c < 3; ++c) sum[4 * i + c] = mean[i][c] * kSamples;
  GlTexture2D sumTexture(GL_RGBA32F, kWidth, kHeight);
  BT_GL(glTextureSubImage2D(sumTexture.id(), 0, 0, 0, kWidth, kHeight, GL_RGBA, GL_FLOAT, sum.data()));
  GlTexture2D display(GL_RGBA8, kWidth, kHeight);
  TonemapPass pass;

  RenderImage image;
  image.width = kWidth;
  image.height = kHeight;
  image.beauty = mean;
  for (Tonemap tonemap : {Tonemap::Faithful, Tonemap::Aces, Tonemap::Agx, Tonemap::Linear}) {
    for (float exposureEv : {0.0f, -1.5f}) {
      SCOPED_TRACE(testing::Message() << "tonemap " << static_cast<int>(tonemap) << ", exposure " << exposureEv);
      pass.run(sumTexture, kSamples, display, tonemap, exposureEv);
      const std::vector<uint8_t> gpu = readRgba8(display);
      const std::vector<uint8_t> cpu = displayPixels(image, {.aov = Aov::Beauty, .exposureEv = exposureEv, .tonemap = tonemap});
      int worst = 0, distinct = 0;
      for (size_t i = 0; i < mean.size(); ++i) {
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(gpu[4 * i + c]) - int(cpu[3 * i + c])));
        EXPECT_EQ(gpu[4 * i + 3], 255);
        distinct += i > 0 && cpu[3 * i] != cpu[3 * (i - 1)];
      }
      EXPECT_LE(worst, 1) << "a channel differs from the CPU's by more than 1/255";
      EXPECT_GT(distinct, 100) << "the ramp should cover the operator's range, not sit at one value";
    }
  }
}

class GlProgressiveTest : public ::testing::Test {
protected:
  static constexpr int kWidth = 48, kHeight = 32;
  // The context first: each test makes GL objects before it asks for the tracer, and ctest runs
  // each test in a process of its own.
  void SetUp() override { test::sharedGlContext(); }
  // The room lit by one point light, physical with a bounce: every sample is noisy, so a sample
  // drawn from the wrong stream, or added to a stale sum, shows.
  GlTracer& tracer() {
    if (!tracer_) {
      GlLighting lighting;
      GpuLight light;
      light.origin = {-100, 0, 200};
      light.value = 300.0f;
      lighting.lights = {light};
      tracer_ = std::make_unique<GlTracer>(test::sharedGlContext(), scene_, test::textureModeUnderTest(), lighting);
    }
    return *tracer_;
  }
  BeautySettings settings(int spp) const { return {.width = kWidth, .height = kHeight, .spp = spp, .physical = true, .bounces = 1}; }
  static void expectClose(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    ASSERT_EQ(a.size(), b.size());
    double worst = 0.0, total = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
      worst = std::max(worst, double(glm::length(a[i] - b[i]) / std::max(1e-3f, glm::length(b[i]))));
      total += glm::length(b[i]);
    }
    EXPECT_LT(worst, 1e-4) << "relative difference per pixel";
    EXPECT_GT(total / a.size(), 0.01) << "the image is black: nothing was compared";
  }

  Scene scene_ = test::makeTestRoom();
  std::unique_ptr<GlTracer> tracer_;
};

TEST_F(GlProgressiveTest, SamplesAddedOneByOneSumRenderBeautysImage) {
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  ProgressiveImage progressive(kWidth, kHeight);
  for (int i = 0; i < 3; ++i) progressive.addSample(tracer(), camera, settings(1));
  EXPECT_EQ(progressive.samples(), 3);
  expectClose(progressive.readMean(), tracer().renderBeauty(camera, settings(3)).beauty);
}

TEST_F(GlProgressiveTest, RestartDropsTheOldSum) {
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  CameraBasis elsewhere = camera;
  elsewhere.origin += glm::vec3(0, 64, -32);
  ProgressiveImage progressive(kWidth, kHeight);
  for (int i = 0; i < 2; ++i) progressive.addSample(tracer(), elsewhere, settings(1));
  progressive.restart();
  progressive.addSample(tracer(), camera, settings(1));
  progressive.addSample(tracer(), camera, settings(1));
  expectClose(progressive.readMean(), tracer().renderBeauty(camera, settings(2)).beauty);
}

// Where the GL is slow the viewer draws a pass in pieces (ProgressiveImage::addPiece), one a
// frame. Cut every way the viewer may cut it (parts of a row of groups, whole rows, the rest of a
// row, single groups), in an image whose sides are not multiples of the groups', n passes sum
// the image of n whole passes, every pixel bit for bit, with either form of the path tracer.
// Between pieces, the pixels the pass under way has reached show n + 1 samples and the others
// n: no pixel is divided by another count than its own, so the window never shows a half-added
// pass darker or brighter than it is. (One test: each pays llvmpipe's compile of the programs.)
TEST_F(GlProgressiveTest, PassesDrawnInPiecesSumTheImageOfWholePassesExactly) {
  constexpr int kOddWidth = 52, kOddHeight = 27, kPasses = 3;
  const CameraBasis camera = test::testCamera(kOddWidth, kOddHeight);
  constexpr size_t kGroup = size_t(kPieceAlignment) * kPieceAlignment;
  const size_t rowOfGroups = kGroup * 7; // 52 pixels: 7 groups across
  const size_t cuts[] = {kGroup, 200, 2 * rowOfGroups + 100, 1, 5 * kGroup, 3 * rowOfGroups};
  for (const PathTracerForm form : {PathTracerForm::Megakernel, PathTracerForm::Wavefront}) {
    SCOPED_TRACE(form == PathTracerForm::Megakernel ? "megakernel" : "wavefront");
    BeautySettings one = settings(1);
    one.form = form;
    ProgressiveImage whole(kOddWidth, kOddHeight), cut(kOddWidth, kOddHeight);
    std::vector<std::vector<glm::vec3>> wholeMeans; // after 0, 1, ... passes
    for (int i = 0; i < kPasses; ++i) wholeMeans.push_back(whole.readMean()), whole.addSample(tracer(), camera, one);
    wholeMeans.push_back(whole.readMean());
    int pieces = 0, underWayChecked = 0;
    while (cut.samples() < kPasses) {
      cut.addPiece(tracer(), camera, one, cuts[pieces++ % std::size(cuts)]);
      const std::vector<PixelRect> done = cut.donePieces();
      if (done.empty()) continue;
      // A pass under way: the pixels it reached against n + 1 whole passes, the others against n.
      const std::vector<glm::vec3> mean = cut.readMean(), &before = wholeMeans[size_t(cut.samples())],
                                   &after = wholeMeans[size_t(cut.samples()) + 1];
      int wrong = 0;
      size_t reachedPixels = 0;
      for (int y = 0; y < kOddHeight; ++y)
        for (int x = 0; x < kOddWidth; ++x) {
          const bool reached = std::any_of(done.begin(), done.end(), [&](const PixelRect& r) {
            return x >= r.x && x < r.x + r.width && y >= r.y && y < r.y + r.height;
          });
          const size_t i = size_t(y) * kOddWidth + x;
          wrong += mean[i] != (reached ? after[i] : before[i]);
          reachedPixels += reached;
        }
      EXPECT_EQ(wrong, 0) << "pixels shown with another count than their own, " << reachedPixels << " reached";
      ++underWayChecked;
    }
    EXPECT_GT(pieces, 3 * kPasses) << "the passes were not cut";
    EXPECT_GT(underWayChecked, 3) << "no pass was seen under way";
    const std::vector<glm::vec3>& expected = wholeMeans.back();
    const std::vector<glm::vec3> got = cut.readMean();
    ASSERT_EQ(got.size(), expected.size());
    int differ = 0;
    for (size_t i = 0; i < got.size(); ++i) differ += got[i] != expected[i];
    EXPECT_EQ(differ, 0) << "pixels that differ from the whole passes' image";
    expectClose(got, expected); // and the image is not black
  }
}

} // namespace
} // namespace bt::gl
