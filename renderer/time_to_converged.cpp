#include "renderer/time_to_converged.h"

#include "renderer/exposure.h"
#include "renderer/tonemap.h"
#include "scene/color.h"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace bt {

double relativeMse(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference) {
  double sum = 0.0;
  for (size_t i = 0; i < reference.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double x = image[i][c], r = reference[i][c];
      sum += (x - r) * (x - r) / (r * r + 0.01);
    }
  return reference.empty() ? 0.0 : sum / double(reference.size() * 3);
}

std::vector<glm::vec3> displayedImage(const std::vector<glm::vec3>& linear, float exposureEv) {
  const float scale = std::exp2(exposureEv);
  std::vector<glm::vec3> out(linear.size());
  for (size_t i = 0; i < linear.size(); ++i) out[i] = linearToSrgb(applyTonemap(Tonemap::Aces, linear[i] * scale));
  return out;
}

std::vector<ConvergeStep> timeToConverged(const std::function<RenderImage(int spp)>& render, const std::vector<glm::vec3>& referenceDisplay,
                                          const ConvergeSettings& settings) {
  using Clock = std::chrono::steady_clock;
  std::vector<ConvergeStep> steps;
  for (int spp = 1; spp <= settings.maxSpp; spp *= 2) {
    const auto start = Clock::now();
    RenderImage image = render(spp);
    if (settings.denoise) image.denoised = settings.denoiser(image);
    ConvergeStep step;
    step.spp = spp;
    step.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const float ev = autoExposureEv(image.beauty, image.width, image.height);
    step.relativeMse = relativeMse(displayedImage(settings.denoise ? image.denoised : image.beauty, ev), referenceDisplay);
    steps.push_back(step);
    if (settings.onStep) settings.onStep(step);
    if (step.relativeMse <= kConvergedRelativeMse) break;
  }
  return steps;
}

void printTimeToConverged(const ConvergeRun& run) {
  const auto start = std::chrono::steady_clock::now();
  const RenderImage reference = run.render(run.referenceSpp, 0x5eed);
  const float ev = autoExposureEv(reference.beauty, reference.width, reference.height);
  fmt::print("reference: {} spp in {:.2f} s, exposure {:+.2f} EV\n", run.referenceSpp,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), ev);
  std::fflush(stdout);
  const std::vector<glm::vec3> referenceDisplay = displayedImage(reference.beauty, ev);
  for (bool denoiseOn : {false, true}) {
    ConvergeSettings settings;
    settings.maxSpp = run.referenceSpp / 4;
    settings.denoise = denoiseOn;
    settings.denoiser = run.denoiser;
    settings.onStep = [](const ConvergeStep& s) {
      fmt::print("  {} spp: {:.2f} s, rel MSE {:.4f}\n", s.spp, s.seconds, s.relativeMse);
      std::fflush(stdout);
    };
    fmt::print("denoiser {}:\n", denoiseOn ? "on" : "off");
    const ConvergeStep last = timeToConverged([&](int spp) { return run.render(spp, 0); }, referenceDisplay, settings).back();
    const bool reached = last.relativeMse <= kConvergedRelativeMse;
    fmt::print("time to converged, {}, denoiser {}: {} ({} spp, rel MSE {:.4f}, threshold {}) at {}x{}, {} bounces\n", run.tracer,
               denoiseOn ? "on" : "off", reached ? fmt::format("{:.3f} s", last.seconds) : std::string("not reached"), last.spp,
               last.relativeMse, kConvergedRelativeMse, reference.width, reference.height, run.bounces);
    std::fflush(stdout);
  }
}

} // namespace bt
