// Colour transfer functions, tonemaps and texture filtering shared by the tracers.
#pragma once

#include "scene/material.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

inline float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linearToSrgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}
inline glm::vec3 srgbToLinear(const glm::vec3& c) { return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)}; }
inline glm::vec3 linearToSrgb(const glm::vec3& c) { return {linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z)}; }

// Bilinear filter with repeat wrapping; u, v in texture widths (1.0 = one repeat). Texel
// centres sit at (i + 0.5) / width, like a GL sampler with GL_LINEAR and GL_REPEAT.
// Returns the stored 8-bit values scaled to 0..1 (no transfer function applied).
inline glm::vec4 bilinearRepeat(const Image& image, float u, float v) {
  if (image.empty()) return glm::vec4(1.0f);
  const float x = u * float(image.width) - 0.5f;
  const float y = v * float(image.height) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float ax = x - fx, ay = y - fy;
  auto wrap = [](long i, int n) { long m = i % n; return int(m < 0 ? m + n : m); };
  // Coordinates far outside [0, 1) lose precision in float anyway; wrap in integers.
  const long ix = long(fx), iy = long(fy);
  const int x0 = wrap(ix, image.width), x1 = wrap(ix + 1, image.width);
  const int y0 = wrap(iy, image.height), y1 = wrap(iy + 1, image.height);
  auto texel = [&](int tx, int ty) {
    const uint8_t* p = image.texel(tx, ty);
    return glm::vec4(p[0], p[1], p[2], p[3]) * (1.0f / 255.0f);
  };
  const glm::vec4 top = texel(x0, y0) * (1.0f - ax) + texel(x1, y0) * ax;
  const glm::vec4 bottom = texel(x0, y1) * (1.0f - ax) + texel(x1, y1) * ax;
  return top * (1.0f - ay) + bottom * ay;
}

enum class Tonemap { Faithful, Aces, Agx, Linear };

// Narkowicz's fit of the ACES filmic curve.
inline glm::vec3 tonemapAces(const glm::vec3& x) {
  return glm::clamp((x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
}

// AgX (Troy Sobotka), with the polynomial contrast fit by Benjamin Wrensch; linear in, linear out.
inline glm::vec3 tonemapAgx(glm::vec3 c) {
  const glm::vec3 inRow0{0.842479062253094f, 0.0784335999999992f, 0.0792237451477643f};
  const glm::vec3 inRow1{0.0423282422610123f, 0.878468636469772f, 0.0791661274605434f};
  const glm::vec3 inRow2{0.0423756549057051f, 0.0784336f, 0.879142973793104f};
  glm::vec3 v{glm::dot(inRow0, c), glm::dot(inRow1, c), glm::dot(inRow2, c)};
  const float minEv = -12.47393f, maxEv = 4.026069f;
  for (int i = 0; i < 3; ++i) {
    const float l = std::log2(std::max(v[i], 1e-10f));
    v[i] = (std::clamp(l, minEv, maxEv) - minEv) / (maxEv - minEv);
  }
  const glm::vec3 x2 = v * v, x4 = x2 * x2;
  v = 15.5f * x4 * x2 - 40.14f * x4 * v + 31.96f * x4 - 6.868f * x2 * v + 0.4298f * x2 + 0.1191f * v - 0.00232f;
  const glm::vec3 outRow0{1.19687900512017f, -0.0980208811401368f, -0.0990297440797205f};
  const glm::vec3 outRow1{-0.0528968517574562f, 1.15190312990417f, -0.0989611768448433f};
  const glm::vec3 outRow2{-0.0529716355144438f, -0.0980434501171241f, 1.15107367264116f};
  glm::vec3 out{glm::dot(outRow0, v), glm::dot(outRow1, v), glm::dot(outRow2, v)};
  out = glm::max(out, glm::vec3(0.0f));
  return {std::pow(out.x, 2.2f), std::pow(out.y, 2.2f), std::pow(out.z, 2.2f)};
}

// Linear radiance (after exposure) to a display value in 0..1 before sRGB encoding.
inline glm::vec3 applyTonemap(Tonemap tonemap, const glm::vec3& linear) {
  switch (tonemap) {
  case Tonemap::Aces: return tonemapAces(linear);
  case Tonemap::Agx: return glm::clamp(tonemapAgx(linear), 0.0f, 1.0f);
  case Tonemap::Faithful: // Quake clamps overbright light at the display's white
  case Tonemap::Linear:
  default: return glm::clamp(linear, 0.0f, 1.0f);
  }
}

} // namespace bt
