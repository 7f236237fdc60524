#include "renderer/time_to_converged.h"

#include "renderer/denoise_fade.h"
#include "renderer/exposure.h"
#include "renderer/tonemap.h"
#include "scene/color.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <cstdio>
#include <iterator>
#include <numbers>
#include <string>

namespace bt {

namespace {

// One pixel's share of the relative MSE, summed over its channels.
double pixelError(const glm::vec3& image, const glm::vec3& reference) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double x = image[c], r = reference[c];
    sum += (x - r) * (x - r) / (r * r + 0.01);
  }
  return sum;
}

} // namespace

double relativeMse(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference) {
  double sum = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) sum += pixelError(image[i], reference[i]);
  return reference.empty() ? 0.0 : sum / double(reference.size() * 3);
}

double worstPercentShare(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference) {
  std::vector<double> perPixel(reference.size());
  double total = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) total += perPixel[i] = pixelError(image[i], reference[i]);
  const size_t worst = std::max<size_t>(1, perPixel.size() / 100);
  if (perPixel.size() < worst || total <= 0.0) return 0.0;
  std::nth_element(perPixel.begin(), perPixel.begin() + std::ptrdiff_t(worst), perPixel.end(), std::greater<>());
  double share = 0.0;
  for (size_t i = 0; i < worst; ++i) share += perPixel[i];
  return share / total;
}

std::vector<glm::vec3> displayedImage(const std::vector<glm::vec3>& linear, float exposureEv) {
  const float scale = std::exp2(exposureEv);
  std::vector<glm::vec3> out(linear.size());
  for (size_t i = 0; i < linear.size(); ++i) out[i] = linearToSrgb(applyTonemap(Tonemap::Aces, linear[i] * scale));
  return out;
}

std::vector<int> convergeSteps(int maxSpp) {
  std::vector<int> spps;
  for (int power = 1; power <= maxSpp; power *= 2) {
    spps.push_back(power);
    const int between = int(std::lround(double(power) * std::numbers::sqrt2));
    if (between > power && between < 2 * power && between <= maxSpp) spps.push_back(between);
  }
  return spps;
}

std::vector<ConvergeStep> timeToConverged(const std::function<RenderImage(int spp)>& render, const std::vector<glm::vec3>& referenceDisplay,
                                          const ConvergeSettings& settings) {
  using Clock = std::chrono::steady_clock;
  const auto secondsSince = [](Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); };
  const auto measure = [&](int spp) {
    ConvergeStep step;
    step.spp = spp;
    auto start = Clock::now();
    const RenderImage image = render(spp);
    step.seconds = secondsSince(start);
    const float ev = autoExposureEv(image.beauty, image.width, image.height);
    const std::vector<glm::vec3> shown = displayedImage(image.beauty, ev);
    step.relativeMse = relativeMse(shown, referenceDisplay);
    step.worstShare = worstPercentShare(shown, referenceDisplay);
    if (settings.denoiser) {
      start = Clock::now();
      const std::vector<glm::vec3> denoised = settings.denoiser(image);
      // The viewer skips the denoiser once its share is 0; so does the time.
      step.denoiseSeconds = denoiseShare(image.samples, settings.fade) > 0.0f ? secondsSince(start) : 0.0;
      const std::vector<glm::vec3> shownDenoised = displayedImage(denoised, ev);
      step.relativeMseDenoised = relativeMse(shownDenoised, referenceDisplay);
      step.worstShareDenoised = worstPercentShare(shownDenoised, referenceDisplay);
      step.relativeMseDisplayed =
          relativeMse(displayedImage(displayedBeauty(image.beauty, denoised, image.samples, settings.fade), ev), referenceDisplay);
    }
    if (settings.onStep) settings.onStep(step);
    return step;
  };
  const auto rawThere = [](const ConvergeStep& s) { return s.relativeMse <= kConvergedRelativeMse; };
  const auto displayedThere = [&](const ConvergeStep& s) { return !settings.denoiser || s.relativeMseDisplayed <= kConvergedRelativeMse; };
  std::vector<ConvergeStep> steps;
  for (const int spp : convergeSteps(settings.maxSpp)) {
    steps.push_back(measure(spp));
    if (rawThere(steps.back()) && displayedThere(steps.back())) break;
  }
  if (!settings.refine) return steps;
  // The viewer shows every count between two steps, so each measure's first step within the
  // threshold is bisected down against the step before it: the figure is the first count the
  // display shows within it (to one sample, as far as the error falls with the count).
  const auto refine = [&](const auto& there) {
    const auto first = std::find_if(steps.begin(), steps.end(), there);
    if (first == steps.begin() || first == steps.end()) return;
    int below = std::prev(first)->spp, within = first->spp;
    while (within - below > 1) {
      const int mid = below + (within - below) / 2;
      const ConvergeStep step = measure(mid);
      steps.insert(std::lower_bound(steps.begin(), steps.end(), mid, [](const ConvergeStep& s, int spp) { return s.spp < spp; }), step);
      (there(step) ? within : below) = mid;
    }
  };
  refine(rawThere);
  if (settings.denoiser) refine(displayedThere);
  return steps;
}

