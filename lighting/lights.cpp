#include "lighting/lights.h"

#include "lighting/faithful.h"
#include "lighting/game_rules.h"
#include "lighting/penumbra_suns.h"
#include "lighting/q3map2_light.h"
#include "lighting/q3map2_shader_light.h"
#include "quake/bspfile_q2.h"
#include "quake/entity_keys.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace bt {

namespace {

constexpr float kDefaultLightValue = 300.0f; // Quake's `light` default
constexpr float kDefaultSpotAngle = 40.0f;   // ericw-tools' cone when `angle` is absent
constexpr float kDefaultQuake2Cone = 10.0f;  // ericw-tools' `_cone` (a half-angle) on Quake 2 levels
constexpr int kMaxFormula = 5;

// `_deviance` / `_samples` (ericw-tools CheckEntityFields + JitterEntity, from q3map2): the
// compiler replaces the light by `_samples` copies (16 when only `_deviance` is given), each
// moved by a uniform offset in [-deviance, deviance] on every axis. The inverse, infinite and
// inverse-square formulas split the value among the copies, so they add up to the light;
// linear lights are not split, so a jittered linear light is `_samples` times as bright.
// Both tracers draw one copy per sample (deviance = the cube's half-size) and faithful mode
// multiplies by faithfulScale.
void applyJitter(const quake::EntityKeys& keys, GpuLight& light) {
  const float deviance = keys.number("_deviance", 0.0f);
  int samples = keys.integer("_samples", 0);
  if (deviance > 0.0f && samples == 0) samples = 16;
  if (deviance <= 0.0f || samples <= 1) return;
  light.deviance = deviance;
  if (light.formula == uint32_t(LightFormula::Linear)) light.faithfulScale = float(samples);
}

SurfaceTemplate readSurfaceTemplate(const quake::EntityKeys& keys, const std::string& texture, const GpuLight& light,
                                    const WorldLighting& world) {
  SurfaceTemplate t;
  t.texture = texture;
  t.light = light;
  t.hasColor = keys.has("_color");
  const float offset = keys.number("_surface_offset", 0.0f);
  t.offset = offset != 0.0f ? offset : 2.0f; // ericw-tools: 0 (unset) means 2 units
  t.spotlight = keys.number("_surface_spotlight", 0.0f) != 0.0f;
  t.radiosity = keys.has("_surface_radiosity") ? keys.number("_surface_radiosity", 0.0f) != 0.0f : world.surflightRadiosity;
  t.minlightScale = keys.number("_surflight_minlight_scale", world.surflightMinlightScale);
  t.group = int(keys.number("_surflight_group", 0.0f));
  if (t.spotlight && t.light.cosOuter < -1.0f) {
    // The axis is each face's normal; the cone is the template's `angle` / `_softangle`.
    const float angle = keys.number("angle", kDefaultSpotAngle);
    float soft = keys.number("_softangle", 0.0f);
    if (soft <= 0.0f || soft > angle) soft = angle;
    t.light.cosOuter = std::cos(glm::radians(angle) * 0.5f);
    t.light.cosInner = std::cos(glm::radians(soft) * 0.5f);
  }
  return t;
}

const Entity* findTarget(const Scene& scene, std::string_view targetname) {
  for (const Entity& e : scene.entities)
    if (e.value("targetname") == targetname) return &e;
  return nullptr;
}

WorldLighting readWorld(const Scene& scene, Diagnostics& diagnostics) {
  WorldLighting world = compilerDefaults(gameOf(scene));
  const Entity* ws = scene.worldspawn();
  if (!ws) return world;
  quake::EntityKeys keys(*ws, scene.sourcePath, &diagnostics);
  world.range = keys.number("_range", world.range);
  world.scaledist = keys.number("_dist", world.scaledist);
  world.anglescale = keys.number("_anglescale", keys.number("_anglesense", world.anglescale));
  const float minlight = keys.number("_minlight", keys.number("light", 0.0f));
  const glm::vec3 minColor = keys.colour("_minlight_color", keys.colour("_mincolor"));
  world.minlight = minlight * minlightUnit(gameOf(scene)) * minColor;
  world.bounces = std::clamp(keys.integer("_bounce", world.bounces), 0, 8);
  // ericw-tools' ranges: _bouncescale 0..100, _bouncecolorscale 0..1.
  world.bouncescale = std::clamp(keys.number("_bouncescale", world.bouncescale), 0.0f, 100.0f);
  world.bouncecolorscale = std::clamp(keys.number("_bouncecolorscale", world.bouncecolorscale), 0.0f, 1.0f);
  world.bouncestyled = keys.number("_bouncestyled", world.bouncestyled ? 1.0f : 0.0f) != 0.0f;
  world.litwater = keys.number("_litwater", 0.0f) != 0.0f;
  world.worldUnitsPerLuxel = std::max(keys.number("_world_units_per_luxel", 0.0f), 0.0f);
  world.surflightRadiosity = keys.number("_surflight_radiosity", world.surflightRadiosity ? 1.0f : 0.0f) != 0.0f;
  world.surflightScale = keys.number("_surflightscale", world.surflightScale);
  world.surflightSkyScale = keys.number("_surflightskyscale", world.surflightSkyScale);
  world.surflightMinlightScale = keys.number("_surflight_minlight_scale", world.surflightMinlightScale);

  world.dirt = keys.integer("_dirt", 0) == 1;
  DirtSettings& dirt = world.dirtSettings;
  dirt.mode = keys.integer("_dirtmode", 0) == 1 ? 1 : 0;
  dirt.depth = keys.number("_dirtdepth", dirt.depth);
  if (dirt.depth <= 0.0f) {
    keys.warn(fmt::format("_dirtdepth {} is not positive; using 128", dirt.depth));
    dirt.depth = 128.0f;
  }
  dirt.scale = keys.number("_dirtscale", dirt.scale);
  dirt.gain = keys.number("_dirtgain", dirt.gain);
  dirt.angle = std::clamp(keys.number("_dirtangle", dirt.angle), 0.0f, 90.0f);
  // ericw-tools (FixupGlobalSettings): `_dirt 1` also dims minlight and sunlight, unless the
  // level sets those keys itself.
  dirt.minlight = keys.number("_minlight_dirt", world.dirt ? 1.0f : 0.0f) != 0.0f;
  return world;
}

// Whether the worldspawn sun key `key` (`_sunlight_dirt`, `_sunlight2_dirt`) puts dirt on
// its suns: 1 on, anything else off; unset follows `_dirt`.
bool sunDirt(const quake::EntityKeys& keys, const WorldLighting& world, std::string_view key) {
  return keys.integer(key, world.dirt ? 1 : 0) == 1;
}

// The worldspawn's dirt scale and gain for a light that is dimmed by dirt (suns, domes).
void applyWorldDirt(const WorldLighting& world, bool useDirt, GpuLight& light) {
  if (!useDirt) return;
  light.flags |= kLightFlagDirt;
  light.dirtScale = world.dirtSettings.scale;
  light.dirtGain = world.dirtSettings.gain;
}

// A light entity's dirt (ericw-tools Dirt_GetScaleFactor): `_dirt` -1 never, 1 always, else as
// the worldspawn's `_dirt`; its own `_dirtscale` / `_dirtgain` where non-zero; and with both
// `_dirt_off_radius` and `_dirt_on_radius`, no dirt nearer than the first, full dirt beyond the
// second.
void applyLightDirt(const quake::EntityKeys& keys, const WorldLighting& world, GpuLight& light) {
  const int own = keys.integer("_dirt", 0);
  applyWorldDirt(world, own == 1 || (own != -1 && world.dirt), light);
  if (!(light.flags & kLightFlagDirt)) return;
  if (const float scale = keys.number("_dirtscale", 0.0f); scale != 0.0f) light.dirtScale = scale;
  if (const float gain = keys.number("_dirtgain", 0.0f); gain != 0.0f) light.dirtGain = gain;
  if (keys.has("_dirt_off_radius") && keys.has("_dirt_on_radius")) {
    light.flags |= kLightFlagDirtRadius;
    light.dirtOffRadius = keys.number("_dirt_off_radius", 0.0f);
    light.dirtOnRadius = keys.number("_dirt_on_radius", 0.0f);
  }
}

void addWorldSuns(const Scene& scene, const WorldLighting& world, SceneLights& out, Diagnostics& diagnostics) {
  const Entity* ws = scene.worldspawn();
  if (!ws) return;
  quake::EntityKeys keys(*ws, scene.sourcePath, &diagnostics);

  // ericw-tools reads Quake 2's arghrad spelling `_sun_light` as `_sunlight`, as it reads
  // `_sun_color` and `_sun_mangle` below.
  const float sunlight = keys.number("_sunlight", keys.number("_sun_light", 0.0f));
  if (sunlight != 0.0f) {
    GpuLight sun;
    sun.type = uint32_t(LightType::Sun);
    sun.value = sunlight;
    sun.color = keys.colour("_sunlight_color", keys.colour("_sun_color"));
    glm::vec3 mangle{0.0f, -90.0f, 0.0f}; // straight down, ericw-tools' default
    if (auto m = keys.vec3("_sun_mangle"))
      mangle = *m;
    else if (auto m2 = keys.vec3("_sunlight_mangle"))
      mangle = *m2;
    sun.direction = directionFromMangle(mangle.x, mangle.y);
    sun.anglescale = world.anglescale;
    sun.deviance = glm::radians(keys.number("_sunlight_penumbra", 0.0f));
    applyWorldDirt(world, sunDirt(keys, world, "_sunlight_dirt"), sun);
    out.lights.push_back(sun);
  }

  // Sky domes: light from every direction of the upper (_sunlight2) or lower (_sunlight3)
  // hemisphere that reaches a sky face.
  const struct {
    const char* value;
    const char* color;
    const char* colorAlt;
    float z;
  } domes[] = {
      {"_sunlight2", "_sunlight2_color", "_sunlight_color2", 1.0f},
      {"_sunlight3", "_sunlight3_color", "_sunlight_color3", -1.0f},
  };
  for (const auto& d : domes) {
    const float value = keys.number(d.value, 0.0f);
    if (value == 0.0f) continue;
    GpuLight dome;
    dome.type = uint32_t(LightType::Dome);
    dome.value = value;
    dome.color = keys.colour(d.color, keys.colour(d.colorAlt));
    dome.direction = {0.0f, 0.0f, d.z};
    dome.anglescale = world.anglescale;
    applyWorldDirt(world, sunDirt(keys, world, "_sunlight2_dirt"), dome);
    out.lights.push_back(dome);
  }
}

// `light` and Half-Life's `_light` take "value", "r g b" (value 300) or "r g b value", the
// colour 0..255 or 0..1 as `_color` (ericw-tools reads both forms, q1_light_hlform).
void readLightValue(const quake::EntityKeys& keys, GpuLight& light) {
  for (const char* key : {"light", "_light"}) {
    const std::string* text = keys.find(key);
    if (!text) continue;
    std::vector<float> n;
    for (double v : quake::parseNumbers(*text).value_or(std::vector<double>{})) n.push_back(float(v));
    if (!std::all_of(n.begin(), n.end(), [](float v) { return std::isfinite(v); })) n.clear();
    if (n.size() == 3 || n.size() == 4) {
      light.color = quake::normalisedColour(glm::vec3(n[0], n[1], n[2]));
      if (n.size() == 4) light.value = n[3];
    } else if (n.size() == 1) {
      light.value = n[0];
    } else {
      keys.warn(
          fmt::format("key \"{}\" has value \"{}\", expected a value, \"r g b\" or \"r g b value\"; using {}", key, *text, light.value));
    }
  }
}

// The falloff keys, jitter, dirt and bleed of a light entity. False for a `delay` that
// ericw-tools does not know: it warns and then lights nothing with that light (its
// q1_light_invalid_delay test map compiles to an empty lightmap lump), so do we.
bool readLightShape(const quake::EntityKeys& keys, const WorldLighting& world, GpuLight& light) {
  const float delay = keys.number("delay", 0.0f);
  if (delay < 0.0f || delay > kMaxFormula || delay != std::floor(delay)) {
    keys.warn(fmt::format("invalid delay {}: the compiler lights nothing with this light; ignored", delay));
    return false;
  }
  light.formula = static_cast<uint32_t>(delay);
  light.atten = keys.number("wait", 1.0f);
  if (light.atten <= 0.0f) light.atten = 1.0f; // ericw-tools: a non-positive wait means 1
  light.falloff = keys.number("_falloff", 0.0f);
  light.anglescale = keys.number("_anglescale", keys.number("_anglesense", world.anglescale));
  applyJitter(keys, light);
  applyLightDirt(keys, world, light);
  if (keys.number("_bleed", 0.0f) != 0.0f) light.flags |= kLightFlagBleed;
  return true;
}

// Spotlights: a target entity or a mangle gives the axis.
std::optional<glm::vec3> readSpotAxis(const Scene& scene, const Entity& entity, const quake::EntityKeys& keys, glm::vec3 origin) {
  if (const std::string* target = entity.find("target"); target && !target->empty()) {
    const Entity* t = findTarget(scene, *target);
    std::optional<glm::vec3> targetOrigin = t ? quake::parseVec3(t->value("origin")) : std::nullopt;
    if (targetOrigin && glm::length(*targetOrigin - origin) > 0.0f) return glm::normalize(*targetOrigin - origin);
    if (!t) keys.warn(fmt::format("target \"{}\" not found; light is not a spotlight", *target));
  }
  if (auto mangle = keys.vec3("mangle")) return directionFromMangle(mangle->x, mangle->y);
  return std::nullopt;
}

// A light with `_sun 1` is a sun shining along its spot axis.
GpuLight sunFromLight(const Scene& scene, const quake::EntityKeys& keys, GpuLight light, std::optional<glm::vec3> axis) {
  light.type = uint32_t(LightType::Sun);
  light.direction = axis.value_or(glm::vec3(0.0f, 0.0f, -1.0f));
  // ericw-tools spreads a light-entity sun over its `_deviance` (degrees), not `_samples` copies.
  light.deviance = glm::radians(keys.number("_deviance", keys.number("_sunlight_penumbra", 0.0f)));
  light.faithfulScale = 1.0f;
  if (const std::string* sky = keys.find("_suntexture"); sky && !sky->empty()) {
    if (auto m = scene.findMaterial(*sky)) {
      light.skyMaterial = *m + 1;
    } else {
      keys.warn(fmt::format("_suntexture \"{}\": no face has this texture; the sun lights nothing", *sky));
      light.value = 0.0f;
    }
  }
  return light;
}

// A spotlight's full width in degrees, as ericw-tools' SetupSpotlights reads it: arghrad's
// Quake 2 key `_cone` is the cone's half-angle and wins over Quake's `angle` (the full width);
// with neither (or 0) the width is 2 x 10 degrees on a Quake 2 level, 40 elsewhere.
float spotConeDegrees(const quake::EntityKeys& keys, Game game) {
  float angle = 0.0f;
  if (keys.has("_cone") || keys.has("cone"))
    angle = 2.0f * keys.number("_cone", keys.number("cone", 0.0f));
  else
    angle = keys.number("angle", 0.0f);
  if (angle != 0.0f) return angle;
  return game == Game::Quake2 ? 2.0f * kDefaultQuake2Cone : kDefaultSpotAngle;
}

// A spotlight's cone: spotConeDegrees its full width, `_softangle` the unfaded part.
void applySpotCone(const quake::EntityKeys& keys, Game game, glm::vec3 axis, GpuLight& light) {
  const float angle = spotConeDegrees(keys, game);
  float soft = keys.number("_softangle", 0.0f);
  if (soft <= 0.0f || soft > angle) soft = angle;
  light.direction = axis;
  light.cosOuter = std::cos(glm::radians(angle) * 0.5f);
  light.cosInner = std::cos(glm::radians(soft) * 0.5f);
}

// A sun with a penumbra takes the compiler's kSunSamples directions for it, the next ones `rand`
// gives.
void attachSunTable(GlibcRand& rand, GpuLight& sun, std::vector<glm::vec3>& table) {
  if (sun.type != uint32_t(LightType::Sun) || sun.deviance <= 0.0f) return;
  sun.flags |= kLightFlagSunTable;
  sun.sunTable = uint32_t(table.size());
  const double degrees = double(sun.deviance) * (180.0 / 3.14159265358979323846);
  for (const glm::vec3& d : penumbraDirections(rand, sun.direction, degrees, faithful::kSunSamples)) table.push_back(d);
}

void addLightEntity(const Scene& scene, const Entity& entity, const LightOptions& options, SceneLights& out, Diagnostics& diagnostics,
                    GlibcRand& rand) {
  quake::EntityKeys keys(entity, scene.sourcePath, &diagnostics);
  GpuLight light;
  light.type = uint32_t(LightType::Point);
  light.value = kDefaultLightValue;
  light.color = keys.colour("_color");
  readLightValue(keys, light);
  if (!readLightShape(keys, out.world, light)) return;
  if (auto origin = keys.vec3("origin")) {
    light.origin = *origin;
  } else {
    keys.warn("light without a valid origin; ignored");
    return;
  }
  const std::optional<glm::vec3> spotAxis = readSpotAxis(scene, entity, keys, light.origin);
  if (keys.number("_sun", 0.0f) != 0.0f) {
    out.lights.push_back(sunFromLight(scene, keys, light, spotAxis));
    if (light.value >= 1.0f) attachSunTable(rand, out.lights.back(), out.sunTable); // SetupSuns: int(light) > 0
    return;
  }
  if (spotAxis) applySpotCone(keys, gameOf(scene), *spotAxis, light);

  const int style = std::clamp(keys.integer("style", 0), 0, 255);
  const bool switchable = !entity.value("targetname").empty();
  const bool startOff = switchable && (keys.integer("spawnflags", 0) & 1);
  if (startOff) light.flags |= kLightFlagStartOff;
  // Switchable lights get their own style in the compiled map; give them a non-zero one here.
  const uint32_t effectiveStyle = style > 0 ? uint32_t(style) : (switchable ? 32u : 0u);
  light.flags |= effectiveStyle << 8;

  if (startOff && !options.includeStartOff) return;
  if (options.styleZeroOnly && effectiveStyle != 0) return;
  light.color *= options.styleScale[effectiveStyle];
  if (const std::string* surface = keys.find("_surface"); surface && !surface->empty()) {
    out.surfaceTemplates.push_back(readSurfaceTemplate(keys, *surface, light, out.world));
    return;
  }
  // Suns and surface lights stay on the default channel, as in the compiler (entities.cc).
  light.lightChannels = uint32_t(keys.integer("_light_channel_mask", int(kDefaultChannels)));
  light.shadowChannels = uint32_t(keys.integer("_shadow_channel_mask", int(light.lightChannels)));
  out.lights.push_back(light);
}

// Quake 2's surface lights (ericw-tools surflight.cc MakeSurfaceLightsThread): every face whose
// texinfo has SURF_LIGHT and a non-zero value is a radiosity surface light of that value, in the
// texture's mean colour; one template per texture and value.
void addQuake2SurfaceLights(const Scene& scene, SceneLights& out, Diagnostics& diagnostics) {
  bool skyWarned = false;
  for (const Face& f : scene.faces) {
    if (f.brush == kNoBrush || !f.surface || !(f.surface->flags & quake::q2::SURF_LIGHT) || f.surface->value == 0.0) continue;
    if (f.surface->flags & quake::q2::SURF_SKY) {
      // The compiler's sky emitters shine in every direction, scaled by `_surflightskyscale`.
      if (!skyWarned)
        diagnostics.push_back(
            {Severity::Warning, scene.sourcePath, f.line, 0,
             fmt::format("sky face \"{}\" with SURF_LIGHT: Quake 2 sky surface lights are not modelled; it emits nothing", f.texture)});
      skyWarned = true;
      continue;
    }
    const auto same = [&](const SurfaceTemplate& t) { return t.q2Value == f.surface->value && t.texture == f.texture; };
    if (std::any_of(out.surfaceTemplates.begin(), out.surfaceTemplates.end(), same)) continue;
    SurfaceTemplate t;
    t.texture = f.texture;
    t.q2Value = f.surface->value;
    t.radiosity = true;
    t.minlightScale = out.world.surflightMinlightScale;
    t.light.type = uint32_t(LightType::Point);
    t.light.value = float(f.surface->value);
    t.light.color = glm::vec3(1.0f);
    out.surfaceTemplates.push_back(t);
  }
}

} // namespace

