// halves_lab REF.exr A.exr B.exr: two renders of the same view, of different seeds (two
// independent scrambles of the Sobol sequence), taken as the halves of one image of twice their
// samples; denoises it with the variance of each pixel's mean from its second moment (main) and
// from the halves' difference, and prints the displayed relative MSE of both (issue 18).
#include "renderer/denoise.h"
#include "renderer/denoise_fade.h"
#include "renderer/exposure.h"
#include "renderer/image_output.h"
#include "renderer/time_to_converged.h"

#include <fmt/format.h>

#include <cmath>

int main(int argc, char** argv) {
  if (argc < 4) {
    fmt::print(stderr, "usage: halves_lab REF.exr A.exr B.exr\n");
    return 2;
  }
  const bt::RenderImage reference = bt::readExrImage(argv[1]);
  const auto referenceDisplay =
      bt::displayedImage(reference.beauty, bt::autoExposureEv(reference.beauty, reference.width, reference.height));
  const bt::RenderImage a = bt::readExrImage(argv[2]), b = bt::readExrImage(argv[3]);
  bt::RenderImage whole = a;
  const int n = 2 * a.samples;
  whole.samples = n;
  for (size_t i = 0; i < whole.beauty.size(); ++i) {
    whole.beauty[i] = 0.5f * (a.beauty[i] + b.beauty[i]);
    whole.luminanceMoment2[i] = 0.5f * (a.luminanceMoment2[i] + b.luminanceMoment2[i]);
  }
  const float ev = bt::autoExposureEv(whole.beauty, whole.width, whole.height);
  const auto report = [&](const char* name, const bt::RenderImage& image) {
    const auto denoised = bt::denoise(image);
    const auto shown = bt::displayedImage(bt::displayedBeauty(image.beauty, denoised, image.samples), ev);
    fmt::print("{:4} spp {:8}: raw {:.4f} displayed {:.4f}\n", n, name,
               bt::relativeMse(bt::displayedImage(image.beauty, ev), referenceDisplay), bt::relativeMse(shown, referenceDisplay));
  };
  report("moment", whole);
  // The halves: var(mean) = ((la - lb) / 2)^2, handed to the denoiser as the second moment that
  // gives it: m2 = mean^2 + var (n - 1).
  bt::RenderImage halves = whole;
  double ratio = 0.0;
  int counted = 0;
  for (size_t i = 0; i < whole.beauty.size(); ++i) {
    const float mean = bt::luminance(whole.beauty[i]), d = 0.5f * (bt::luminance(a.beauty[i]) - bt::luminance(b.beauty[i]));
    const float momentVariance = bt::meanVariance(whole.luminanceMoment2[i], mean, n);
    halves.luminanceMoment2[i] = mean * mean + d * d * float(n - 1);
    if (momentVariance > 0.0f) ratio += double(d * d / momentVariance), ++counted;
  }
  fmt::print("            mean of halves' variance / moment's variance: {:.3f}\n", ratio / std::max(counted, 1));
  report("halves", halves);
  // The halves as a local calibration of the moment: each pixel's moment variance times the ratio
  // of the halves' to the moment's variance summed over a (2R+1)^2 window.
  constexpr int R = 3;
  bt::RenderImage calibrated = whole;
  const int w = whole.width, h = whole.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sh = 0.0, sm = 0.0;
      for (int dy = -R; dy <= R; ++dy)
        for (int dx = -R; dx <= R; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const size_t q = size_t(qy) * size_t(w) + size_t(qx);
          if (!std::isfinite(whole.depth[q])) continue;
          const float mean = bt::luminance(whole.beauty[q]), d = 0.5f * (bt::luminance(a.beauty[q]) - bt::luminance(b.beauty[q]));
          if (!std::isfinite(whole.luminanceMoment2[q]) || !std::isfinite(d)) continue;
          sh += double(d) * double(d), sm += double(bt::meanVariance(whole.luminanceMoment2[q], mean, n));
        }
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const float mean = bt::luminance(whole.beauty[i]);
      const float k = sm > 0.0 ? float(sh / sm) : 1.0f;
      calibrated.luminanceMoment2[i] = mean * mean + bt::meanVariance(whole.luminanceMoment2[i], mean, n) * k * float(n - 1);
    }
  report("calib", calibrated);
  return 0;
}
