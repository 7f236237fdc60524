#include "lighting/q3map2_light.h"

#include "lighting/faithful.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt::q3map2 {

namespace {

// q3map2 reads keys with atof: the first number of the value, 0 when there is none.
float firstNumber(const quake::EntityKeys& keys, std::string_view key) {
  const std::string* text = keys.find(key);
  if (!text) return 0.0f;
  const auto numbers = quake::parseNumbers(*text);
  return numbers && !numbers->empty() && std::isfinite((*numbers)[0]) ? float((*numbers)[0]) : 0.0f;
}

// mathlib ColorNormalize: the brightest channel becomes 1; black becomes white.
glm::vec3 colorNormalize(glm::vec3 c) {
  const float peak = std::max({c.x, c.y, c.z});
  return peak == 0.0f ? glm::vec3(1.0f) : c / peak;
}

const Entity* findTarget(const Scene& scene, std::string_view targetname) {
  for (const Entity& e : scene.entities)
    if (e.value("targetname") == targetname) return &e;
  return nullptr;
}

// The light entity's keys as CreateEntityLights reads them, before the spotlight and the jitter.
struct EntityLight {
  glm::vec3 origin{0.0f};
  glm::vec3 color{1.0f};
  float intensity = kDefaultLight; // `_light` / `light` × `scale`, then / `_samples`
  int samples = 1;
  float deviance = 0.0f;
  bool linear = false;
  bool angle = true;
  float fade = 1.0f;
};

EntityLight readEntityLight(const quake::EntityKeys& keys) {
  EntityLight l;
  const int spawnflags = keys.integer("spawnflags", 0);
  l.linear = (spawnflags & 1) != 0;                             // LIGHT_ATTEN_LINEAR, and no angle attenuation
  l.angle = !(spawnflags & 3);                                  // 2: LIGHT_ATTEN_ANGLE off
  if (firstNumber(keys, "_anglescale") != 0.0f) l.angle = true; // vlight's key turns the angle back on
  if (spawnflags & 12) keys.warn("q3map2 dark lights (spawnflags 4 / 8) are not modelled; lit as an ordinary light");
  if (l.linear && firstNumber(keys, "fade") != 0.0f) l.fade = firstNumber(keys, "fade");

  float intensity = firstNumber(keys, "_light");
  if (intensity == 0.0f) intensity = firstNumber(keys, "light");
  if (intensity == 0.0f) intensity = kDefaultLight;
  if (const float scale = firstNumber(keys, "scale"); scale != 0.0f) intensity *= scale;
  float deviance = firstNumber(keys, "_deviance");
  if (deviance == 0.0f) deviance = firstNumber(keys, "_deviation");
  if (deviance == 0.0f) deviance = firstNumber(keys, "_jitter");
  l.samples = std::max(1, int(firstNumber(keys, "_samples")));
  l.deviance = std::max(deviance, 0.0f);
  l.intensity = intensity / float(l.samples);
  if (auto c = keys.vec3("_color")) l.color = spawnflags & 32 ? glm::max(*c, glm::vec3(0.0f)) : colorNormalize(*c);
  return l;
}

// A targeted light with `_sun 1`: CreateSunLight's sun along the light's axis, photons × cos
// where a ray towards it reaches sky. Its `_samples` suns split the already split intensity again.
GpuLight sunLight(const EntityLight& l, const glm::vec3& axis) {
  GpuLight sun;
  sun.type = uint32_t(LightType::Sun);
  sun.value = l.intensity;
  sun.color = l.color;
  sun.direction = axis;
  sun.anglescale = 1.0f;
  sun.deviance = glm::radians(l.deviance);
  return sun;
}

// The point light of one q3map2 light: per copy photons / samples, each copy with its own
// envelope (falloffTolerance / samples); faithful mode sums `samples` copies.
GpuLight pointLight(const EntityLight& l, float photons) {
  GpuLight light;
  light.type = uint32_t(LightType::Point);
  light.origin = l.origin;
  light.color = l.color;
  light.anglescale = l.angle ? 1.0f : 0.0f;
  light.faithfulScale = float(l.samples);
  if (l.samples > 1) light.deviance = l.deviance;
  const float tolerance = kFalloffTolerance / float(l.samples);
  if (l.linear) {
    light.formula = uint32_t(LightFormula::Q3Linear);
    light.value = photons * kLinearScale;
    light.atten = l.fade;
    light.falloff = (light.value - tolerance) / l.fade;
  } else {
    light.formula = uint32_t(LightFormula::Q3Point);
    light.value = photons / (faithful::kFormulaScale * faithful::kFormulaScale);
    light.falloff = std::sqrt(photons / tolerance);
  }
  return light;
}

void addLightEntity(const Scene& scene, const Entity& entity, const LightOptions& options, SceneLights& out, Diagnostics& diagnostics) {
  quake::EntityKeys keys(entity, scene.sourcePath, &diagnostics);
  EntityLight l = readEntityLight(keys);
  if (auto origin = keys.vec3("origin")) {
    l.origin = *origin;
  } else {
    keys.warn("light without a valid origin; ignored");
    return;
  }
  int style = keys.integer("_style", 0);
  if (style == 0) style = keys.integer("style", 0);
  if (options.styleZeroOnly && style != 0) return;

  float photons = l.intensity * kPointScale;
  std::optional<glm::vec3> axis;
  float radiusByDist = 0.0f;
  if (const std::string* target = entity.find("target"); target && !target->empty()) {
    const Entity* t = findTarget(scene, *target);
    if (!t) {
      keys.warn(fmt::format("target \"{}\" not found; light is not a spotlight", *target));
    } else {
      const glm::vec3 to = quake::parseVec3(t->value("origin")).value_or(glm::vec3(0.0f)) - l.origin;
      float dist = glm::length(to);
      axis = dist > 0.0f ? to / dist : glm::vec3(0.0f);
      if (dist == 0.0f) dist = 64.0f;
      float radius = firstNumber(keys, "radius");
      if (radius == 0.0f) radius = kDefaultSpotRadius;
      radiusByDist = (radius + 16.0f) / dist;
      if (keys.integer("_sun", 0) == 1) {
        out.lights.push_back(sunLight(l, *axis));
        return;
      }
      l.linear = false; // spotlights always fall off as inverse square, with the angle
      l.angle = true;
      l.fade = 1.0f;
      photons = l.intensity * kSpotScale;
    }
  }
  GpuLight light = pointLight(l, photons);
  if (axis) {
    light.flags |= kLightFlagQ3Spot;
    light.direction = *axis;
    light.cosInner = radiusByDist;
  }
  light.flags |= uint32_t(std::clamp(style, 0, 255)) << 8;
  light.color *= options.styleScale[size_t(std::clamp(style, 0, 255))]; // the viewer's style sliders
  out.lights.push_back(light);
}

} // namespace

void readWorld(const Scene& scene, WorldLighting& world, Diagnostics& diagnostics) {
  const Entity* ws = scene.worldspawn();
  if (!ws) return;
  quake::EntityKeys keys(*ws, scene.sourcePath, &diagnostics);
  // light.c LightMain: the worldspawn `_color` (not normalised; white when unset or black)
  // scales `_minlight` and `_ambient`.
  glm::vec3 color = keys.vec3("_color").value_or(glm::vec3(0.0f));
  if (glm::length(color) == 0.0f) color = glm::vec3(1.0f);
  world.minlight = firstNumber(keys, "_minlight") * color;
  // LightingAtSample starts every sample's sum at ambientColor before the lights.
  float ambient = firstNumber(keys, "_ambient");
  if (ambient == 0.0f) ambient = firstNumber(keys, "ambient");
  world.ambient = ambient * color;
}

void addLightEntities(const Scene& scene, const LightOptions& options, SceneLights& out, Diagnostics& diagnostics) {
  for (const Entity& entity : scene.entities)
    if (entity.classname().starts_with("light")) addLightEntity(scene, entity, options, out, diagnostics);
}

} // namespace bt::q3map2
