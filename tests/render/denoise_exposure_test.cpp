// Physical mode's display: automatic exposure (renderer/exposure.h) and the preview denoiser
// (renderer/denoise.h), on a small lit room rendered by the CPU tracer, every pixel in colour.
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/denoise.h"
#include "renderer/denoise_fade.h"
#include "renderer/exposure.h"
#include "renderer/time_to_converged.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <string>

namespace bt {
namespace {

constexpr int kWidth = 48, kHeight = 36; // renderFurnishedRoom's

// The furnished room (tests/render/box_scene.h) at worldspawn `_range` `range`. `sobol`: physical
// mode's Sobol sequence, else PCG alone.
RenderImage renderRoom(const std::string& range, int spp, uint32_t seed = 1, bool bricks = false, bool tinted = false, bool sobol = true) {
  Diagnostics diagnostics;
  const Scene scene = test::furnishedRoom({.range = range, .bricks = bricks, .tinted = tinted});
  const RenderScene rs = buildRenderScene(scene, {}, diagnostics);
  return test::renderFurnishedRoom(rs, spp, seed, sobol);
}

// The 1024-spp reference of the room at _range 0.5, rendered once for the whole program.
const RenderImage& reference() {
  static const RenderImage image = renderRoom("0.5", 1024, 99);
  return image;
}

// Relative MSE over every channel of every pixel, (x - r)^2 / (r^2 + 0.01) (Rousselle et al.'s
// epsilon), on the exposed linear image, the reference's exposure for both.
double relativeMse(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& ref, float exposureEv) {
  const float scale = std::exp2(exposureEv);
  double sum = 0.0;
  for (size_t i = 0; i < ref.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double x = image[i][c] * scale, r = ref[i][c] * scale;
      sum += (x - r) * (x - r) / (r * r + 0.01);
    }
  return sum / double(ref.size() * 3);
}

double displayedMean(const RenderImage& image, float exposureEv) {
  const std::vector<uint8_t> pixels = displayPixels(image, {.aov = Aov::Beauty, .exposureEv = exposureEv, .tonemap = Tonemap::Aces});
  double sum = 0.0;
  for (uint8_t p : pixels) sum += p;
  return sum / double(pixels.size()) / 255.0;
}

TEST(AutoExposure, DarkAndBrightRoomsEndAtTheSameDisplayedMean) {
  // _range 1/16 and 16: the bright room's radiance is 256 times the dark one's (8 EV).
  const RenderImage dark = renderRoom("0.03125", 16), bright = renderRoom("8", 16);
  const float darkEv = autoExposureEv(dark.beauty, kWidth, kHeight), brightEv = autoExposureEv(bright.beauty, kWidth, kHeight);
  EXPECT_NEAR(darkEv - brightEv, 8.0f, 0.01f);
  // Unexposed, one is nearly black and the other blown out: the test can tell them apart.
  EXPECT_GT(displayedMean(bright, 0.0f) - displayedMean(dark, 0.0f), 0.3);
  // Exposed, the PNGs' mean value (every channel, 0..1) agrees within 1/255.
  const double darkMean = displayedMean(dark, darkEv), brightMean = displayedMean(bright, brightEv);
  EXPECT_NEAR(darkMean, brightMean, 1.0 / 255.0);
  // And middle grey lands in the middle of the display, not at its ends.
  EXPECT_GT(darkMean, 0.2);
  EXPECT_LT(darkMean, 0.8);
}

TEST(AutoExposure, IgnoresBlackNanAndInfinitePixels) {
  std::vector<glm::vec3> image(32 * 16, glm::vec3(0.18f));
  EXPECT_NEAR(autoExposureEv(image, 32, 16), 0.0f, 1e-5f);
  for (int y = 0; y < 16; ++y)
    for (int x = 16; x < 32; ++x) image[size_t(y) * 32 + size_t(x)] = glm::vec3(0.0f); // the void beside the level
  image[3] = glm::vec3(NAN);
  image[40] = glm::vec3(INFINITY);
  EXPECT_NEAR(autoExposureEv(image, 32, 16), 0.0f, 1e-5f);
  EXPECT_EQ(autoExposureEv(std::vector<glm::vec3>(64, glm::vec3(0.0f)), 8, 8), 0.0f); // all black: 0 EV
  // 0.045 is two stops below the key.
  EXPECT_NEAR(autoExposureEv(std::vector<glm::vec3>(64, glm::vec3(0.045f)), 8, 8), 2.0f, 1e-5f);
}

TEST(AutoExposure, SmootherFollowsWithoutJumping) {
  ExposureSmoother s;
  EXPECT_TRUE(s.due(0.0));
  EXPECT_EQ(s.update(2.0f, 0.0), 2.0f); // the first measurement is taken as it is
  EXPECT_FALSE(s.due(0.1));
  const float next = s.update(4.0f, ExposureSmoother::kInterval);
  EXPECT_GT(next, 2.0f);
  EXPECT_LT(next, 3.0f); // a quarter second moves it less than half way
  float ev = next;
  for (int i = 2; i < 40; ++i) ev = s.update(4.0f, i * ExposureSmoother::kInterval);
  EXPECT_NEAR(ev, 4.0f, 0.01f);
}

TEST(Denoise, FourSppDenoisedIsCloserToTheReferenceThanRaw) {
  const RenderImage noisy = renderRoom("0.5", 4);
  const float ev = autoExposureEv(reference().beauty, kWidth, kHeight);
  const double raw = relativeMse(noisy.beauty, reference().beauty, ev);
  const double denoised = relativeMse(denoise(noisy), reference().beauty, ev);
  RecordProperty("raw_rel_mse", std::to_string(raw));
  RecordProperty("denoised_rel_mse", std::to_string(denoised));
  // Stated: at least 5 times closer (measured here: 0.357 raw, 0.034 denoised; 0.048 with the
  // filter before the variance-guided one).
  EXPECT_LT(denoised * 5.0, raw) << "raw " << raw << ", denoised " << denoised;
}

// The variance-guided filter (each pixel smoothed by its own noise, from the tracer's second
// moment) against the filter it replaced (the noise assumed 1 / sqrt(spp) everywhere): the
// mean relative MSE of three 4-spp renders (seeds 1-3), denoised, against the reference.
TEST(Denoise, VarianceGuidedIsCloserThanTheOldFilter) {
  const float ev = autoExposureEv(reference().beauty, kWidth, kHeight);
  double raw = 0.0, denoised = 0.0;
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const RenderImage noisy = renderRoom("0.5", 4, seed);
    ASSERT_EQ(noisy.luminanceMoment2.size(), noisy.beauty.size()) << "the tracer keeps the second moment";
    raw += relativeMse(noisy.beauty, reference().beauty, ev) / 3.0;
    denoised += relativeMse(denoise(noisy), reference().beauty, ev) / 3.0;
  }
  RecordProperty("raw_rel_mse", std::to_string(raw));
  RecordProperty("denoised_rel_mse", std::to_string(denoised));
  std::printf("lit room, 4 spp: raw %.4f, denoised %.4f\n", raw, denoised);
  // Stated: below the old filter's 0.0507 (measured on these renders at fd4f78d; here 0.033).
  EXPECT_LT(denoised, 0.0507) << "raw " << raw;
}

TEST(Denoise, ConvergedImageIsNearlyUnchanged) {
  const float ev = autoExposureEv(reference().beauty, kWidth, kHeight);
  const double change = relativeMse(denoise(reference()), reference().beauty, ev);
  // The reference's own noise: two 1024-spp renders of other seeds differ by twice its variance.
  const double ownNoise = relativeMse(renderRoom("0.5", 1024, 5).beauty, reference().beauty, ev) / 2.0;
  // Stated: the filter changes a converged image by less than the noise it still has, and by
  // less than a relative MSE of 1e-3 (measured here: 0.00093 against a noise of 0.0012; 0.0006
  // with the filter before the variance-guided one).
  RecordProperty("change_rel_mse", std::to_string(change));
  RecordProperty("own_noise_rel_mse", std::to_string(ownNoise));
  EXPECT_LT(change, ownNoise) << change;
  EXPECT_LT(change, 1e-3) << change;
}

// Issue 18: past the young image's few samples the denoiser must not add error of its own. At
// 256 spp (a quarter of the reference's), the mean of three seeds: the lit room denoised is no
// farther from its reference than raw; with brick textures finer than a pixel on every wall (where
// the centre's albedo misleads the demodulation most) at most 1.25 times as far (measured: 1.04
// with the shrink per channel, 1.15 with it on the luminance, 13 times before the shrink toward
// the raw mean, BT_DENOISE_SHRINK_FROM).
TEST(Denoise, AtHighSppTheDenoisedImageIsNoFartherFromTheReferenceThanRaw) {
  for (const bool bricks : {false, true}) {
    const RenderImage reference = bricks ? renderRoom("0.5", 1024, 99, true) : bt::reference();
    const float ev = autoExposureEv(reference.beauty, kWidth, kHeight);
    double raw = 0.0, denoised = 0.0;
    for (uint32_t seed = 11; seed <= 13; ++seed) {
      const RenderImage noisy = renderRoom("0.5", 256, seed, bricks);
      raw += relativeMse(noisy.beauty, reference.beauty, ev) / 3.0;
      denoised += relativeMse(denoise(noisy), reference.beauty, ev) / 3.0;
    }
    RecordProperty(bricks ? "bricks_raw_rel_mse" : "raw_rel_mse", std::to_string(raw));
    RecordProperty(bricks ? "bricks_denoised_rel_mse" : "denoised_rel_mse", std::to_string(denoised));
    std::printf("lit room%s, 256 spp: raw %.5f, denoised %.5f\n", bricks ? " of bricks" : "", raw, denoised);
    EXPECT_LE(denoised, (bricks ? 1.25 : 1.0) * raw) << (bricks ? "bricks" : "plain walls");
  }
}

// Issue 18, session 21: the image the viewer displays at 64 and 256 spp (displayedBeauty, the
// bench's "denoiser on"), as its PNG shows it (auto exposure, ACES, sRGB), against the reference's,
// on the room of tinted bricks: the mean relative MSE of three seeds. The shrink toward the raw
// mean per channel keeps the hue a pixel's samples saw where the luminance alone did not, and the
// fade keeps the denoised image to 256 spp. With PCG's noise, the noise the shrink and the fade
// were tuned on: with the Sobol sequence (session 24) the raw image is so much closer (0.00211 at
// 256 spp, PCG's 0.00368) that the denoised one is the farther (0.00242; 0.00645 against 0.00637
// at 64 spp), though closer than PCG's (bench/README.md, issue 18 session 24).
TEST(Denoise, DisplayedImageOfTintedBricksIsCloserThanSession20s) {
  const RenderImage reference = renderRoom("0.5", 1024, 99, true, true, false);
  const std::vector<glm::vec3> referenceDisplay = displayedImage(reference.beauty, autoExposureEv(reference.beauty, kWidth, kHeight));
  for (const int spp : {64, 256}) {
    double raw = 0.0, displayed = 0.0;
    for (uint32_t seed = 31; seed <= 33; ++seed) {
      const RenderImage noisy = renderRoom("0.5", spp, seed, true, true, false);
      const float ev = autoExposureEv(noisy.beauty, kWidth, kHeight);
      raw += bt::relativeMse(displayedImage(noisy.beauty, ev), referenceDisplay) / 3.0;
      const std::vector<glm::vec3> shown = displayedBeauty(noisy.beauty, denoise(noisy), spp);
      displayed += bt::relativeMse(displayedImage(shown, ev), referenceDisplay) / 3.0;
    }
    RecordProperty("raw_rel_mse_" + std::to_string(spp) + "spp", std::to_string(raw));
    RecordProperty("displayed_rel_mse_" + std::to_string(spp) + "spp", std::to_string(displayed));
    std::printf("tinted bricks, %d spp: raw %.5f, displayed %.5f\n", spp, raw, displayed);
    // Stated: the displayed image closer than the raw one (measured: 0.0091 against 0.0098 at 64
    // spp, 0.00361 against 0.00368 at 256; session 20's filter and fade 0.0118 and 0.00438,
    // farther than raw at both).
    EXPECT_LT(displayed, raw) << spp << " spp";
  }
}

// Issue 18, session 22: the image displayed at 8 spp on the room of bricks whose mortar is nearly
// black (albedo about 0.02 in each channel), as its PNG shows it, the mean relative MSE of three
// seeds. Demodulation divided by the albedo floored at 0.01 (session 21), so the mortar's light
// that its albedo does not scale (a dielectric's 4 % specular reflection) became irradiance many
// times its neighbours', which the filter spread; dividing by the albedo plus 0.01 it does less.
// At 8 spp the last step has no second moment to draw a pixel back toward its raw mean
// (BT_DENOISE_SHRINK_FROM), so the filter's own bias shows in full: on these bricks the denoised
// image is farther from the reference than raw (0.17 against 0.059), as lq_e4m3's is not (0.070
// against 0.161; bench/README.md, issue 18 session 22).
TEST(Denoise, DisplayedImageOfDarkMortarIsCloserThanSession21s) {
  const RenderImage reference = renderRoom("0.5", 1024, 99, true);
  const std::vector<glm::vec3> referenceDisplay = displayedImage(reference.beauty, autoExposureEv(reference.beauty, kWidth, kHeight));
  double raw = 0.0, displayed = 0.0;
  for (uint32_t seed = 41; seed <= 43; ++seed) {
    const RenderImage noisy = renderRoom("0.5", 8, seed, true);
    const float ev = autoExposureEv(noisy.beauty, kWidth, kHeight);
    raw += bt::relativeMse(displayedImage(noisy.beauty, ev), referenceDisplay) / 3.0;
    displayed += bt::relativeMse(displayedImage(displayedBeauty(noisy.beauty, denoise(noisy), 8), ev), referenceDisplay) / 3.0;
  }
  RecordProperty("raw_rel_mse", std::to_string(raw));
  RecordProperty("displayed_rel_mse", std::to_string(displayed));
  std::printf("dark mortar, 8 spp: raw %.5f, displayed %.5f\n", raw, displayed);
  // Stated: below 0.19 (measured: 0.174; session 21's floor 0.210, and at 64 spp 0.01446 against
  // its 0.01483, raw 0.01449).
  EXPECT_LT(displayed, 0.19) << "raw " << raw;
}

// Two planes side by side, a bright one (x < 24, depth 100, facing the camera) and a dark one
// (`darkDepth`, `darkNormal`), both noisy, denoised. Stated for the dark plane: no pixel, the
// one beside the edge included (0 pixels of bleeding), gets more than 0.1 % of the bright
// plane's light; and the bright plane is smoothed (the filter does something): its noise
// drops at least 4x.
void expectNoBleeding(float darkDepth, const glm::vec3& darkNormal) {
  RenderImage image;
  image.width = 48, image.height = 32, image.samples = 4;
  const size_t n = size_t(image.width) * size_t(image.height);
  image.beauty.resize(n), image.albedo.assign(n, glm::vec3(0.5f)), image.normal.resize(n);
  image.depth.resize(n), image.face.resize(n);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const size_t i = size_t(y) * size_t(image.width) + size_t(x);
      const bool bright = x < 24;
      const float noise = float((i * 2654435761u >> 8) % 1000) / 500.0f; // 0..2, mean 1
      image.beauty[i] = glm::vec3(bright ? 1.0f : 0.01f) * noise;
      image.depth[i] = bright ? 100.0f : darkDepth;
      image.normal[i] = bright ? glm::vec3(0, 0, -1) : darkNormal;
      image.face[i] = bright ? 1 : 2;
    }
  const std::vector<glm::vec3> out = denoise(image);
  for (int y = 0; y < image.height; ++y)
    for (int x = 24; x < image.width; ++x) {
      const size_t i = size_t(y) * size_t(image.width) + size_t(x);
      EXPECT_LT(out[i].x, 0.02f + 0.001f) << "pixel " << x << "," << y;
    }
  double rawVar = 0.0, outVar = 0.0;
  for (int y = 4; y < image.height - 4; ++y)
    for (int x = 4; x < 20; ++x) {
      const size_t i = size_t(y) * size_t(image.width) + size_t(x);
      rawVar += (image.beauty[i].x - 1.0) * (image.beauty[i].x - 1.0);
      outVar += (out[i].x - 1.0) * (out[i].x - 1.0);
    }
  EXPECT_LT(outVar * 4.0, rawVar);
}

