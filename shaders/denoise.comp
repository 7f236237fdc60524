#version 450
#extension GL_GOOGLE_include_directive : require
// One step of the preview denoiser: renderer/denoise.cpp line for line (the edge-avoiding a-trous
// filter, Dammertz et al. 2010, with SVGF's edge stops and its variance-scaled luminance stop),
// with the constants of denoise_constants.glsl. The first step (`prepare`) turns the beauty (rgb
// a sum of `inputScale`^-1 samples, a the sum of their luminance squared) into the irradiance
// (divided by the albedo) and the variance of its luminance (in a); each pass after it filters
// both, the last multiplying its output by the albedo again.
// tests/gl/gl_denoise_test.cpp holds it to the CPU's.
#include "denoise_constants.glsl"
#include "gl_bindings.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = BT_IMAGE_DENOISE_IN) uniform readonly image2D inputImage;
layout(rgba32f, binding = BT_IMAGE_DENOISE_OUT) uniform writeonly image2D outputImage;
layout(rgba32f, binding = BT_IMAGE_DENOISE_ALBEDO) uniform readonly image2D albedoImage;
layout(rgba32f, binding = BT_IMAGE_DENOISE_NORMAL_DEPTH) uniform readonly image2D normalDepthImage; // xyz normal, w depth (inf: nothing hit)
layout(rgba32f, binding = BT_IMAGE_DENOISE_RAW) uniform readonly image2D rawImage; // the last pass: the beauty as the first step read it

layout(location = 0) uniform int spacing;      // 2^pass
layout(location = 1) uniform int samples;      // of the beauty's mean
layout(location = 2) uniform float inputScale; // 1 / samples when preparing a sum, else 1
layout(location = 3) uniform bool prepare;     // the first step: demodulate, estimate the variance
layout(location = 4) uniform bool lastPass;    // remodulate the output
layout(location = 5) uniform bool temporal;    // the variance from the beauty's own second moment
layout(location = 6) uniform float rawScale;   // the last pass: rawImage's inputScale
layout(location = 7) uniform bool shrink;      // the last pass: draw the result back toward the raw mean (BT_DENOISE_SHRINK_FROM)

const float kKernel[3] = float[3](BT_DENOISE_KERNEL0, BT_DENOISE_KERNEL1, BT_DENOISE_KERNEL2);
const float kVarianceKernel[3] = float[3](BT_DENOISE_VARIANCE_KERNEL0, BT_DENOISE_VARIANCE_KERNEL1, BT_DENOISE_VARIANCE_KERNEL2);

float luminance(vec3 c) {
  return BT_LUMINANCE_R * c.r + BT_LUMINANCE_G * c.g + BT_LUMINANCE_B * c.b;
}

bool inside(ivec2 q, ivec2 size) {
  return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size));
}

bool hit(ivec2 p) {
  return !isinf(imageLoad(normalDepthImage, p).w);
}

// denoise.cpp Guide::demodulator.
vec3 demodulator(ivec2 p) {
  return imageLoad(albedoImage, p).rgb + BT_DENOISE_ALBEDO_OFFSET;
}

// The mean beauty at p divided by the albedo (0 where it is not finite), as prepare() makes it.
vec3 irradiance(ivec2 p) {
  vec3 c = imageLoad(inputImage, p).rgb * inputScale;
  if (any(isinf(c)) || any(isnan(c))) return vec3(0.0);
  return c / demodulator(p);
}

float depthStep(ivec2 q, float z, ivec2 size) {
  if (!inside(q, size) || !hit(q)) return uintBitsToFloat(0x7f800000u); // +inf
  return abs(imageLoad(normalDepthImage, q).w - z);
}

// denoise.cpp Guide::depthGradient.
float depthGradient(ivec2 p, float z, ivec2 size) {
  float gx = min(depthStep(p - ivec2(1, 0), z, size), depthStep(p + ivec2(1, 0), z, size));
  float gy = min(depthStep(p - ivec2(0, 1), z, size), depthStep(p + ivec2(0, 1), z, size));
  return max(isinf(gx) ? 0.0 : gx, isinf(gy) ? 0.0 : gy);
}

// denoise.cpp Guide::geometryWeight.
float geometryWeight(vec4 nzp, vec4 nzq, float gradient, float offset) {
  float wNormal = pow(max(0.0, dot(nzp.xyz, nzq.xyz)), BT_DENOISE_SIGMA_NORMAL);
  float wDepth = exp(-abs(nzp.w - nzq.w) / (BT_DENOISE_SIGMA_DEPTH * gradient * offset + BT_DENOISE_DEPTH_FLOOR * nzp.w));
  return wNormal * wDepth;
}

