// The "faithful" lighting formulas: what ericw-tools `light` computes for one light at one
// sample point (ltface.cc GetLightValue / GetLightValueWithAngle), so that a preview looks like
// the compiled game. Plain functions of plain values, written to transliterate to GLSL.
//
// Units: light values are Quake light units (the `light` key, 300 by default); distances are
// Quake units. The compiler stores `sum * _range` (0.5 by default) clamped to 255 in the
// lightmap, and the engine draws texture * lightmap / 128 ("overbright": 255 is almost 2x).
#pragma once

#include "scene/gpu_structs.h"

#include <glm/geometric.hpp>

#include <algorithm>

namespace bt::faithful {

// ericw-tools' LF_SCALE: the inverse formulas are normalised so that at 128 units they give the
// light's own value.
inline constexpr float kFormulaScale = 128.0f;
// Quake's default `_range` (rangescale): the stored lightmap is half the light sum.
inline constexpr float kDefaultRange = 0.5f;
// Overbright: the engine maps lightmap 128 to the texture's own colour.
inline constexpr float kOverbrightOne = 128.0f;

// Radiosity surface lights clamp the distance here (ltface.cc's "hotspot clamp"), so that a
// luxel right next to an emitting face does not blow up.
inline constexpr float kSurfaceHotspotClamp = 16.0f;

// Light value at `dist` from one copy of a point light, before the angle terms (GetLightValue).
// `atten` is the light's `wait`; ericw-tools multiplies it with the global `_dist` (scaledist).
inline float copyDistanceValue(const GpuLight& light, float dist, float scaledist) {
  const float value = light.value;
  if (light.formula == uint32_t(LightFormula::SurfaceRadiosity)) {
    const float d = std::max(dist, kSurfaceHotspotClamp);
    return value / (d * d);
  }
  if (light.falloff > 0.0f && light.formula == uint32_t(LightFormula::Linear))
    return dist < light.falloff ? value * (1.0f - dist / light.falloff) : 0.0f;

  const LightFormula formula = LightFormula(light.formula);
  if (formula == LightFormula::Infinite || formula == LightFormula::LocalMin) return value;

  float scaled = scaledist * light.atten * dist;
  switch (formula) {
  case LightFormula::Inverse:
    return value / (std::max(scaled, 1e-3f) / kFormulaScale);
  case LightFormula::Inverse2A:
    scaled += kFormulaScale;
    return value / ((scaled * scaled) / (kFormulaScale * kFormulaScale));
  case LightFormula::Inverse2:
    scaled = std::max(scaled, 1e-3f);
    return value / ((scaled * scaled) / (kFormulaScale * kFormulaScale));
  case LightFormula::Linear:
  default:
    // Negative lights ("darklights") fall off towards zero from below.
    if (value > 0.0f) return std::max(value - scaled, 0.0f);
    return std::min(value + scaled, 0.0f);
  }
}

// ... and summed over the light's copies (faithfulScale: ericw-tools' unsplit jittered copies).
inline float distanceValue(const GpuLight& light, float dist, float scaledist = 1.0f) {
  return light.faithfulScale * copyDistanceValue(light, dist, scaledist);
}

// Half-Lambert: anglescale 0.5 lights a grazing surface at half strength instead of zero,
// which is why Quake's lighting looks soft.
inline float angleTerm(float cosIncidence, float anglescale) {
  return (1.0f - anglescale) + anglescale * cosIncidence;
}

// Spotlight cone: 1 inside the soft angle, 0 outside the cone, linear in cosine between.
// `toLight` points from the surface to the light.
inline float spotTerm(const GpuLight& light, const glm::vec3& toLight) {
  if (light.cosOuter < -1.0f) return 1.0f;
  const float cosAxis = -glm::dot(light.direction, toLight);
  if (cosAxis < light.cosOuter) return 0.0f;
  if (cosAxis >= light.cosInner) return 1.0f;
  return (cosAxis - light.cosOuter) / (light.cosInner - light.cosOuter);
}

// A radiosity surface light point shines into the half-space in front of its face, with the
// same half-Lambert (0.5 + 0.5 cos) on its side as on the receiver's (ltface.cc
// GetSurfaceLighting, "rescale"); 1 for every other light.
inline float emitterTerm(const GpuLight& light, const glm::vec3& toLight) {
  if (light.formula != uint32_t(LightFormula::SurfaceRadiosity)) return 1.0f;
  const float cosEmit = -glm::dot(light.direction, toLight);
  return cosEmit < 0.0f ? 0.0f : angleTerm(cosEmit, 0.5f);
}

// One point light's contribution at a surface point with unit normal `normal`
// (GetLightValueWithAngle). `toLight` is unit, from the surface to the light.
inline float pointLightValue(const GpuLight& light, const glm::vec3& normal, const glm::vec3& toLight,
                             float dist, float scaledist = 1.0f) {
  float cosIncidence = glm::dot(toLight, normal);
  if (light.flags & kLightFlagBleed) cosIncidence = std::abs(cosIncidence);
  if (cosIncidence < 0.0f) return 0.0f; // behind the surface: nothing, whatever the anglescale
  return distanceValue(light, dist, scaledist) * angleTerm(cosIncidence, light.anglescale) * spotTerm(light, toLight) *
         emitterTerm(light, toLight);
}

// The minlight a face gets from its material's _surface template (value 0 = no template):
// ericw-tools lights the faces of a radiosity surface light at least at the template's value x
// `_surflight_minlight_scale`, in its colour.
inline glm::vec3 surfaceFaceMinlight(const GpuLight& surfaceTemplate) {
  if (!(surfaceTemplate.flags & kLightFlagFaceMinlight)) return glm::vec3(0.0f);
  return surfaceTemplate.value * surfaceTemplate.faithfulScale * surfaceTemplate.color;
}

// A sun's contribution: no distance falloff, the angle term only (sky visibility is the
// caller's shadow test).
inline float sunValue(const GpuLight& sun, const glm::vec3& normal) {
  const float cosIncidence = glm::dot(-sun.direction, normal);
  if (cosIncidence < 0.0f) return 0.0f;
  return sun.value * angleTerm(cosIncidence, sun.anglescale);
}

// The value the compiler stores in the lightmap for a light sum.
inline float lightmapValue(float lightSum, float range = kDefaultRange) {
  return std::clamp(lightSum * range, 0.0f, 255.0f);
}

} // namespace bt::faithful