glm::vec3 directionFromMangle(float yawDegrees, float pitchDegrees) {
  const float yaw = glm::radians(yawDegrees);
  const float pitch = glm::radians(pitchDegrees);
  return {std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch)};
}

LightKinds lightKinds(const Scene& scene, const SceneLights& lights, bool bounceLights) {
  LightKinds kinds;
  for (const GpuLight& l : lights.lights) {
    kinds.sky |= l.type == uint32_t(LightType::Sun) || l.type == uint32_t(LightType::Dome);
    kinds.jitter |= l.type == uint32_t(LightType::Point) && l.deviance > 0.0f;
    kinds.negative |= faithful::subtractedLight(l);
  }
  for (const SurfaceTemplate& t : lights.surfaceTemplates) {
    kinds.jitter |= t.light.deviance > 0.0f;
    kinds.negative |= faithful::subtractedLight(t.light);
  }
  kinds.dirt = lights.world.dirtSettings.enabled;
  kinds.bounce = bounceLights && lights.world.bounces > 0;
  kinds.filter = gameOf(scene) == Game::Quake3;
  return kinds;
}

// Keys ericw-tools reads that faithful mode does not model (issue 14: named, never silently
// ignored): one warning a key for the level, at the first entity that asks for it, with how many
// do. A key asks for it when its value is a non-zero number or, for a key that names something,
// any text ("0" and "" are the compiler's defaults). In `what`, {0} is the count, {1} and {2}
// the plural endings of "entit-" and "light".
struct UnmodelledKey {
  std::array<std::string_view, 2> names; // the key and its alias, if any ("" none)
  bool namesEntity;                      // its value names entities (any text asks for it)
  std::string_view what;
};
// Phong: the oracle compile of LibreQuake's lqdm5, whose 24 func_detail entities ask for it, lit
// them flat too: a first model of it moved those faces' luxels from 93 % to 79 % within 5 % of
// the compiler's. The rest: keys of the lit oracle levels' sources (q1_lightignore, q1_litwater,
// q1_light_switchableshadow_*) and their neighbours in the compiler's shadow keys.
constexpr std::array kUnmodelledKeys{
    UnmodelledKey{
        {"_phong", "_phong_angle"}, false, "phong shading is not modelled; the faces of the {0} brush entit{1} asking for it are lit flat"},
    UnmodelledKey{{"_lightignore", ""},
                  false,
                  "ignoring the lights is not modelled ({0} brush entit{1}); their faces take every light, where the compiler "
                  "gives them minlight only"},
    UnmodelledKey{{"_switchableshadow", ""},
                  false,
                  "switchable shadows are not modelled ({0} brush entit{1}); without `_shadow 1` they cast none, where the "
                  "compiler's style 0 has their shadow and a style of their own the light they block"},
    UnmodelledKey{{"_switchableshadow_target", ""},
                  true,
                  "the shadow a light's style switches is not modelled ({0} light{2}); they light as any other, where the "
                  "compiler's give no light of their own (`_nostaticlight`)"},
    UnmodelledKey{{"_nostaticlight", ""},
                  false,
                  "lights without static light are not modelled ({0} light{2}); they light the level, where the compiler's do not"},
    UnmodelledKey{{"_shadowself", "_selfshadow"},
                  false,
                  "self-shadowing brush entities are not modelled ({0} brush entit{1}); they cast no shadow on themselves"},
    UnmodelledKey{{"_shadowworldonly", ""}, false, "shadows on the world alone are not modelled ({0} brush entit{1}); they cast none"},
};

