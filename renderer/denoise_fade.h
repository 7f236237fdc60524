// What physical mode displays with the preview denoiser on (issue 18): the denoised beauty while
// the image is young, fading to the raw one as samples accumulate, where the denoiser stops
// helping. One rule for the viewer's windows (GL and CPU) and the time-to-converged bench
// (renderer/time_to_converged.h), so that the bench measures the image a user sees.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace bt {

// The fade: the denoised picture's share is 1 up to `fullUntil` samples per pixel, falling
// linearly to 0 at `goneAt` and after. kDenoiseFade is what the viewer and the bench use (README
// "Viewer"; bench/README.md, issue 18 session 21, for the measurements it was chosen from: with
// the per-channel shrink the denoised image at full strength beat every blend with the raw one
// up to 512 spp on lq_e4m3); another is for tests that cannot wait (ViewerOptions::denoiseFade).
struct DenoiseFade {
  int fullUntil = 256;
  int goneAt = 4096;
};
inline constexpr DenoiseFade kDenoiseFade{};
float denoiseShare(int samples, const DenoiseFade& fade = kDenoiseFade);

// The beauty displayed at `samples` spp: denoiseShare(samples) x denoised + the rest x raw,
// pixel by pixel. `denoised` is read only where the share is above 0 (it may be empty there).
std::vector<glm::vec3> displayedBeauty(const std::vector<glm::vec3>& raw, const std::vector<glm::vec3>& denoised, int samples,
                                       const DenoiseFade& fade = kDenoiseFade);

} // namespace bt