namespace {

// A stored reference drawn from another camera, level or size would make the figure meaningless.
void checkStoredReference(const RenderImage& reference, const RenderImage& rendered) {
  if (reference.width != rendered.width || reference.height != rendered.height)
    throw std::runtime_error(
        fmt::format("the reference is {}x{}, the bench renders {}x{}", reference.width, reference.height, rendered.width, rendered.height));
  size_t differ = 0;
  for (size_t i = 0; i < rendered.depth.size(); ++i) {
    const float a = reference.depth[i], b = rendered.depth[i];
    const bool same = std::isfinite(a) == std::isfinite(b) && (!std::isfinite(a) || std::abs(a - b) <= 1e-3f * std::max(1.0f, std::abs(b)));
    differ += !same;
  }
  // A few silhouette pixels may differ between the tracers' primary rays; a camera does not.
  if (differ > rendered.depth.size() / 100)
    throw std::runtime_error(fmt::format("the reference's depth differs from the bench's view at {} of {} pixels: another level, "
                                         "camera or size",
                                         differ, rendered.depth.size()));
}

} // namespace

void printTimeToConverged(const ConvergeRun& run) {
  const auto start = std::chrono::steady_clock::now();
  const RenderImage reference = run.storedReference ? *run.storedReference : run.render(run.referenceSpp, 0x5eed);
  const float ev = autoExposureEv(reference.beauty, reference.width, reference.height);
  if (run.storedReference)
    fmt::print("reference: stored, {} spp, exposure {:+.2f} EV\n", run.referenceSpp, ev);
  else
    fmt::print("reference: {} spp in {:.2f} s, exposure {:+.2f} EV\n", run.referenceSpp,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), ev);
  std::fflush(stdout);
  const std::vector<glm::vec3> referenceDisplay = displayedImage(reference.beauty, ev);
  if (run.keep) run.keep(reference, "reference");
  if (run.referenceFloor && !run.storedReference) {
    const RenderImage second = run.render(run.referenceSpp, 0x5eed + 1);
    const std::vector<glm::vec3> secondDisplay = displayedImage(second.beauty, autoExposureEv(second.beauty, second.width, second.height));
    fmt::print("reference floor: two references of {} spp differ by rel MSE {:.4f} (worst 1 % of pixels: {:.0f} % of it)\n",
               run.referenceSpp, relativeMse(secondDisplay, referenceDisplay), 100.0 * worstPercentShare(secondDisplay, referenceDisplay));
    std::fflush(stdout);
  }
  ConvergeSettings settings;
  settings.maxSpp = std::max(1, run.referenceSpp / 4);
  if (run.maxSpp > 0) settings.maxSpp = std::min(settings.maxSpp, run.maxSpp);
  settings.denoiser = run.denoiser;
  settings.onStep = [](const ConvergeStep& s) {
    fmt::print("  {} spp: {:.2f} s, rel MSE {:.4f} (worst 1 %: {:.0f} %); denoised +{:.2f} s, rel MSE {:.4f} ({:.0f} %); displayed "
               "({:.0f} % denoised) rel MSE {:.4f}\n",
               s.spp, s.seconds, s.relativeMse, 100.0 * s.worstShare, s.denoiseSeconds, s.relativeMseDenoised, 100.0 * s.worstShareDenoised,
               100.0f * denoiseShare(s.spp), s.relativeMseDisplayed);
    std::fflush(stdout);
  };
  bool checked = !run.storedReference;
  const std::vector<ConvergeStep> steps = timeToConverged(
      [&](int spp) {
        RenderImage image = run.render(spp, 0);
        if (!checked) checkStoredReference(reference, image), checked = true;
        if (run.keep) run.keep(image, fmt::format("{:04}spp", spp));
        return image;
      },
      referenceDisplay, settings);
  for (bool denoiseOn : {false, true}) {
    if (denoiseOn && !run.denoiser) continue;
    // The first step within the threshold, else the last one.
    const auto there = [&](const ConvergeStep& s) { return (denoiseOn ? s.relativeMseDisplayed : s.relativeMse) <= kConvergedRelativeMse; };
    const auto found = std::find_if(steps.begin(), steps.end(), there);
    const ConvergeStep& last = found != steps.end() ? *found : steps.back();
    const double seconds = last.seconds + (denoiseOn ? last.denoiseSeconds : 0.0);
    fmt::print("time to converged, {}, denoiser {}: {} ({} spp, rel MSE {:.4f}, threshold {}) at {}x{}, {} bounces\n", run.tracer,
               denoiseOn ? "on" : "off", found != steps.end() ? fmt::format("{:.3f} s", seconds) : std::string("not reached"), last.spp,
               denoiseOn ? last.relativeMseDisplayed : last.relativeMse, kConvergedRelativeMse, reference.width, reference.height,
               run.bounces);
  }
  std::fflush(stdout);
}

} // namespace bt
