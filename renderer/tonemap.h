// The display's tonemap operators, the same in both tracers: shaders/tonemap.comp computes them
// from the same constants.
#pragma once

#include "shaders/tonemap_constants.glsl" // shared with shaders/tonemap.comp

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

enum class Tonemap { Faithful, Aces, Agx, Linear };

// Narkowicz's fit of the ACES filmic curve.
inline glm::vec3 tonemapAces(const glm::vec3& x) {
  return glm::clamp((x * (BT_ACES_A * x + BT_ACES_B)) / (x * (BT_ACES_C * x + BT_ACES_D) + BT_ACES_E), 0.0f, 1.0f);
}

// AgX (Troy Sobotka), with the polynomial contrast fit by Benjamin Wrensch; linear in, linear out.
inline glm::vec3 tonemapAgx(glm::vec3 c) {
  const glm::vec3 inRow0{BT_AGX_IN_ROW0};
  const glm::vec3 inRow1{BT_AGX_IN_ROW1};
  const glm::vec3 inRow2{BT_AGX_IN_ROW2};
  glm::vec3 v{glm::dot(inRow0, c), glm::dot(inRow1, c), glm::dot(inRow2, c)};
  const float minEv = BT_AGX_MIN_EV, maxEv = BT_AGX_MAX_EV;
  for (int i = 0; i < 3; ++i) {
    const float l = std::log2(std::max(v[i], 1e-10f));
    v[i] = (std::clamp(l, minEv, maxEv) - minEv) / (maxEv - minEv);
  }
  const glm::vec3 x2 = v * v, x4 = x2 * x2;
  v = BT_AGX_POLY6 * x4 * x2 + BT_AGX_POLY5 * x4 * v + BT_AGX_POLY4 * x4 + BT_AGX_POLY3 * x2 * v + BT_AGX_POLY2 * x2 + BT_AGX_POLY1 * v +
      BT_AGX_POLY0;
  const glm::vec3 outRow0{BT_AGX_OUT_ROW0};
  const glm::vec3 outRow1{BT_AGX_OUT_ROW1};
  const glm::vec3 outRow2{BT_AGX_OUT_ROW2};
  glm::vec3 out{glm::dot(outRow0, v), glm::dot(outRow1, v), glm::dot(outRow2, v)};
  out = glm::max(out, glm::vec3(0.0f));
  return {std::pow(out.x, BT_AGX_GAMMA), std::pow(out.y, BT_AGX_GAMMA), std::pow(out.z, BT_AGX_GAMMA)};
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
