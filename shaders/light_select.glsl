// Light selection: lighting/light_grid.h's lists and integrator.cpp's selected paths in
// GLSL, reading the same bytes (scene/gpu_structs.h GpuLightGrid, GpuLightCell, and the index
// array) and drawing the same random numbers in the same order, so that a pixel's sample n
// picks the same light on both tracers.
// Needs scene_buffers.glsl, sampling.glsl and faithful.glsl (spotTerm); no ray queries, so it
// does not care how the caller traces its shadow rays.

// scene/gpu_structs.h GpuLightGrid, byte for byte.
#include "gl_bindings.glsl"
#include "light_constants.glsl"
struct GpuLightGrid {
  vec3 origin;        // offset 0: min corner of cell (0, 0, 0)
  float cellSize;     // offset 12
  uvec3 dims;         // offset 16
  uint fixedCount;    // offset 28: suns, domes, local minlights at lightIndices[0, fixedCount)
  uint globalFirst;   // offset 32: faithful point lights of infinite reach
  uint globalCount;   // offset 36
  uint physicalFirst; // offset 40: physical mode's candidates
  uint physicalCount; // offset 44
};                    // 48 bytes

struct GpuLightCell {
  uint first; // into lightIndices
  uint count;
};

layout(std430, binding = BT_BINDING_LIGHT_GRID) readonly buffer LightGridBuffer {
  GpuLightGrid lightGrid;
  GpuLightCell lightCells[];
};
layout(std430, binding = BT_BINDING_LIGHT_INDICES) readonly buffer LightIndices { uint lightIndices[]; }; // into lights[]

// lighting lightGridCell: the cell holding p, clamped to the grid (NaN to cell 0).
uint lightGridAxis(float coordinate, float origin, uint dim) {
  float f = (coordinate - origin) / lightGrid.cellSize;
  if (!(f >= 0.0)) return 0u;
  if (f >= float(dim)) return dim - 1u;
  return min(uint(f), dim - 1u);
}

uint lightGridCell(vec3 p) {
  uvec3 d = lightGrid.dims;
  return lightGridAxis(p.x, lightGrid.origin.x, d.x) +
         d.x * (lightGridAxis(p.y, lightGrid.origin.y, d.y) + d.y * lightGridAxis(p.z, lightGrid.origin.z, d.z));
}

// Faithful mode's lights at a point of `cell`, in the CPU's order (LightSet::Grid): the
// fixed lights, the infinite-reach lights, then the cell's own list.
uint faithfulLightCount(uint cell) { return lightGrid.fixedCount + lightGrid.globalCount + lightCells[cell].count; }

uint faithfulLight(uint cell, uint k) {
  if (k < lightGrid.fixedCount) return lightIndices[k];
  k -= lightGrid.fixedCount;
  if (k < lightGrid.globalCount) return lightIndices[lightGrid.globalFirst + k];
  return lightIndices[lightCells[cell].first + k - lightGrid.globalCount];
}

// lighting/physical_light.h falloff: the prepared light's windowed inverse-square falloff,
// intensity x window / dist^2 (GpuLight::physicalIntensity, physicalInvReach, set on the CPU).
float physicalFalloff(GpuLight light, float dist2) {
  float x2 = dist2 * light.physicalInvReach * light.physicalInvReach;
  float w = clamp(1.0 - x2 * x2, 0.0, 1.0);
  return light.physicalIntensity * (w * w) / dist2;
}

// integrator.cpp selectionWeight: unshadowed irradiance on the surface plane, the emitted
// colour's channels summed (lighting/physical_light.h selectionColour: no pow per light).
float selectionWeight(GpuLight light, vec3 origin, vec3 n) {
  vec3 d = light.origin - origin;
  float dist2 = dot(d, d);
  if (!(dist2 > 0.0)) return 0.0;
  vec3 wi = d / sqrt(dist2);
  float cosSurface = dot(n, wi);
  if (cosSurface <= 0.0) return 0.0;
  float colourSum = max(light.color.x, max(light.color.y, light.color.z)) * light.physicalHueSum;
  return colourSum * physicalFalloff(light, dist2) * spotTerm(light, wi) * cosSurface;
}

const float NEAR_LIST_PROBABILITY = BT_NEAR_LIST_PROBABILITY;

// Physical mode (integrator.cpp allLightsSelected, pickFromNearList): one point light, from the
// cell's near list by weight with probability NEAR_LIST_PROBABILITY, else uniformly from the
// cell's other lights in reach (the two lists are disjoint).
// The caller then draws the light's _deviance jitter (jitteredOrigin), as the CPU does.
struct SelectedLight {
  bool found;
  uint light;     // index into lights[]
  float pdf;      // probability of having picked it
};

SelectedLight selectPhysicalLight(vec3 origin, vec3 n, inout Rng rng) {
  SelectedLight s = SelectedLight(false, 0u, 0.0);
  uvec3 d = lightGrid.dims;
  uint cellCount = d.x * d.y * d.z, cell = lightGridCell(origin);
  GpuLightCell near = lightCells[cellCount + cell];
  GpuLightCell rest = lightCells[2u * cellCount + cell];
  float nearTotal = 0.0;
  for (uint k = 0u; k < near.count; ++k) {
    GpuLight light = lights[lightIndices[near.first + k]];
    nearTotal += selectionWeight(light, origin, n);
  }
  float uStrategy = rngNext(rng);
  float uPick = rngNext(rng);
  float nearProbability = nearTotal > 0.0 ? (rest.count == 0u ? 1.0 : NEAR_LIST_PROBABILITY) : 0.0;
  if (nearProbability == 0.0 && rest.count == 0u) return s;

  uint chosen = 0u;
  float chosenWeight = 0.0; // its near-list weight, 0 when not listed
  if (uStrategy < nearProbability) {
    float target = uPick * nearTotal;
    float cumulative = 0.0;
    for (uint k = 0u; k < near.count; ++k) {
      uint index = lightIndices[near.first + k];
      GpuLight light = lights[index];
      float w = selectionWeight(light, origin, n);
      if (w <= 0.0) continue;
      chosen = index;
      chosenWeight = w;
      cumulative += w;
      if (cumulative > target) break;
    }
  } else {
    chosen = lightIndices[rest.first + min(uint(uPick * float(rest.count)), rest.count - 1u)];
  }
  s.pdf = uStrategy < nearProbability ? nearProbability * chosenWeight / nearTotal : (1.0 - nearProbability) / float(rest.count);
  s.light = chosen;
  s.found = s.pdf > 0.0;
  return s;
}

// Physical mode's emitter triangle for a uniform u: the first whose cumulative area share
// (GpuEmitter::cdf) reaches u, by bisection.
uint pickEmitter(float u) {
  uint lo = 0u, hi = world.emitterCount - 1u;
  while (lo < hi) {
    uint mid = (lo + hi) / 2u;
    if (emitters[mid].cdf < u) lo = mid + 1u;
    else hi = mid;
  }
  return lo;
}
