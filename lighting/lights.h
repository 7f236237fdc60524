// Light entities and worldspawn lighting keys -> the flat light list both tracers read.
// Key names and defaults are ericw-tools `light`'s (see lighting/README.md for the table).
#pragma once

#include "quake/entity_keys.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace bt {

// Worldspawn dirt keys (ericw-tools' dirtmapping, q3map2's fake ambient occlusion): how a
// surface point's occlusion is measured. Which lights it dims is on each GpuLight
// (kLightFlagDirt); minlight is dimmed when `minlight` is set.
struct DirtSettings {
  bool enabled = false;  // anything uses dirt: the occlusion rays are traced at all
  int mode = 0;          // `_dirtmode`: 0 the fixed 48-ray cone, 1 random rays in it
  float depth = 128.0f;  // `_dirtdepth`: rays look this far; a hit at 0 is full occlusion
  float scale = 1.0f;    // `_dirtscale`
  float gain = 1.0f;     // `_dirtgain`: occlusion ^ gain
  float angle = 88.0f;   // `_dirtangle`: the cone's half-angle from the normal, degrees
  bool minlight = false; // `_minlight_dirt` (on by default when `_dirt` is 1)
};

// Worldspawn keys that set up the whole level's lighting.
struct WorldLighting {
  float range = 0.5f;                  // `_range`: lightmap = light sum * range
  float overbrightOne = 128.0f;        // the stored value the engine shows as the texture's own colour (Quake's overbright; 255 without)
  uint32_t luxelDisplay = 0;           // BT_LUXEL_DISPLAY_*: what the engine makes of a stored luxel first (lighting/luxel_display.h)
  float scaledist = 1.0f;              // `_dist`: scales distance in every falloff formula
  float anglescale = 0.5f;             // `_anglescale` (or `_anglesense`): default for every light and the sun
  glm::vec3 minlight{0.0f};            // `light` / `_minlight` * `_minlight_color`, in light units
  glm::vec3 ambient{0.0f};             // q3map2's worldspawn `_ambient` × `_color`: added to every sum (Quake 3 only)
  int bounces = 0;                     // `_bounce`: passes of ericw-tools bounce lights (lighting/bounce.h)
  float bouncescale = 1.0f;            // `_bouncescale`
  float bouncecolorscale = 0.0f;       // `_bouncecolorscale`: 0 bounces grey (127), 1 the texture's mean colour
  bool bouncestyled = false;           // `_bouncestyled`: styled lights bounce too
  bool litwater = false;               // `_litwater`: liquids receive light instead of drawing fullbright
  bool surflightRadiosity = false;     // `_surflight_radiosity`: default kind of every _surface template
  float surflightScale = 1.0f;         // `_surflightscale`: scales radiosity surface lights
  float surflightSkyScale = 1.0f;      // `_surflightskyscale`: scales Quake 2 sky faces that emit (not modelled)
  float surflightMinlightScale = 1.0f; // `_surflight_minlight_scale`: default face minlight of radiosity templates
  // `_world_units_per_luxel` (ericw-tools' `world_units_per_luxel`, BSPX DECOUPLED_LM): a luxel
  // every so many world units on axes of the face's own, not Quake's 16 texels; 0: unset.
  float worldUnitsPerLuxel = 0.0f;
  bool dirt = false; // `_dirt 1`: every light is dimmed by dirt unless its own `_dirt` is -1
  DirtSettings dirtSettings;
};

// An area-light template: a light entity with `_surface "texture"` makes every face with that
// texture emit. Physical mode lights those faces as area emitters; faithful mode spreads point
// lights over them the way ericw-tools `light` does (lighting/surface_lights.h).
struct SurfaceTemplate {
  std::string texture;
  GpuLight light;             // value, colour, formula, anglescale, style of the template
  bool hasColor = false;      // `_color` given (a radiosity template otherwise takes the texture's colour)
  float offset = 2.0f;        // `_surface_offset`: how far off the face the point lights sit (0 means 2)
  bool spotlight = false;     // `_surface_spotlight`: each point light is a spotlight along the face normal
  bool radiosity = false;     // `_surface_radiosity` 1: ericw-tools' "Q2-style" radiosity surface light
  float minlightScale = 1.0f; // `_surflight_minlight_scale`: radiosity kind: face minlight = value x this
  int group = 0;              // `_surflight_group`: only faces of entities with the same `_surflight_group` (0: unset) emit
  // Quake 2's texinfo surface lights (SURF_LIGHT with a value): only faces whose texinfo has the
  // flag and this value emit, not every face with the texture.
  std::optional<double> q2Value;
};

struct SceneLights {
  std::vector<GpuLight> lights; // point and spot lights, suns, domes
  // The directions of the compiler's suns for every sun with a penumbra (GpuLight::sunTable),
  // drawn in the compiler's order: the `_sun 1` lights in entity order, then the worldspawn sun
  // (lighting/penumbra_suns.h).
  std::vector<glm::vec3> sunTable;
  std::vector<SurfaceTemplate> surfaceTemplates;
  WorldLighting world;
};

struct LightOptions {
  // Lights that start off (spawnflags & 1 with a targetname) stay dark unless this is set.
  bool includeStartOff = false;
  // Only lights on lightstyle 0 (what the compiler bakes into the first lightmap), for tests
  // that compare with compiled lightmaps.
  bool styleZeroOnly = false;
  // The viewer's light-style sliders: each light's colour (its contribution, not its reach) times
  // its style's scale, as the engine weighs a style's lightmap by the lightstyle's value.
  std::array<float, 256> styleScale = [] {
    std::array<float, 256> all;
    all.fill(1.0f);
    return all;
  }();
};

// Reads every `light*` entity and the worldspawn keys. Unknown or malformed values are reported
// in `diagnostics` (file and line of the entity) and replaced by the default.
SceneLights collectLights(const Scene& scene, const LightOptions& options, Diagnostics& diagnostics);

// The kinds of light a level has, as collectLights() finds them: before the `_surface` and
// `_bounce` lights are made, which take most of a level's preparation and add point lights only.
// The GL tracer compiles only the code for the kinds a level has, and starts that compile from
// these as soon as the lights are collected (renderer/gl FaithfulFeatures); with them goes the one
// surface kind that program needs to know, known as early from the level's game.
struct LightKinds {
  bool sky = false;      // suns or sky domes
  bool jitter = false;   // point lights with `_deviance`, or `_surface` templates with it (their lights inherit it)
  bool dirt = false;     // dirt's occlusion rays (DirtSettings::enabled)
  bool bounce = false;   // `_bounce` lights will be made (worldspawn `_bounce`, and the render wants them)
  bool negative = false; // negative lights taken off after the floors (faithful::subtractedLight), or templates of them
  // A Quake 3 level: its shaders (read after the entities) may have blendFunc filter surfaces,
  // which tint what lies behind them per channel.
  bool filter = false;
  bool operator==(const LightKinds&) const = default;
};
LightKinds lightKinds(const Scene& scene, const SceneLights& lights, bool bounceLights);

// "yaw pitch roll" in degrees as ericw-tools' mangle: the direction (+pitch looks up).
glm::vec3 directionFromMangle(float yawDegrees, float pitchDegrees);

// Light style of a packed GpuLight::flags value.
inline uint32_t lightStyle(const GpuLight& light) {
  return light.flags >> 8;
}

} // namespace bt
