#version 450
// The display image of a progressive render: the accumulated sum divided by its sample count,
// exposed, tonemapped and sRGB-encoded into an RGBA8 image the viewer draws as it is.
// The operators are renderer/cpu/color.h's (applyTonemap, linearToSrgb) line for line, so a
// PNG the CPU writes from the same linear image has the same bytes, within rounding
// (tests/gl/gl_tonemap_test.cpp holds them to 1/255).

layout(local_size_x = 8, local_size_y = 8) in;

layout(rgba32f, binding = 0) uniform readonly image2D accumulation; // rgb: radiance summed over `samples`
layout(rgba8, binding = 1) uniform writeonly image2D display;       // sRGB-encoded, a = 1

layout(location = 0) uniform float scale;    // exp2(exposure EV) / samples
layout(location = 1) uniform uint tonemap;   // bt::Tonemap: 0 faithful, 1 aces, 2 agx, 3 linear

const uint kFaithful = 0u;
const uint kAces = 1u;
const uint kAgx = 2u;

// Narkowicz's fit of the ACES filmic curve.
vec3 tonemapAces(vec3 x) {
  return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// AgX (Troy Sobotka), with the polynomial contrast fit by Benjamin Wrensch; linear in, linear out.
vec3 tonemapAgx(vec3 c) {
  const vec3 inRow0 = vec3(0.842479062253094, 0.0784335999999992, 0.0792237451477643);
  const vec3 inRow1 = vec3(0.0423282422610123, 0.878468636469772, 0.0791661274605434);
  const vec3 inRow2 = vec3(0.0423756549057051, 0.0784336, 0.879142973793104);
  vec3 v = vec3(dot(inRow0, c), dot(inRow1, c), dot(inRow2, c));
  const float minEv = -12.47393, maxEv = 4.026069;
  v = (clamp(log2(max(v, vec3(1e-10))), minEv, maxEv) - minEv) / (maxEv - minEv);
  vec3 x2 = v * v, x4 = x2 * x2;
  v = 15.5 * x4 * x2 - 40.14 * x4 * v + 31.96 * x4 - 6.868 * x2 * v + 0.4298 * x2 + 0.1191 * v - 0.00232;
  const vec3 outRow0 = vec3(1.19687900512017, -0.0980208811401368, -0.0990297440797205);
  const vec3 outRow1 = vec3(-0.0528968517574562, 1.15190312990417, -0.0989611768448433);
  const vec3 outRow2 = vec3(-0.0529716355144438, -0.0980434501171241, 1.15107367264116);
  vec3 outColor = max(vec3(dot(outRow0, v), dot(outRow1, v), dot(outRow2, v)), vec3(0.0));
  return pow(outColor, vec3(2.2));
}

vec3 applyTonemap(uint op, vec3 linearColor) {
  if (op == kAces) return tonemapAces(linearColor);
  if (op == kAgx) return clamp(tonemapAgx(linearColor), 0.0, 1.0);
  // Faithful: Quake clamps overbright light at the display's white; Linear the same.
  return clamp(linearColor, 0.0, 1.0);
}

float linearToSrgb(float c) {
  return c <= 0.0031308 ? c * 12.92 : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(display)))) return;
  vec3 c = applyTonemap(tonemap, imageLoad(accumulation, pixel).rgb * scale);
  imageStore(display, pixel, vec4(linearToSrgb(c.r), linearToSrgb(c.g), linearToSrgb(c.b), 1.0));
}