// The dark plane behind (depth 400), the same normal: only depth tells them apart, as at a
// pillar's silhouette.
TEST(Denoise, NoBleedingAcrossADepthDiscontinuity) {
  expectNoBleeding(400.0f, glm::vec3(0, 0, -1));
}

// The dark plane at the same depth, square to the bright one: only the normal tells them
// apart, as where a wall meets the floor.
TEST(Denoise, NoBleedingAcrossACrease) {
  expectNoBleeding(100.0f, glm::vec3(1, 0, 0));
}

// The bench's "denoiser on" figure is the image the viewer displays (displayedBeauty: the
// denoised image while young, faded to the raw one as samples accumulate), not the denoiser's
// output at full strength: each step's figure against the displayed image made here.
TEST(TimeToConverged, MeasuresTheDisplayedImage) {
  // Any reference does for the arithmetic: a 16-spp one of another seed, whose own noise keeps
  // every step above the threshold (so every step is measured) while raw and denoised images
  // still score apart.
  const RenderImage noisyReference = renderRoom("0.5", 16, 77);
  const std::vector<glm::vec3> referenceDisplay =
      displayedImage(noisyReference.beauty, autoExposureEv(noisyReference.beauty, kWidth, kHeight));
  ConvergeSettings settings;
  settings.fade = {16, 64};                      // the viewer tests' short fade: the test renders to 32 spp, not 512
  settings.maxSpp = 2 * settings.fade.fullUntil; // into the fade, where the two images differ
  settings.denoiser = [](const RenderImage& image) { return denoise(image); };
  const auto render = [](int spp) { return renderRoom("0.5", spp, 21); };
  const std::vector<ConvergeStep> steps = timeToConverged(render, referenceDisplay, settings);
  ASSERT_EQ(steps.back().spp, settings.maxSpp);
  bool fadeSeen = false;
  for (const ConvergeStep& step : steps) {
    const RenderImage image = render(step.spp); // the same seed and spp: the same image
    const float ev = autoExposureEv(image.beauty, kWidth, kHeight);
    const std::vector<glm::vec3> denoised = denoise(image);
    std::vector<glm::vec3> shown(image.beauty.size());
    const DenoiseFade& fade = settings.fade;
    const float share = step.spp <= fade.fullUntil ? 1.0f
        : step.spp >= fade.goneAt                  ? 0.0f
                                                   : float(fade.goneAt - step.spp) / float(fade.goneAt - fade.fullUntil);
    for (size_t i = 0; i < shown.size(); ++i) shown[i] = share * denoised[i] + (1.0f - share) * image.beauty[i];
    const double expected = bt::relativeMse(displayedImage(shown, ev), referenceDisplay);
    EXPECT_NEAR(step.relativeMseDisplayed, expected, 1e-9 + 1e-6 * expected) << step.spp << " spp";
    if (step.spp >= fade.goneAt) {
      EXPECT_NEAR(step.relativeMseDisplayed, step.relativeMse, 1e-12) << step.spp << " spp: not the raw image";
    }
    if (share < 1.0f) fadeSeen |= std::abs(step.relativeMseDenoised - expected) > 1e-3 * expected;
  }
  EXPECT_TRUE(fadeSeen) << "the denoised image at full strength scores as the displayed one: the test cannot tell them apart";
}

