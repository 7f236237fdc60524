// Issue 18: physical mode matches each Quake point light to the compiled light over the surfaces
// its light lands on (lighting/README.md, "Physical mode"), not at one fixed distance for every
// light: a linear light of 500 matched at 128 units gives a third of the compiler's light on walls
// 250 units away, and a light hung near a wall is matched where little of its light lands. At
// preparation, CPU side, so both tracers read the same GpuLight::physicalIntensity.
#pragma once

#include "scene/gpu_structs.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace bt {
struct RenderScene;
struct WorldLighting;
} // namespace bt

namespace bt::physical {

// Rays cast from each light to find where its light lands: the directions of a Fibonacci sphere
// of this many that lie in a sixteenth of the sphere, copied by its mirrorings and x <-> y swaps
// (256 rays; the same for every light, no randomness), those outside a spotlight's cone left out.
inline constexpr int kLandingRays = 256;
// The nearest a landing counts as (the inverse formulas' hot spots; a light nudged off a face is
// a unit or two from it).
inline constexpr float kLandingMinDistance = 16.0f;
// The least cosine of incidence a landing counts with: a ray that grazes a face stands for a
// patch of area d^2 / cos, unbounded towards the grazing angle.
inline constexpr float kLandingMinCosine = 0.2f;

// Where one ray from a light lands: its distance, the cosine of its incidence on that face, the
// point and the side the face looks to (its normal's axis towards the light: +x, -x, +y, ...; 0-5).
struct Landing {
  float distance;
  float cosine;
  glm::vec3 position;
  uint32_t side;
  float texture; // the face's texture as the display shows it: its mean's brightest channel, sRGB
};

// Whether a light's intensity is matched where its light lands (Quake's point formulas: linear,
// inverse, inverse square) that physical mode draws; the rest keep matchDistance()'s rule
// (q3map2's lights; _surface points and bounce lights, which physical mode does not draw).
bool matchedWhereItLands(const GpuLight& light);

// Where each of the rays from the light meets its first surface within the light's
// reach; sky and the void do not count, liquids and faces that cast no shadow are passed through
// (the compiler lights what lies beyond them).
std::vector<Landing> landings(const RenderScene& rs, const GpuLight& light);

// The intensity (light units x distance^2, as physical::intensity) whose light, summed over the
// area of the surfaces the light lands on, equals the compiler's there; nullopt where no ray
// lands. Per ray, a patch at distance d and incidence cos stands for d^2 / cos of area per unit
// solid angle, so the compiler's light over it is c(d) x angleTerm(cos) x d^2 / cos and physical
// light's I x W(d) (the cos of the receiver cancels the patch's): I = sum of the first / sum of W.
std::optional<float> landedIntensity(const GpuLight& light, std::span<const Landing> landed, float scaledist);

// The lightmap fraction S one light gives a landing in faithful mode: the compiler's light there
// (its copies summed, the brightest channel) x `_range` / the value the engine shows as the
// texture's own colour (WorldLighting's), before the lightmap's clamp at 255.
float landedFraction(const GpuLight& light, const Landing& l, const WorldLighting& world);

// The edge of LandedLightmap's cubes: about the spacing of a light's rays 500 units away, so a
// cube a light lights is met by some of its rays.
inline constexpr float kLightmapCell = 32.0f;

// The compiled lightmap where the lights land, estimated from their landings alone (no ray more):
// per cube of kLightmapCell units and side a face looks to, each light's mean fraction over its
// landings there, summed over the lights. Shadows are in it (a ray stops at its first face); a
// light whose rays miss a cube it lights is left out there, which the cube's edge keeps to the
// distant, dim ones. Minlight, suns and bounce are not in it.
class LandedLightmap {
public:
  void add(const GpuLight& light, std::span<const Landing> landed, const WorldLighting& world);
  float at(const Landing& l) const;

private:
  std::unordered_map<uint64_t, float> cells_;
};

// The display match of one light (lighting/README.md, "Physical mode", the display match), in
// place of the one global k (BT_PHYSICAL_DISPLAY_MATCH) for the lights matched where they land:
// the k that makes the light's physical output over the surfaces it lands on equal what the
// game's display shows of it there. At a landing (patch A = d^2 / cos, as in landedIntensity) on
// a texture the display shows at t (sRGB), where the lightmap is T (`lightmap`, with this light's
// own S at the landing) of which this light gives S, the display shows srgbToLinear(t T), of
// which this light's share is S / T, and physical light k S srgbToLinear(t):
// k = sum A S / T srgbToLinear(t T) / sum A S srgbToLinear(t). Landings where the display is
// clipped (T at 255, or t T at white) are left out; nullopt where none is left, and for
// GoldSrc's display (its light gamma table is another curve): the global k stays.
std::optional<float> landedDisplayMatch(const GpuLight& light, std::span<const Landing> landed, const WorldLighting& world,
                                        const LandedLightmap& lightmap);

// physical::prepare for each light, those matchedWhereItLands() at their landings, their
// intensity scaled by landedDisplayMatch() over the global k that the tracers multiply by, on
// all cores.
void prepareWhereTheyLand(const RenderScene& rs, std::span<GpuLight> lights);

} // namespace bt::physical
