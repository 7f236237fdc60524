// What physical mode displays with the preview denoiser on (issue 18): the denoised beauty while
// the image is young, fading to the raw one as samples accumulate, where the denoiser stops
// helping. One rule for the viewer's windows (GL and CPU) and the time-to-converged bench
// (renderer/time_to_converged.h), so that the bench measures the image a user sees.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace bt {

// The share of the denoised picture at `samples` samples per pixel: 1 up to kDenoiseFullUntil,
// falling linearly to 0 at kDenoiseGoneAt and after (README "Viewer"; bench/README.md, issue 18
// session 20, for the measurements they were chosen from).
inline constexpr int kDenoiseFullUntil = 64;
inline constexpr int kDenoiseGoneAt = 1024;
float denoiseShare(int samples);

// The beauty displayed at `samples` spp: denoiseShare(samples) x denoised + the rest x raw,
// pixel by pixel. `denoised` is read only where the share is above 0 (it may be empty there).
std::vector<glm::vec3> displayedBeauty(const std::vector<glm::vec3>& raw, const std::vector<glm::vec3>& denoised, int samples);

} // namespace bt
