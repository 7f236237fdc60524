// Physical mode's point lights keep the reach the mapper tuned (lighting/README.md, "Physical
// mode", key by key): an inverse-square source whose light is windowed to zero where the
// compiler's formula reaches zero (linear lights: `_falloff`, or `light` / (`wait` x `_dist`)) or
// falls below kPhysicalReachThreshold (the inverse formulas), and whose intensity matches the
// compiler's light: over the surfaces its light lands on for Quake's point lights in a level
// (lighting/physical_reference.h, which overwrites what prepare() below gives), else at the
// reference distance matchDistance() gives. shaders/light_select.glsl computes the same.
#pragma once

#include "lighting/faithful.h"
#include "scene/color.h"
#include "scene/gpu_structs.h"
#include "shaders/light_constants.glsl"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace bt::physical {

// Light units (the compiler's light at a point) below which an inverse-formula light ends.
inline constexpr float kReachThreshold = BT_PHYSICAL_REACH_THRESHOLD;

// Where the light ends: the distance its compiled light reaches zero (linear) or the threshold
// (inverse, inverse square); infinity for lights that never fall off (delay 3).
inline float reach(const GpuLight& light, float scaledist) {
  const float s = std::max(scaledist * light.atten, 1e-6f), value = std::abs(light.value);
  switch (LightFormula(light.formula)) {
  case LightFormula::Linear: return light.falloff > 0.0f ? light.falloff : value / s;
  case LightFormula::Inverse: return value / kReachThreshold * BT_FORMULA_SCALE / s;
  case LightFormula::Inverse2: return std::sqrt(value / kReachThreshold) * BT_FORMULA_SCALE / s;
  case LightFormula::Inverse2A: return std::max(std::sqrt(value / kReachThreshold) - 1.0f, 0.0f) * BT_FORMULA_SCALE / s;
  case LightFormula::Q3Point:
  case LightFormula::Q3Area:
  case LightFormula::Q3Linear: return light.falloff; // q3map2's envelope
  default: return std::numeric_limits<float>::infinity();
  }
}

// The windowed falloff of Karis, "Real Shading in Unreal Engine 4" (SIGGRAPH 2013 course
// notes): (1 - (d / reach)^4)^2 clamped to [0, 1]; 1 near the light, smooth to 0 at the reach.
inline float window(float dist, float reachDistance) {
  const float x = dist / reachDistance, x2 = x * x;
  const float w = std::clamp(1.0f - x2 * x2, 0.0f, 1.0f);
  return w * w;
}

// The distance at which the physical light matches the compiled one where its landings are not
// measured (physical_reference.h: q3map2's lights, lights listed by hand, none landing): for a
// linear light 128 units (the formulas' unit, a typical distance from a Quake light to the walls it lights), or
// half its reach (where the compiler gives half its value) where that is nearer: an inverse
// square matched at half a long reach (low `wait`) is many times the compiler's light on the
// walls near it; the formula's own unit (128 / (wait x `_dist`)) for the inverse formulas (where
// inverse and inverse square give exactly `light`); for q3map2's inverse-square lights 128
// units, or half their envelope where that is nearer; half the envelope of its linear ones.
inline float matchDistance(const GpuLight& light, float scaledist) {
  if (light.formula == uint32_t(LightFormula::Q3Linear)) return 0.5f * reach(light, scaledist);
  if (light.formula == uint32_t(LightFormula::Linear) || light.formula == uint32_t(LightFormula::Q3Point) ||
      light.formula == uint32_t(LightFormula::Q3Area))
    return std::min(BT_FORMULA_SCALE, 0.5f * reach(light, scaledist));
  return BT_FORMULA_SCALE / std::max(scaledist * light.atten, 1e-6f);
}

// Intensity in light units x distance^2: intensity / d^2 x window(d) at the match distance
// equals the compiler's light there, head-on (before `_range` and the physical unit).
// `r`: reach(light, scaledist), which the caller may have at hand.
inline float intensity(const GpuLight& light, float scaledist, float r) {
  const float d = matchDistance(light, scaledist);
  const float compiled = faithful::copyDistanceValue(light, d, scaledist);
  const float w = std::isfinite(r) ? window(d, r) : 1.0f;
  return w > 0.0f ? compiled * d * d / w : 0.0f;
}
inline float intensity(const GpuLight& light, float scaledist) {
  return intensity(light, scaledist, reach(light, scaledist));
}

