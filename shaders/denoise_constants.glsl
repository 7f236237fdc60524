// The denoiser's constants, one source for both tracers: renderer/denoise.cpp and
// renderer/exposure.cpp include this file as C++, shaders/denoise.comp as GLSL. Hence only
// #defines of literals both languages read alike (floats with the f suffix).
#ifndef BT_DENOISE_CONSTANTS
#define BT_DENOISE_CONSTANTS

// Rec. 709 luminance of linear RGB.
#define BT_LUMINANCE_R 0.2126f
#define BT_LUMINANCE_G 0.7152f
#define BT_LUMINANCE_B 0.0722f

// Edge-avoiding a-trous wavelet filter (Dammertz et al. 2010): this many passes of the 5x5 B3
// spline kernel (1/16, 1/4, 3/8, 1/4, 1/16), the taps 2^i pixels apart in pass i, so the last
// pass reaches 2 * 2^(N-1) = 32 pixels.
#define BT_DENOISE_PASSES 5
#define BT_DENOISE_KERNEL0 0.375f
#define BT_DENOISE_KERNEL1 0.25f
#define BT_DENOISE_KERNEL2 0.0625f
// Edge stops, as SVGF (Schied et al. 2017) writes them: normals max(0, n.n')^SIGMA_NORMAL;
// depth exp(-|z - z'| / (SIGMA_DEPTH |grad z| |offset| + DEPTH_FLOOR z)), the gradient so that
// a sloped floor is one surface; irradiance luminance exp(-|l - l'| / (sigma sqrt(g(var l)) +
// LUMINANCE_FLOOR)), var l the variance of the pixel's demodulated mean luminance and g a 3x3
// Gaussian of it (VARIANCE_KERNEL0..2, the centre tap first): each pixel is smoothed as much as
// its own noise asks, so a firefly (far outside its neighbours' spread) stays where it is
// instead of being spread into a blob, and a converged pixel is left alone. Each pass filters
// the variance with its weights squared (sum w^2 var / (sum w)^2), so the next pass sees the
// smaller noise the last one left. sigma = SIGMA_LUMINANCE / 2^pass: Dammertz's halving kept
// beside SVGF's propagation, since without it a converged image (the lit test room at 1024 spp)
// changed by 3 times its own noise; 3.5 rather than SVGF's 4 for the same reason (4: 1.05e-3,
// over tests/render/denoise_exposure_test.cpp's bar of 1e-3; bench/README.md, conv18).
#define BT_DENOISE_SIGMA_NORMAL 128.0f
#define BT_DENOISE_SIGMA_DEPTH 1.0f
#define BT_DENOISE_DEPTH_FLOOR 0.001f
#define BT_DENOISE_SIGMA_LUMINANCE 3.5f
#define BT_DENOISE_LUMINANCE_FLOOR 1e-6f
#define BT_DENOISE_VARIANCE_KERNEL0 0.25f
#define BT_DENOISE_VARIANCE_KERNEL1 0.125f
#define BT_DENOISE_VARIANCE_KERNEL2 0.0625f
// The variance: from the pixel's own samples (the tracers sum each sample's squared luminance
// beside the sample: the second moment m2, so var = (m2 - mean^2) / (n - 1) for the mean of n)
// from this many samples on; below it, or where a caller has no second moment, as SVGF does for
// a young history: the spread of the pixel means over a (2 RADIUS + 1)^2 window weighed by the
// normal and depth stops (one or two samples say nothing of their own spread).
#define BT_DENOISE_TEMPORAL_VARIANCE_FROM 4
#define BT_DENOISE_SPATIAL_VARIANCE_RADIUS 3
// The denoiser's bias (issue 18): the albedo AOV is the pixel centre's, the beauty the mean over
// the pixel's area, so where texels or surfaces of unlike colour share a pixel the demodulated
// irradiance is off by their ratio, and the filter trades that for its neighbours' (bricks finer
// than a pixel: 13 times the raw image's error at 256 spp). From SHRINK_FROM samples on, where
// the second moment gives each pixel's own noise, the last step keeps of the filtered value's
// difference d from the raw mean, in each channel, the share min(1, var / d^2), var the variance
// of that channel's mean (the luminance's, scaled by the square of the channel's share of it):
// the Wiener weight of a smooth estimate biased by b, var / (var + b^2), with d^2 estimating
// var + b^2: noise-sized changes stay, a change many times the pixel's own noise (a bias, a hue
// shift included) falls back to the raw mean. Below SHRINK_FROM the few samples' variance is too rough
// (at 4 spp it cost lq_e4m3 a third of the filter's gain); measurements: bench/README.md, issue
// 18 session 20. A clamp of the filtered value to the raw mean +- 1.25 standard errors instead
// (session 22) left lq_e4m3 at 64 / 128 spp 10 % closer still, but moved a pixel 1.25 sigma
// whatever its bias: the bricks below a pixel at 256 spp 1.47 times raw, over the tests' 1.25.
#define BT_DENOISE_SHRINK_FROM 16

// Demodulation divides the beauty by the albedo plus this much, and remodulation multiplies by
// the same: black texels do not blow up, and a dark texel's light that its albedo does not scale
// (a dielectric's specular reflection, 4 % whatever its colour; an emitter's own light) is not
// turned into a spike of irradiance ten or a hundred times its neighbours', which the filter
// spread and the shrink could only partly take back. The albedo floored at 0.01 instead (session
// 21) left lq_e4m3 at 8 / 16 / 64 / 128 spp 0.0846 / 0.0575 / 0.0218 / 0.0138 against 0.0695 /
// 0.0546 / 0.0201 / 0.0126 (bench/README.md, issue 18 session 22).
#define BT_DENOISE_ALBEDO_OFFSET 0.01f

#endif