// The sweep's sample counts: every power of two and the half-octave between, so that the time it
// reports is at most 1.41 times the time at which the display first passes the threshold.
TEST(TimeToConverged, StepsByHalfOctaves) {
  EXPECT_EQ(convergeSteps(256), (std::vector<int>{1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256}));
  EXPECT_EQ(convergeSteps(100), (std::vector<int>{1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 91}));
  EXPECT_EQ(convergeSteps(1), (std::vector<int>{1}));
  for (const int spp : {4, 16, 4096}) {
    const std::vector<int> steps = convergeSteps(spp);
    for (size_t i = 2; i < steps.size(); ++i) EXPECT_LE(double(steps[i]), 1.5 * double(steps[i - 1])) << steps[i];
  }
}

// The viewer shows every sample count, so the bench reports the first count within the
// threshold, not the next half-octave: an image whose error falls with the count as a known
// function, every count measured by hand, against what the sweep finds by bisection.
TEST(TimeToConverged, FindsTheFirstCountWithinTheThresholdBetweenHalfOctaves) {
  constexpr int kSide = 16;
  std::vector<glm::vec3> reference(size_t(kSide) * kSide);
  for (size_t i = 0; i < reference.size(); ++i) reference[i] = glm::vec3(0.05f + 0.9f * float(i) / float(reference.size()));
  const std::vector<glm::vec3> referenceDisplay = displayedImage(reference, autoExposureEv(reference, kSide, kSide));
  int renders = 0;
  const auto render = [&](int spp) {
    ++renders;
    RenderImage image;
    image.width = image.height = kSide, image.samples = spp;
    image.beauty = reference;
    const float amplitude = 7.0f / float(spp); // the error falls as 1 / spp^2
    for (size_t i = 0; i < image.beauty.size(); ++i) image.beauty[i] *= 1.0f + ((i + i / kSide) % 2 ? amplitude : -0.5f * amplitude);
    return image;
  };
  const auto error = [&](int spp) {
    const RenderImage image = render(spp);
    return bt::relativeMse(displayedImage(image.beauty, autoExposureEv(image.beauty, kSide, kSide)), referenceDisplay);
  };
  int first = 1;
  while (error(first) > kConvergedRelativeMse) ++first;
  const std::vector<int> halfOctaves = convergeSteps(256);
  ASSERT_EQ(std::find(halfOctaves.begin(), halfOctaves.end(), first), halfOctaves.end())
      << first << " spp is a half-octave: the test cannot tell a bisection from the sweep";
  ConvergeSettings settings;
  settings.maxSpp = 256;
  renders = 0;
  const std::vector<ConvergeStep> steps = timeToConverged(render, referenceDisplay, settings);
  const auto within =
      std::find_if(steps.begin(), steps.end(), [](const ConvergeStep& s) { return s.relativeMse <= kConvergedRelativeMse; });
  ASSERT_NE(within, steps.end());
  EXPECT_EQ(within->spp, first) << "the first count within the threshold";
  ASSERT_NE(within, steps.begin());
  EXPECT_EQ(std::prev(within)->spp, first - 1) << "the count before it, measured above the threshold";
  for (size_t i = 1; i < steps.size(); ++i) EXPECT_LT(steps[i - 1].spp, steps[i].spp) << "steps in order of spp";
  EXPECT_EQ(renders, int(steps.size()));
  std::printf("first count within the threshold: %d spp, found in %d renders\n", first, renders);
}

// The time-to-converged bench's diagnostic: error spread evenly gives the worst 1 % of pixels
// about 1 % of it; one firefly on an otherwise exact image gives them all of it.
TEST(TimeToConverged, WorstPercentShareTellsEvenNoiseFromAFirefly) {
  const std::vector<glm::vec3> reference(10000, glm::vec3(0.5f));
  std::vector<glm::vec3> even = reference, firefly = reference;
  for (size_t i = 0; i < even.size(); ++i) even[i] += glm::vec3(i % 2 ? 0.01f : -0.01f);
  firefly[1234] = glm::vec3(1.0f);
  EXPECT_NEAR(worstPercentShare(even, reference), 0.01, 1e-6);
  EXPECT_NEAR(worstPercentShare(firefly, reference), 1.0, 1e-9);
  EXPECT_EQ(worstPercentShare(reference, reference), 0.0);
}

} // namespace
} // namespace bt
