// Issue 18: physical mode matches each Quake point light to the compiled light over the surfaces
// its light lands on (lighting/README.md, "Physical mode"), not at one fixed distance for every
// light: a linear light of 500 matched at 128 units gives a third of the compiler's light on walls
// 250 units away, and a light hung near a wall is matched where little of its light lands. At
// preparation, CPU side, so both tracers read the same GpuLight::physicalIntensity.
#pragma once

#include "scene/gpu_structs.h"

#include <glm/vec3.hpp>

#include <optional>
#include <span>
#include <vector>

namespace bt {
struct RenderScene;
}

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

// Where one ray from a light lands: its distance and the cosine of its incidence on that face.
struct Landing {
  float distance;
  float cosine;
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

// physical::prepare for each light, those matchedWhereItLands() at their landings, on all cores.
void prepareWhereTheyLand(const RenderScene& rs, std::span<GpuLight> lights);

} // namespace bt::physical
