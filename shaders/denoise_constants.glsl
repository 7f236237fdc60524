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
// a sloped floor is one surface; irradiance luminance exp(-|l - l'| / (sigma sqrt(l l') +
// LUMINANCE_FLOOR)), sigma = SIGMA_LUMINANCE / sqrt(spp) / 2^pass: relative to the geometric
// mean of the two, so the brighter a firefly the less it weighs (relative to their arithmetic
// mean the weight would tend to exp(-2 / sigma) however bright, and spread fireflies into blobs;
// relative to the darker one it smooths noise too little). SVGF divides by the pixel's
// measured standard deviation; brushtrace's tracers keep no second moment, so the expected
// relative noise of a path-traced mean (1 / sqrt(spp)) stands in for it: a young image is
// smoothed, a converged one is left nearly as it is. Dammertz halves the colour sigma each pass.
#define BT_DENOISE_SIGMA_NORMAL 128.0f
#define BT_DENOISE_SIGMA_DEPTH 1.0f
#define BT_DENOISE_DEPTH_FLOOR 0.001f
#define BT_DENOISE_SIGMA_LUMINANCE 4.0f
#define BT_DENOISE_LUMINANCE_FLOOR 1e-6f
// Demodulation divides the beauty by the albedo, each channel at least this much, so black
// texels do not blow up; remodulation multiplies by the same value.
#define BT_DENOISE_ALBEDO_FLOOR 0.01f

#endif
