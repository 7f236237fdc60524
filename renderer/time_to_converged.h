// `brushtrace bench`'s time to converged (issue 18): how long a tracer takes until the image a
// user sees (automatic exposure, ACES, sRGB) is within a relative MSE of a high-spp reference,
// with the denoiser on (the viewer's fade from the denoised to the raw image,
// renderer/denoise_fade.h) or off. The same measure for both tracers: each gives `render(spp)`.
#pragma once

#include "renderer/denoise_fade.h"
#include "renderer/render.h"

#include <functional>
#include <string>
#include <vector>

namespace bt {

// Relative MSE, the measure of the threshold: mean over every channel of every pixel of
// (x - r)^2 / (r^2 + 0.01) (Rousselle et al. 2011's epsilon), on displayed values 0..1.
inline constexpr double kConvergedRelativeMse = 0.01;
double relativeMse(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference);
// The share of that error (0..1) that the worst 1 % of pixels hold: near 0.01 for noise spread
// evenly, near 1 where a few fireflies or one wrong region rule the figure.
double worstPercentShare(const std::vector<glm::vec3>& image, const std::vector<glm::vec3>& reference);

// What a PNG of `linear` shows, as floats 0..1 before rounding: 2^exposureEv, ACES, sRGB.
std::vector<glm::vec3> displayedImage(const std::vector<glm::vec3>& linear, float exposureEv);

struct ConvergeStep {
  int spp = 0;
  double seconds = 0.0;                              // the render of `spp` samples (a progressive render has spent this much by then)
  double denoiseSeconds = 0.0;                       // the denoiser's on that render, when the display asks for it
  double relativeMse = 0.0;                          // the raw image's
  double relativeMseDenoised = 0.0;                  // the denoised image's at full strength, when the denoiser is on
  double relativeMseDisplayed = 0.0;                 // what the viewer shows with the denoiser on (displayedBeauty)
  double worstShare = 0.0, worstShareDenoised = 0.0; // worstPercentShare of the first two
};

struct ConvergeSettings {
  int maxSpp = 4096;
  // The denoiser of the tracer under test (the CPU's or the GL one); empty: measured without.
  std::function<std::vector<glm::vec3>(const RenderImage&)> denoiser;
  std::function<void(const ConvergeStep&)> onStep; // each measured step, for a progress line
  DenoiseFade fade = kDenoiseFade;                 // the display's; tests shorten it
  // Bisect the counts between the last step above the threshold and the first within it (raw,
  // and displayed with the denoiser on), as the viewer shows them all; off: the half-octaves alone.
  bool refine = true;
};

// The sample counts the sweep renders, up to maxSpp: every power of two and, between two, the
// rounded geometric mean (1, 2, 3, 4, 6, 8, 11, 16, 23, 32, 45, 64, 91, 128, 181, 256, ...). The
// viewer shows every sample count on its way, so a sweep by doubling alone would report up to
// twice the time the display needs; half-octaves keep that over-report within a factor of 1.41,
// and timeToConverged's bisection between them takes it to one sample.
std::vector<int> convergeSteps(int maxSpp);

// Renders at each of convergeSteps(maxSpp) (each auto-exposed on its own raw beauty, as `render` does), each
// image measured raw, denoised and as displayed with the denoiser on (displayedBeauty of the two
// at its spp), until the raw and the displayed image are within kConvergedRelativeMse of
// `referenceDisplay` (or maxSpp), then (settings.refine) the counts between each measure's last
// step above and first step within the threshold, by bisection; returns the steps in order of
// spp. The denoiser's time counts where the display shows some of it.
std::vector<ConvergeStep> timeToConverged(const std::function<RenderImage(int spp)>& render, const std::vector<glm::vec3>& referenceDisplay,
                                          const ConvergeSettings& settings);

// The whole measure as `brushtrace bench` and gl_bench print it: a reference of `referenceSpp`
// (seed 0x5eed), or the stored one given, then the sweep of seed 0, denoiser off and on, up to a
// quarter of the reference's spp (beyond that its own noise counts); each step and each result on
// stdout. `tracer` names the tracer in the lines ("cpu", "gl"). A stored reference must show what
// the sweep renders: its size and its depth AOV the same (else std::runtime_error).
struct ConvergeRun {
  const char* tracer = "cpu";
  int referenceSpp = 4096;
  int bounces = 4;
  std::function<RenderImage(int spp, uint32_t seed)> render;
  std::function<std::vector<glm::vec3>(const RenderImage&)> denoiser;
  const RenderImage* storedReference = nullptr; // renderer/image_output.h readExrImage; referenceSpp its spp
  int maxSpp = 0;                               // the sweep's last step at most; 0: a quarter of referenceSpp
  // Also render a second reference of another seed and print the two's relative MSE: the floor
  // of the measure (half of it is in every step's figure), which says whether the reference's
  // own noise or the sweep's keeps a step above the threshold.
  bool referenceFloor = false;
  // Given: called with the reference ("reference") and each step's raw image ("NNNNspp"), with
  // their AOVs and second moment, for a denoiser lab to filter again (gl_bench's `dump DIR`).
  std::function<void(const RenderImage&, const std::string& name)> keep;
};
void printTimeToConverged(const ConvergeRun& run);

} // namespace bt
