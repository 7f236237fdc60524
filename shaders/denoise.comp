#version 450
#extension GL_GOOGLE_include_directive : require
// One pass of the preview denoiser: renderer/denoise.cpp's filterRows line for line (the
// edge-avoiding a-trous filter, Dammertz et al. 2010, with SVGF's edge stops), with the
// constants of denoise_constants.glsl. The first pass divides its input (the beauty, a sum of
// `inputScale`^-1 samples) by the albedo; the last multiplies its output by it again.
// tests/gl/gl_denoise_test.cpp holds it to the CPU's.
#include "denoise_constants.glsl"
#include "gl_bindings.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = BT_IMAGE_DENOISE_IN) uniform readonly image2D inputImage;
layout(rgba32f, binding = BT_IMAGE_DENOISE_OUT) uniform writeonly image2D outputImage;
layout(rgba32f, binding = BT_IMAGE_DENOISE_ALBEDO) uniform readonly image2D albedoImage;
layout(rgba32f, binding = BT_IMAGE_DENOISE_NORMAL_DEPTH) uniform readonly image2D normalDepthImage; // xyz normal, w depth (inf: nothing hit)

layout(location = 0) uniform int spacing;      // 2^pass
layout(location = 1) uniform float sigma;      // BT_DENOISE_SIGMA_LUMINANCE / sqrt(spp) / 2^pass
layout(location = 2) uniform float inputScale; // 1 / samples on the first pass (a sum), else 1
layout(location = 3) uniform bool firstPass;   // demodulate the input
layout(location = 4) uniform bool lastPass;    // remodulate the output

const float kKernel[3] = float[3](BT_DENOISE_KERNEL0, BT_DENOISE_KERNEL1, BT_DENOISE_KERNEL2);

float luminance(vec3 c) {
  return BT_LUMINANCE_R * c.r + BT_LUMINANCE_G * c.g + BT_LUMINANCE_B * c.b;
}

bool hit(ivec2 p) {
  return !isinf(imageLoad(normalDepthImage, p).w);
}

vec3 albedoFloor(ivec2 p) {
  return max(imageLoad(albedoImage, p).rgb, vec3(BT_DENOISE_ALBEDO_FLOOR));
}

// The pass's input at p: on the first pass the mean beauty divided by the albedo (0 where it is
// not finite), as denoise() prepares it.
vec3 irradiance(ivec2 p) {
  vec3 c = imageLoad(inputImage, p).rgb * inputScale;
  if (!firstPass) return c;
  if (any(isinf(c)) || any(isnan(c))) return vec3(0.0);
  return c / albedoFloor(p);
}

float depthStep(ivec2 q, float z, ivec2 size) {
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)) || !hit(q)) return uintBitsToFloat(0x7f800000u); // +inf
  return abs(imageLoad(normalDepthImage, q).w - z);
}

// denoise.cpp Guide::depthGradient.
float depthGradient(ivec2 p, float z, ivec2 size) {
  float gx = min(depthStep(p - ivec2(1, 0), z, size), depthStep(p + ivec2(1, 0), z, size));
  float gy = min(depthStep(p - ivec2(0, 1), z, size), depthStep(p + ivec2(0, 1), z, size));
  return max(isinf(gx) ? 0.0 : gx, isinf(gy) ? 0.0 : gy);
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(outputImage);
  if (any(greaterThanEqual(p, size))) return;
  if (!hit(p)) { // nothing to filter: the beauty as it is
    imageStore(outputImage, p, vec4(imageLoad(inputImage, p).rgb * inputScale, 1.0));
    return;
  }
  vec4 nzp = imageLoad(normalDepthImage, p);
  vec3 cp = irradiance(p);
  float lp = luminance(cp), gradient = depthGradient(p, nzp.w, size);
  vec3 sum = vec3(0.0);
  float weights = 0.0;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      ivec2 q = p + ivec2(dx, dy) * spacing;
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size)) || !hit(q)) continue;
      vec4 nzq = imageLoad(normalDepthImage, q);
      vec3 cq = irradiance(q);
      float lq = luminance(cq);
      float wNormal = pow(max(0.0, dot(nzp.xyz, nzq.xyz)), BT_DENOISE_SIGMA_NORMAL);
      float offset = float(spacing * (abs(dx) + abs(dy)));
      float wDepth = exp(-abs(nzp.w - nzq.w) / (BT_DENOISE_SIGMA_DEPTH * gradient * offset + BT_DENOISE_DEPTH_FLOOR * nzp.w));
      float wLum = exp(-abs(lp - lq) / (sigma * sqrt(max(lp * lq, 0.0)) + BT_DENOISE_LUMINANCE_FLOOR));
      float w = kKernel[abs(dx)] * kKernel[abs(dy)] * wNormal * wDepth * wLum;
      sum += w * cq;
      weights += w;
    }
  }
  vec3 result = sum / weights;
  if (lastPass) result *= albedoFloor(p);
  imageStore(outputImage, p, vec4(result, 1.0));
}
