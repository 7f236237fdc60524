// Quake 3's light compiler, q3map2, in faithful mode: its light entities and worldspawn keys as
// GpuLights and WorldLighting (light.c CreateEntityLights, light_ydnar.c
// LightContributionToSample), evaluated by faithful.h's Q3Point / Q3Linear formulas on both
// tracers. lighting/README.md ("Quake 3 in faithful mode") lists every key with its source.
#pragma once

#include "lighting/lights.h"
#include "scene/scene.h"

namespace bt::q3map2 {

// q3map2's scales (light.c globals): a point light's `light` becomes pointScale × light photons,
// a spotlight's spotScale ×; a linear light loses 1 photon × linearScale per unit; a light ends
// where it would add less than falloffTolerance (its envelope, SetupEnvelopes).
inline constexpr float kPointScale = 7500.0f;
inline constexpr float kSpotScale = 7500.0f;
inline constexpr float kLinearScale = 1.0f / 8000.0f;
inline constexpr float kFalloffTolerance = 1.0f;
inline constexpr float kDefaultLight = 300.0f;
inline constexpr float kDefaultSpotRadius = 64.0f;

// The display of ioquake3 at its defaults: q3map2 stores the light sum (gamma 1, compensate 1,
// its colour scaled so the brightest channel fits 255); R_ColorShiftLightingBytes shifts it by
// r_mapOverBrightBits 2 − r_overBrightBits 1 = 1 bit, scaling it again to fit 255, and the gamma
// ramp doubles the picture (r_overBrightBits 1). So a luxel holds 2 × the sum and shows as
// texture × luxel / 127.5: WorldLighting's range and overbrightOne for Quake 3.
inline constexpr float kLuxelScale = 2.0f;
inline constexpr float kOverbrightOne = 127.5f;

// Worldspawn keys q3map2 reads (`_minlight` × `_color`); `world` holds the game's defaults.
void readWorld(const Scene& scene, WorldLighting& world, Diagnostics& diagnostics);

// Every `light*` entity, as q3map2 makes its lights; appended to out.lights.
void addLightEntities(const Scene& scene, const LightOptions& options, SceneLights& out, Diagnostics& diagnostics);

} // namespace bt::q3map2
