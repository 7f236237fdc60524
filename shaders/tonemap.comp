#version 450
#extension GL_GOOGLE_include_directive : require
// The display image of a progressive render: the accumulated sum divided by its sample count,
// exposed, tonemapped and sRGB-encoded into an RGBA8 image the viewer draws as it is.
// The operators are scene/color.h's (applyTonemap, linearToSrgb) line for line, with the
// constants of both from tonemap_constants.glsl, so a PNG the CPU writes from the same linear
// image has the same bytes, within rounding (tests/gl/gl_progressive_test.cpp holds them to 1/255).
#include "gl_bindings.glsl"
#include "tonemap_constants.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = BT_IMAGE_ACCUMULATION) uniform readonly image2D accumulation; // rgb: radiance summed over `samples`
layout(rgba8, binding = BT_IMAGE_DISPLAY) uniform writeonly image2D display;       // sRGB-encoded, a = 1

layout(location = 0) uniform float scale;    // exp2(exposure EV) / samples
layout(location = 1) uniform uint tonemap;   // bt::Tonemap: 0 faithful, 1 aces, 2 agx, 3 linear
layout(location = 2) uniform ivec4 region;   // the pixels to tonemap: x0, y0 (this dispatch's first), x1, y1 (past its last)

const uint kAces = 1u;
const uint kAgx = 2u;

// Narkowicz's fit of the ACES filmic curve.
vec3 tonemapAces(vec3 x) {
  return clamp((x * (BT_ACES_A * x + BT_ACES_B)) / (x * (BT_ACES_C * x + BT_ACES_D) + BT_ACES_E), 0.0, 1.0);
}

// AgX (Troy Sobotka), with the polynomial contrast fit by Benjamin Wrensch; linear in, linear out.
vec3 tonemapAgx(vec3 c) {
  const vec3 inRow0 = vec3(BT_AGX_IN_ROW0);
  const vec3 inRow1 = vec3(BT_AGX_IN_ROW1);
  const vec3 inRow2 = vec3(BT_AGX_IN_ROW2);
  vec3 v = vec3(dot(inRow0, c), dot(inRow1, c), dot(inRow2, c));
  const float minEv = BT_AGX_MIN_EV, maxEv = BT_AGX_MAX_EV;
  v = (clamp(log2(max(v, vec3(1e-10))), minEv, maxEv) - minEv) / (maxEv - minEv);
  vec3 x2 = v * v, x4 = x2 * x2;
  v = BT_AGX_POLY6 * x4 * x2 + BT_AGX_POLY5 * x4 * v + BT_AGX_POLY4 * x4 + BT_AGX_POLY3 * x2 * v + BT_AGX_POLY2 * x2 +
      BT_AGX_POLY1 * v + BT_AGX_POLY0;
  const vec3 outRow0 = vec3(BT_AGX_OUT_ROW0);
  const vec3 outRow1 = vec3(BT_AGX_OUT_ROW1);
  const vec3 outRow2 = vec3(BT_AGX_OUT_ROW2);
  vec3 outColor = max(vec3(dot(outRow0, v), dot(outRow1, v), dot(outRow2, v)), vec3(0.0));
  return pow(outColor, vec3(BT_AGX_GAMMA));
}

vec3 applyTonemap(uint op, vec3 linearColor) {
  if (op == kAces) return tonemapAces(linearColor);
  if (op == kAgx) return clamp(tonemapAgx(linearColor), 0.0, 1.0);
  // Faithful: Quake clamps overbright light at the display's white; Linear the same.
  return clamp(linearColor, 0.0, 1.0);
}

float linearToSrgb(float c) {
  return c <= BT_SRGB_LINEAR_LIMIT ? c * BT_SRGB_LINEAR_SLOPE
                                   : BT_SRGB_SCALE * pow(c, 1.0 / BT_SRGB_GAMMA) - BT_SRGB_OFFSET;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy) + region.xy;
  if (any(greaterThanEqual(pixel, min(region.zw, imageSize(display))))) return;
  vec3 c = applyTonemap(tonemap, imageLoad(accumulation, pixel).rgb * scale);
  imageStore(display, pixel, vec4(linearToSrgb(c.r), linearToSrgb(c.g), linearToSrgb(c.b), 1.0));
}