void warnUnmodelledKeys(const Scene& scene, Diagnostics& diagnostics) {
  for (const UnmodelledKey& key : kUnmodelledKeys) {
    const Entity* first = nullptr;
    std::string_view firstName;
    size_t count = 0;
    for (const Entity& entity : scene.entities) {
      const quake::EntityKeys keys(entity);
      std::string_view asked;
      for (std::string_view name : key.names) {
        if (name.empty() || !asked.empty()) continue;
        const std::string* value = keys.find(name);
        if (value && (key.namesEntity ? !value->empty() : keys.number(name, 0.0f) != 0.0f)) asked = name;
      }
      if (asked.empty()) continue;
      if (!first) first = &entity, firstName = asked;
      ++count;
    }
    if (!first) continue;
    const std::string what = fmt::format(fmt::runtime(key.what), count, count == 1 ? "y" : "ies", count == 1 ? "" : "s");
    quake::EntityKeys(*first, scene.sourcePath, &diagnostics).warn(fmt::format("{}: {}", firstName, what));
  }
}

SceneLights collectLights(const Scene& scene, const LightOptions& options, Diagnostics& diagnostics) {
  SceneLights out;
  if (gameOf(scene) == Game::Quake3) {
    // q3map2's keys and rules, not ericw-tools' (lighting/q3map2_light.h).
    out.world = compilerDefaults(Game::Quake3);
    q3map2::readWorld(scene, out.world, diagnostics);
    q3map2::addLightEntities(scene, options, out, diagnostics);
    q3map2::addShaderSuns(scene, out);
    return out;
  }
  out.world = readWorld(scene, diagnostics);
  addWorldSuns(scene, out.world, out, diagnostics);
  const size_t worldLights = out.lights.size();
  // The compiler's rand() stream: its light jitter first, then the entity suns, then the world's.
  GlibcRand rand;
  for (uint64_t n = randDrawsBeforeSuns(scene); n > 0; --n) rand.next();
  for (const Entity& entity : scene.entities)
    if (entity.classname().starts_with("light")) addLightEntity(scene, entity, options, out, diagnostics, rand);
  for (uint64_t n = randDrawsOfSunCopies(scene); n > 0; --n) rand.next();
  for (size_t i = 0; i < worldLights; ++i) attachSunTable(rand, out.lights[i], out.sunTable);
  if (gameOf(scene) == Game::Quake2) addQuake2SurfaceLights(scene, out, diagnostics);
  warnUnmodelledKeys(scene, diagnostics);

  // ericw-tools traces the occlusion rays only where something uses dirt (SetupDirt).
  DirtSettings& dirt = out.world.dirtSettings;
  dirt.enabled = out.world.dirt || dirt.minlight;
  for (const GpuLight& light : out.lights) dirt.enabled = dirt.enabled || (light.flags & kLightFlagDirt);
  for (const SurfaceTemplate& t : out.surfaceTemplates) dirt.enabled = dirt.enabled || (t.light.flags & kLightFlagDirt);
  return out;
}

} // namespace bt