// denoise.cpp spatialVariance.
float spatialVariance(ivec2 p, vec4 nzp, ivec2 size) {
  float gradient = depthGradient(p, nzp.w, size);
  float weights = 0.0, m1 = 0.0, m2 = 0.0;
  for (int dy = -BT_DENOISE_SPATIAL_VARIANCE_RADIUS; dy <= BT_DENOISE_SPATIAL_VARIANCE_RADIUS; ++dy)
    for (int dx = -BT_DENOISE_SPATIAL_VARIANCE_RADIUS; dx <= BT_DENOISE_SPATIAL_VARIANCE_RADIUS; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (!inside(q, size) || !hit(q)) continue;
      float w = geometryWeight(nzp, imageLoad(normalDepthImage, q), gradient, float(abs(dx) + abs(dy)));
      float l = luminance(irradiance(q));
      weights += w, m1 += w * l, m2 += w * l * l;
    }
  m1 /= weights, m2 /= weights;
  return max(0.0, m2 - m1 * m1);
}

// denoise.cpp meanVariance.
float meanVariance(float moment2, float meanLuminance) {
  float variance = max(0.0, moment2 - meanLuminance * meanLuminance) / float(samples - 1);
  return isinf(variance) || isnan(variance) ? 0.0 : variance;
}

// denoise.cpp shrinkTowardRaw: each channel on its own.
vec3 shrinkTowardRaw(vec3 raw, vec3 filtered, float variance) {
  float rawLuminance = luminance(raw);
  vec3 share = rawLuminance > 0.0 ? raw / rawLuminance : vec3(1.0);
  vec3 channelVariance = variance * share * share, d = filtered - raw;
  vec3 keep = vec3(1.0);
  for (int c = 0; c < 3; ++c)
    if (d[c] * d[c] > channelVariance[c]) keep[c] = channelVariance[c] / (d[c] * d[c]);
  return raw + d * keep;
}

// denoise.cpp prepare, for one pixel.
vec4 prepared(ivec2 p, vec4 nzp, ivec2 size) {
  vec3 c = irradiance(p);
  if (!temporal) return vec4(c, spatialVariance(p, nzp, size));
  vec4 mean = imageLoad(inputImage, p) * inputScale;
  float beautyLuminance = luminance(mean.rgb), l = luminance(c);
  float ratio = beautyLuminance > 0.0 ? l / beautyLuminance : 0.0;
  float variance = meanVariance(mean.a, beautyLuminance) * ratio * ratio;
  return vec4(c, isinf(variance) || isnan(variance) ? 0.0 : variance);
}

// denoise.cpp filteredVariance.
float filteredVariance(ivec2 p, ivec2 size) {
  float sum = 0.0, weights = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 q = p + ivec2(dx, dy);
      if (!inside(q, size) || !hit(q)) continue;
      float w = kVarianceKernel[abs(dx)] * kVarianceKernel[abs(dy)];
      sum += w * imageLoad(inputImage, q).a, weights += w;
    }
  return sum / weights;
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(outputImage);
  if (any(greaterThanEqual(p, size))) return;
  if (!hit(p)) { // nothing to filter: the beauty as it is
    imageStore(outputImage, p, vec4(imageLoad(inputImage, p).rgb * inputScale, 0.0));
    return;
  }
  vec4 nzp = imageLoad(normalDepthImage, p);
  if (prepare) {
    imageStore(outputImage, p, prepared(p, nzp, size));
    return;
  }
  float lp = luminance(imageLoad(inputImage, p).rgb), gradient = depthGradient(p, nzp.w, size);
  float sigma = BT_DENOISE_SIGMA_LUMINANCE / float(spacing); // halved each pass
  float lumScale = sigma * sqrt(filteredVariance(p, size)) + BT_DENOISE_LUMINANCE_FLOOR;
  vec3 sum = vec3(0.0);
  float weights = 0.0, variance = 0.0;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      ivec2 q = p + ivec2(dx, dy) * spacing;
      if (!inside(q, size) || !hit(q)) continue;
      vec4 cq = imageLoad(inputImage, q);
      float wLum = exp(-abs(lp - luminance(cq.rgb)) / lumScale);
      float w = kKernel[abs(dx)] * kKernel[abs(dy)] * geometryWeight(nzp, imageLoad(normalDepthImage, q), gradient, float(spacing * (abs(dx) + abs(dy)))) * wLum;
      sum += w * cq.rgb;
      variance += w * w * cq.a;
      weights += w;
    }
  }
  vec3 result = sum / weights;
  if (lastPass) {
    result *= demodulator(p);
    vec4 raw = imageLoad(rawImage, p) * rawScale;
    if (shrink && !any(isinf(raw.rgb)) && !any(isnan(raw.rgb))) result = shrinkTowardRaw(raw.rgb, result, meanVariance(raw.a, luminance(raw.rgb)));
  }
  imageStore(outputImage, p, vec4(result, variance / (weights * weights)));
}
