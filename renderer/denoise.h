// The preview denoiser: an edge-avoiding a-trous wavelet filter (Dammertz et al. 2010, "Edge-
// Avoiding A-Trous Wavelet Transform for fast Global Illumination Filtering") guided by the
// albedo, normal and depth AOVs, with SVGF's edge stops (Schied et al. 2017), its luminance stop
// scaled by each pixel's own noise (the variance of its mean, from the tracer's second moment).
// The beauty is divided by the albedo (so textures stay sharp), the irradiance filtered, and
// multiplied back; from BT_DENOISE_SHRINK_FROM spp each pixel is drawn back toward its raw mean
// where it moved by more than its own noise explains (the demodulation's bias at texel edges).
// What the viewer shows of it: renderer/denoise_fade.h.
// shaders/denoise.comp does the same arithmetic on the GPU (gl::DenoisePass), with the
// constants of shaders/denoise_constants.glsl.
#pragma once

#include "renderer/render.h"

#include <glm/vec3.hpp>

#include <vector>

namespace bt {

// The denoised beauty of `image` (its AOVs guide the filter; image.luminanceMoment2 and
// image.samples give each pixel's noise, and so how strongly it is smoothed; without the moment,
// its neighbours' spread does). Pixels where nothing was hit (depth not finite) are neither
// changed nor read.
// `threads`: 0 = every hardware thread.
std::vector<glm::vec3> denoise(const RenderImage& image, int threads = 0);

// The variance of the mean luminance of `samples` samples from their second moment (0 where
// that is not finite): each pixel's noise as the denoiser reads it.
float meanVariance(float moment2, float meanLuminance, int samples);

} // namespace bt