// A light's colour as physical mode emits it, per unit of its brightest channel. The compiler's
// colour (`_color`, the Half-Life form's, `_sunlight_color`, a `_surface` template's,
// `_minlight_color`) is the one the game shows: its lightmap multiplies the texture in gamma
// space, so a channel at a fraction c of the brightest one shows sRGB-to-linear(c) of the
// brightest one's linear light (faithful mode's display, the same curve). Physical light is
// linear, so each channel's share is linearised; the brightest channel is 1, on which the
// intensity is matched. White is (1, 1, 1); "255 127 0" is (1, 0.21, 0), the game's orange,
// where the colour used as linear, (1, 0.5, 0), shows a yellow.
// The brightest channel (and every channel of a white light, most of a level's) is exactly 1,
// whose sRGB decode is exactly 1 ((1 + 0.055) / 1.055 rounds to 1, and pow(1, y) is 1): no pow
// for it. The CPU tracer calls this for every light it samples.
inline float hueChannel(float share) {
  return share == 1.0f ? 1.0f : srgbToLinear(share);
}
inline glm::vec3 hue(const glm::vec3& c) {
  const float m = faithful::maxChannel(c);
  if (!(m > 0.0f)) return glm::vec3(0.0f);
  const glm::vec3 share = c / m;
  return {hueChannel(share.x), hueChannel(share.y), hueChannel(share.z)};
}

// The colour physical mode emits: the brightest channel kept, the others as hue() has them.
// Scaling c scales it alike (the viewer's style sliders scale GpuLight::color). GLSL
// physicalColour (shaders/pathtrace.comp) computes the same.
inline glm::vec3 colour(const glm::vec3& c) {
  return faithful::maxChannel(c) * hue(c);
}

// The emitted colour's channels summed: what light selection weighs a light's colour by (the
// light tree, the near lists' ranking and their pick), so that each light is picked in
// proportion to the light it gives, in both tracers. From a prepared light it costs no pow:
// selectionColour below.
inline float hueSum(const glm::vec3& c) {
  const glm::vec3 h = hue(c);
  return h.x + h.y + h.z;
}
inline float colourSum(const glm::vec3& c) {
  return faithful::maxChannel(c) * hueSum(c);
}

// Stores what the tracers' light loops read instead of deriving it per sample
// (GpuLight::physical*): the intensity, 1 / reach, and the hue's channel sum. buildRenderScene
// prepares every light; the hue sum does not change when the style sliders scale the colour.
inline void prepare(GpuLight& light, float scaledist) {
  const float r = reach(light, scaledist);
  light.physicalIntensity = intensity(light, scaledist, r);
  light.physicalInvReach = std::isfinite(r) && r > 0.0f ? 1.0f / r : 0.0f;
  light.physicalHueSum = hueSum(light.color);
}

// A prepared light's colourSum, the style sliders' scale included: its brightest channel times
// the prepared hue sum, no pow. GLSL selectionWeight (shaders/light_select.glsl) computes the same.
inline float selectionColour(const GpuLight& light) {
  return faithful::maxChannel(light.color) * light.physicalHueSum;
}

// The prepared light's windowed irradiance factor at squared distance dist2: intensity x
// window / dist^2, the window as window() with x = dist / reach (1 everywhere for 1 / reach 0).
inline float falloff(const GpuLight& light, float dist2) {
  const float x2 = dist2 * light.physicalInvReach * light.physicalInvReach;
  const float w = std::clamp(1.0f - x2 * x2, 0.0f, 1.0f);
  return light.physicalIntensity * (w * w) / dist2;
}

// How likely light selection picks a point light from the near list: its unshadowed
// irradiance at `origin` on the plane of shading normal n, summed over the channels of the colour
// it emits (selectionColour; at the light's own origin: the pick does not depend on the
// _deviance jitter). The CPU's pick computes it four lights at a time, lane by lane these float
// operations in their order (renderer/cpu/integrator.cpp nearListWeights).
inline float selectionWeight(const GpuLight& light, const glm::vec3& origin, const glm::vec3& n) {
  const glm::vec3 d = light.origin - origin;
  const float dist2 = glm::dot(d, d);
  if (!(dist2 > 0.0f)) return 0.0f;
  const glm::vec3 wi = d / std::sqrt(dist2);
  const float cosSurface = glm::dot(n, wi);
  if (cosSurface <= 0.0f) return 0.0f;
  return selectionColour(light) * falloff(light, dist2) * faithful::spotTerm(light, wi) * cosSurface;
}

} // namespace bt::physical
