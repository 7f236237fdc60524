// Colour transfer functions and tonemaps shared by the tracers.
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
