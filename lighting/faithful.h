// The "faithful" lighting formulas: what ericw-tools `light` computes for one light at one
// sample point (ltface.cc GetLightValue / GetLightValueWithAngle), so that a preview looks like
// the compiled game. Plain functions of plain values, written to transliterate to GLSL.
//
// Units: light values are Quake light units (the `light` key, 300 by default); distances are
// Quake units. The compiler stores `sum * _range` (0.5 by default) clamped to 255 in the
// lightmap, and the engine draws texture * lightmap / 128 ("overbright": 255 is almost 2x).
#pragma once

#include "shaders/light_constants.glsl" // the numbers, shared with the shaders
#include "scene/gpu_structs.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <vector>
#include <cmath>

namespace bt::faithful {

// ericw-tools' LF_SCALE: the inverse formulas are normalised so that at 128 units they give the
// light's own value.
inline constexpr float kFormulaScale = BT_FORMULA_SCALE;
// Quake's default `_range` (rangescale): the stored lightmap is half the light sum.
inline constexpr float kDefaultRange = 0.5f;
// Overbright: the engine maps lightmap 128 to the texture's own colour.
inline constexpr float kOverbrightOne = BT_OVERBRIGHT_ONE;

// Radiosity surface lights clamp the distance here (ltface.cc's "hotspot clamp"), so that a
// luxel right next to an emitting face does not blow up.
inline constexpr float kSurfaceHotspotClamp = BT_SURFACE_HOTSPOT_CLAMP;
// Bounce lights clamp the distance at 128 (IndirectLightFace's hotspot clamp) ...
inline constexpr float kBounceHotspotClamp = BT_BOUNCE_HOTSPOT_CLAMP;
// ... and the compiler drops a bounce light's share at a sample point when no channel of it is
// above this (LightFace_SurfaceLight's gate at the default -emissivequality): so a bounce light
// reaches a finite distance (light_grid.h faithfulReach).
inline constexpr float kBounceGate = BT_BOUNCE_GATE;

// q3map2's point and linear lights (light_ydnar.c LightContributionToSample): nothing from the
// envelope on (`falloff`), the distance clamped at 16 units, then photons / d² or, linear,
// photons × linearScale − d × fade (lighting/q3map2_light.h sets the fields).
inline float q3map2Value(const GpuLight& light, float dist) {
  if (dist >= light.falloff) return 0.0f;
  const float d = std::max(dist, BT_Q3_HOTSPOT_CLAMP);
  if (light.formula == uint32_t(LightFormula::Q3Linear)) return std::max(light.value - d * light.atten, 0.0f);
  return light.value * (kFormulaScale * kFormulaScale) / (d * d);
}

// Light value at `dist` from one copy of a point light, before the angle terms (GetLightValue).
// `atten` is the light's `wait`; ericw-tools multiplies it with the global `_dist` (scaledist).
inline float copyDistanceValue(const GpuLight& light, float dist, float scaledist) {
  const float value = light.value;
  if (light.formula == uint32_t(LightFormula::SurfaceRadiosity)) {
    const float d = std::max(dist, kSurfaceHotspotClamp);
    return value / (d * d);
  }
  if (light.formula == uint32_t(LightFormula::Bounce)) {
    const float d = std::max(dist, kBounceHotspotClamp);
    return value / (d * d);
  }
  if (light.formula == uint32_t(LightFormula::Q3Point) || light.formula == uint32_t(LightFormula::Q3Linear) ||
      light.formula == uint32_t(LightFormula::Q3Area))
    return q3map2Value(light, dist);
  if (light.falloff > 0.0f && light.formula == uint32_t(LightFormula::Linear))
    return dist < light.falloff ? value * (1.0f - dist / light.falloff) : 0.0f;

  const LightFormula formula = LightFormula(light.formula);
  if (formula == LightFormula::Infinite || formula == LightFormula::LocalMin) return value;

  float scaled = scaledist * light.atten * dist;
  switch (formula) {
  case LightFormula::Inverse: return value / (std::max(scaled, 1e-3f) / kFormulaScale);
  case LightFormula::Inverse2A: scaled += kFormulaScale; return value / ((scaled * scaled) / (kFormulaScale * kFormulaScale));
  case LightFormula::Inverse2: scaled = std::max(scaled, 1e-3f); return value / ((scaled * scaled) / (kFormulaScale * kFormulaScale));
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

// q3map2's spotlight cone (LightContributionToSample): the cone's radius grows by radiusByDist
// (`cosInner`) per unit along the axis; a point outside gets nothing, one within 32 units of its
// edge a linear fade. `toLight` is unit, `dist` the distance to the light.
inline float q3map2SpotTerm(const GpuLight& light, const glm::vec3& toLight, float dist) {
  if (!(light.flags & kLightFlagQ3Spot)) return 1.0f;
  const float along = -glm::dot(light.direction, toLight) * dist;
  if (along < 0.0f) return 0.0f;
  const float radiusAtDist = light.cosInner * along;
  const float sampleRadius = std::sqrt(std::max(dist * dist - along * along, 0.0f));
  if (sampleRadius >= radiusAtDist) return 0.0f;
  return std::min((radiusAtDist - sampleRadius) / BT_Q3_SPOT_EDGE, 1.0f);
}

// GetSurfaceLighting's tolerance (LIGHT_ANGLE_EPSILON): a radiosity point lights a receiver this
// little behind its face (in cosine), and a receiver facing this little away from it, such as the
// faces in its own plane.
inline constexpr float kLightAngleEpsilon = BT_LIGHT_ANGLE_EPSILON;

// The cosine below which a light gives nothing: 0, or -kLightAngleEpsilon for a radiosity point.
inline float behindCosine(const GpuLight& light) {
  return light.formula == uint32_t(LightFormula::SurfaceRadiosity) ? -kLightAngleEpsilon : 0.0f;
}

// A radiosity surface light point shines into the half-space in front of its face, with the
// same half-Lambert (0.5 + 0.5 cos) on its side as on the receiver's (ltface.cc
// GetSurfaceLighting, "rescale"); a bounce light and a q3map2 area light (light.c
// LightContributionToSample, `-faster`: angle *= -dot(light normal, direction)) with the plain
// cosine; 1 for every other light.
inline float emitterTerm(const GpuLight& light, const glm::vec3& toLight) {
  const bool radiosity = light.formula == uint32_t(LightFormula::SurfaceRadiosity);
  if (!radiosity && light.formula != uint32_t(LightFormula::Bounce) && light.formula != uint32_t(LightFormula::Q3Area)) return 1.0f;
  const float cosEmit = -glm::dot(light.direction, toLight);
  if (cosEmit < behindCosine(light)) return 0.0f;
  return radiosity ? angleTerm(cosEmit, 0.5f) : cosEmit;
}

// A negative light that the compiler subtracts after the floors (ltface.cc: "cast all positive
// lights, fix minlight levels, then cast all negative lights", DirectLightFace then
// PostProcessLightFace): a point light or sun entity of negative value, not a local minlight.
// Soft ones (`_deviance`, a penumbra) stay in the sum before the floors (not modelled).
inline bool subtractedLight(const GpuLight& light) {
  return light.value < 0.0f && light.deviance <= 0.0f && light.formula <= uint32_t(LightFormula::Inverse2A) &&
      light.formula != uint32_t(LightFormula::LocalMin) &&
      (light.type == uint32_t(LightType::Point) || light.type == uint32_t(LightType::Sun));
}

// The brightest channel a light's value is spread over: what the bounce gate compares.
inline float maxChannel(const glm::vec3& c) {
  return std::max({c.x, c.y, c.z});
}

// One point light's contribution at a surface point with unit normal `normal`
// (GetLightValueWithAngle). `toLight` is unit, from the surface to the light.
inline float pointLightValue(const GpuLight& light, const glm::vec3& normal, const glm::vec3& toLight, float dist, float scaledist = 1.0f) {
  float cosIncidence = glm::dot(toLight, normal);
  if (light.flags & kLightFlagBleed) cosIncidence = std::abs(cosIncidence);
  if (cosIncidence < behindCosine(light)) return 0.0f; // behind the surface: nothing, whatever the anglescale
  const float value = distanceValue(light, dist, scaledist) * angleTerm(cosIncidence, light.anglescale) * spotTerm(light, toLight) *
      emitterTerm(light, toLight) * q3map2SpotTerm(light, toLight, dist);
  if (light.formula == uint32_t(LightFormula::Bounce) && value * maxChannel(light.color) <= kBounceGate) return 0.0f;
  return value;
}

// The minlight a face gets from its material's _surface template (value 0 = no template):
// ericw-tools lights the faces of a radiosity surface light at least at the template's value x
// `_surflight_minlight_scale`, in its colour.
inline glm::vec3 surfaceFaceMinlight(const GpuLight& surfaceTemplate) {
  if (!(surfaceTemplate.flags & kLightFlagFaceMinlight)) return glm::vec3(0.0f);
  return surfaceTemplate.value * surfaceTemplate.faithfulScale * surfaceTemplate.color;
}

// ericw-tools' LightFace_Sky skips a face only when a sun lies more than ANGLE_EPSILON (in cosine)
// behind its plane, then takes (1 - a) + a max(0, cos): a sun along the face's plane (a dome's
// zenith on a wall, its ring suns square to the wall, a sun straight down) still gives the wall
// (1 - a) of its value, where the ray reaches the sky. The same for every sun and dome sun.
inline constexpr float kSunAngleEpsilon = BT_SUN_ANGLE_EPSILON;
// The angle term of a sun (or dome sun) towards which the face turns by cosIncidence; 0 when it
// is behind the face.
inline float sunAngleTerm(float cosIncidence, float anglescale) {
  if (cosIncidence < -kSunAngleEpsilon) return 0.0f;
  return angleTerm(std::max(cosIncidence, 0.0f), anglescale);
}

// A sun's contribution: no distance falloff, the angle term only (sky visibility is the
// caller's shadow test).
inline float sunValue(const GpuLight& sun, const glm::vec3& normal) {
  return sun.value * sunAngleTerm(glm::dot(-sun.direction, normal), sun.anglescale);
}

// --- Dirt (ericw-tools' dirtmapping, from q3map2: a fake ambient occlusion) ---------------
// At each sample point the compiler casts rays into a cone around the normal and averages how
// far they get (a hit beyond `_dirtdepth` counts as `_dirtdepth`): occlusion = 1 - mean / depth,
// 0 in the open, 1 with a wall right on the point. Each light dimmed by dirt is multiplied by
// 1 - dirt, dirt = min(1, min(1, occlusion ^ gain) x scale).

// `_dirtmode 0`: the fixed pattern, 16 azimuths x 3 elevations (at 1/6, 3/6 and 5/6 of the
// cone's half-angle).
inline constexpr int kDirtAzimuthSteps = BT_DIRT_AZIMUTH_STEPS;
inline constexpr int kDirtElevationSteps = BT_DIRT_ELEVATION_STEPS;
inline constexpr int kDirtRays = kDirtAzimuthSteps * kDirtElevationSteps;
// The compiler's sample points sit this far off the face (ltface.cc sampleOffPlaneDist); the
// occlusion rays leave from there.
// ericw-tools' `-sunsamples` (64): how many suns a sky dome or a sun's penumbra becomes.
inline constexpr int kSunSamples = BT_SUN_SAMPLES;

// The directions towards the sky of q3map2's sky dome (2.5.17 CreateSkyLights, for
// q3map_skylight; ericw-tools' SetupSkyDome took it from there): `iterations` - 1 rings of
// 4 (iterations - 1) suns at equal elevation steps, each ring turned by a fraction of a step,
// plus one straight up. Fewer than 2 iterations: none.
inline std::vector<glm::vec3> skyDomeRings(int iterations) {
  std::vector<glm::vec3> toSky;
  if (iterations < 2) return toSky;
  const int elevationSteps = iterations - 1, angleSteps = elevationSteps * 4;
  const float elevationStep = glm::radians(90.0f / float(iterations));
  const float angleStep = glm::radians(360.0f / float(angleSteps));
  float angle = 0.0f, elevation = elevationStep * 0.5f;
  for (int i = 0; i < elevationSteps; ++i) {
    for (int j = 0; j < angleSteps; ++j) {
      toSky.emplace_back(std::cos(angle) * std::cos(elevation), std::sin(angle) * std::cos(elevation), std::sin(elevation));
      angle += angleStep;
    }
    elevation += elevationStep;
    angle += angleStep / float(elevationSteps);
  }
  toSky.emplace_back(0.0f, 0.0f, 1.0f);
  return toSky;
}

// ericw-tools' upper sky dome: `kSunSamples` 64 gives 4 rings of 16 and the zenith, 65 suns
// sharing the value. The lower dome is the same with z negated.
inline std::vector<glm::vec3> skyDomeDirections(int sunSamples = kSunSamples) {
  return skyDomeRings(std::max(int(std::lround(std::sqrt(double(sunSamples - 1) / 4.0))) + 1, 2));
}

inline constexpr float kDirtSampleLift = BT_DIRT_SAMPLE_LIFT;
// A point light nearer than this to the point it lights counts as this far, straight up (+z), as
// GetLightContrib takes it: a radiosity `_surface` point can sit on a luxel's sample point.
inline constexpr float kNearestLight = BT_NEAREST_LIGHT;

// Ray `index` of the fixed pattern in the sample's tangent space (z along the normal), for a
// cone of half-angle `coneRadians`; azimuth-major, as SetupDirt orders them.
inline glm::vec3 dirtPatternVector(int index, float coneRadians) {
  const float azimuth = float(index / kDirtElevationSteps) * (2.0f * 3.14159265358979f / float(kDirtAzimuthSteps));
  const float elevation = (float(index % kDirtElevationSteps) + 0.5f) * (coneRadians / float(kDirtElevationSteps));
  return {std::sin(elevation) * std::cos(azimuth), std::sin(elevation) * std::sin(azimuth), std::cos(elevation)};
}

// `_dirtmode 1`: a random direction of the cone from two uniform numbers (azimuth, elevation;
// uniform in angle, not in solid angle, as the compiler draws them).
inline glm::vec3 dirtRandomVector(float u0, float u1, float coneRadians) {
  const float azimuth = u0 * 2.0f * 3.14159265358979f;
  const float elevation = u1 * coneRadians;
  return {std::cos(azimuth) * std::sin(elevation), std::sin(azimuth) * std::sin(elevation), std::cos(elevation)};
}

// The tangent frame the compiler turns the pattern into (qvec MakeTangentAndBitangentUnnormalized):
// built from the unit axes after the normal's largest component, so the pattern's azimuth
// depends on the face's orientation. Returns the direction of tangent-space vector `v`.
inline glm::vec3 dirtRayDirection(const glm::vec3& n, const glm::vec3& v) {
  int axis = 0;
  float largest = 0.0f;
  for (int i = 0; i < 3; ++i)
    if (std::abs(n[i]) > largest) largest = std::abs(n[i]), axis = i;
  glm::vec3 a(0.0f), b(0.0f);
  a[(axis + 1) % 3] = 1.0f;
  b[(axis + 2) % 3] = 1.0f;
  glm::vec3 tangent = glm::cross(n, a), bitangent = glm::cross(n, b);
  if (glm::dot(glm::cross(tangent, bitangent), n) < 0.0f) std::swap(tangent, bitangent);
  return glm::normalize(bitangent) * v.x + glm::normalize(tangent) * v.y + n * v.z;
}

// Occlusion from the summed ray distances (each already clamped to `depth`) of `rays` rays.
inline float dirtOcclusion(float distanceSum, int rays, float depth) {
  return 1.0f - distanceSum / (float(rays) * depth);
}

// How much dirt takes away at this occlusion, 0..1 (Dirt_GetScaleFactor before the radius ramp).
inline float dirtAmount(float occlusion, float gain, float scale) {
  if (occlusion <= 0.0f) return 0.0f;
  return std::min(std::min(std::pow(occlusion, gain), 1.0f) * scale, 1.0f);
}

// The factor dirt leaves of one light at a point `dist` from it (1 for lights without dirt).
inline float lightDirtFactor(const GpuLight& light, float occlusion, float dist) {
  if (!(light.flags & kLightFlagDirt)) return 1.0f;
  float dirt = dirtAmount(occlusion, light.dirtGain, light.dirtScale);
  if (light.flags & kLightFlagDirtRadius) {
    if (dist < light.dirtOffRadius)
      dirt = 0.0f;
    else if (dist < light.dirtOnRadius)
      dirt *= (dist - light.dirtOffRadius) / (light.dirtOnRadius - light.dirtOffRadius);
  }
  return 1.0f - dirt;
}

// The value the compiler stores in the lightmap for a light sum.
inline float lightmapValue(float lightSum, float range = kDefaultRange) {
  return std::clamp(lightSum * range, 0.0f, 255.0f);
}

} // namespace bt::faithful
