// `brushtrace bench`'s time to converged (issue 18): how long a tracer takes until the image a
// user sees (automatic exposure, ACES, sRGB) is within a relative MSE of a high-spp reference,
// with the denoiser on or off. The same measure for both tracers: each gives `render(spp)`.
#pragma once

#include "renderer/render.h"

#include <functional>
#include <vector>

namespace bt {

// Relative MSE, the measure of the threshold: mean over every channel of every pixel of
// (x - r)^2 / (r^2 + 0.01) (Rousselle et al. 2011's epsilon), on displayed values 0..1.
inline constexpr double kConvergedRelativeMse = 0.01;
double relativeMse(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference);

// What a PNG of `linear` shows, as floats 0..1 before rounding: 2^exposureEv, ACES, sRGB.
std::vector<glm::vec3> displayedImage(const std::vector<glm::vec3>& linear, float exposureEv);

struct ConvergeStep {
  int spp = 0;
  double seconds = 0.0; // the render of `spp` samples (a progressive render has spent this much
                        // by then), plus the denoiser's time when it is on
  double relativeMse = 0.0;
};

struct ConvergeSettings {
  int maxSpp = 4096;
  bool denoise = false;
  // The denoiser of the tracer under test (the CPU's or the GL one); used when `denoise`.
  std::function<std::vector<glm::vec3>(const RenderImage&)> denoiser;
  std::function<void(const ConvergeStep&)> onStep; // each measured step, for a progress line
};

// Renders at 1, 2, 4, ... spp (each auto-exposed on its own raw beauty, as `render` does) until
// the displayed image is within kConvergedRelativeMse of `referenceDisplay`; returns the steps,
// the last one the first to get there (or maxSpp, not converged).
std::vector<ConvergeStep> timeToConverged(const std::function<RenderImage(int spp)>& render, const std::vector<glm::vec3>& referenceDisplay,
                                          const ConvergeSettings& settings);

// The whole measure as `brushtrace bench` and gl_bench print it: a reference of `referenceSpp`
// (seed 0x5eed), then the sweep of seed 0 with the denoiser off and on, up to a quarter of the
// reference's spp (beyond that its own noise counts); each step and each result on stdout.
// `tracer` names the tracer in the lines ("cpu", "gl").
struct ConvergeRun {
  const char* tracer = "cpu";
  int referenceSpp = 4096;
  int bounces = 4;
  std::function<RenderImage(int spp, uint32_t seed)> render;
  std::function<std::vector<glm::vec3>(const RenderImage&)> denoiser;
};
void printTimeToConverged(const ConvergeRun& run);

} // namespace bt
