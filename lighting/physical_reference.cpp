#include "lighting/physical_reference.h"

#include "bvh/trace_scene.h"
#include "lighting/faithful.h"
#include "lighting/physical_light.h"
#include "lighting/render_scene.h"
#include "scene/color.h"
#include "scene/parallel_for.h"
#include "shaders/luxel_display_constants.glsl"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

namespace bt::physical {
namespace {

// Direction i of n spread evenly over the sphere (the golden-angle spiral).
glm::vec3 fibonacciDirection(int i, int n) {
  constexpr float kGoldenAngle = 2.39996322972865332f; // pi (3 - sqrt 5)
  const float z = 1.0f - (2.0f * float(i) + 1.0f) / float(n);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = kGoldenAngle * float(i);
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// The rays' directions: the spiral's kLandingRays directions that fall in the wedge 0 <= y < x,
// z > 0 (a sixteenth of the sphere), each copied by the sixteen mirrorings and x <-> y swaps,
// so that a level mirrored along an axis or turned by 90 degrees about z matches its lights
// alike (the spiral itself has no such symmetry: a light's intensity moved by 3 % between the
// mirrored halves of a symmetric room).
const std::vector<glm::vec3>& landingDirections() {
  static const std::vector<glm::vec3> directions = [] {
    std::vector<glm::vec3> out;
    for (int i = 0; i < kLandingRays; ++i) {
      const glm::vec3 d = fibonacciDirection(i, kLandingRays);
      if (!(d.z > 0.0f && d.y >= 0.0f && d.y < d.x)) continue;
      for (int m = 0; m < 16; ++m) {
        glm::vec3 e = (m & 8) ? glm::vec3(d.y, d.x, d.z) : d;
        if (m & 1) e.x = -e.x;
        if (m & 2) e.y = -e.y;
        if (m & 4) e.z = -e.z;
        out.push_back(e);
      }
    }
    return out;
  }();
  return directions;
}

// Faces a light's ray goes on through: liquids and faces that cast no shadow (the compiler lights
// what lies beyond them), and faces never drawn.
bool passesThrough(const RenderScene& rs, uint32_t face) {
  return (rs.faceFlags[face] & (kFaceLiquid | kFaceNoShadow | kFaceHidden)) != 0;
}

// Where the ray from `origin` along unit `dir` lands within `reach`; nullopt where it meets sky,
// leaves the level or lands nowhere nearer.
std::optional<Landing> land(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& dir, float reach) {
  constexpr int kMaxPasses = 8;
  Ray ray{origin, 0.0f, dir, reach};
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    const std::optional<Hit> hit = rs.tracer.closestHit(ray);
    if (!hit || (rs.faceFlags[hit->face] & kFaceSky)) return std::nullopt;
    // Checked before `inside`: a light in a liquid (q1_litwater's green one) leaves through the
    // liquid's own faces from within, and the compiler lights what lies beyond them.
    if (passesThrough(rs, hit->face)) {
      ray.tMin = continueRayAfter(hit->t);
      continue;
    }
    if (hit->inside) return std::nullopt; // a light inside a wall lights nothing through it
    const glm::vec3 n = faceNormal(rs, hit->face);
    // The side the lit face looks to: the axis of its normal turned towards the light.
    const glm::vec3 towards = glm::dot(n, dir) > 0.0f ? -n : n, a = glm::abs(towards);
    const uint32_t axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
    const float texture = linearToSrgb(faithful::maxChannel(glm::vec3(rs.materials[rs.scene->faces[hit->face].material].averageAlbedo)));
    return Landing{hit->t, std::abs(glm::dot(n, dir)), ray.origin + dir * hit->t, axis * 2 + (towards[axis] < 0.0f ? 1 : 0), texture};
  }
  return std::nullopt;
}

} // namespace

bool matchedWhereItLands(const GpuLight& light) {
  // A point spread over a _surface face (or a bounce light) is faithful-only: physical mode draws
  // the face as an area emitter and leaves the point out of its lists (light_grid.cpp
  // isPhysicalCandidate), so no tracer reads its physical intensity. On lq_e4m3 those are 1,578
  // of 2,757 lights: most of the landings' rays went to them.
  if (light.flags & kLightFlagFromSurface) return false;
  if (light.type != uint32_t(LightType::Point)) return false;
  switch (LightFormula(light.formula)) {
  case LightFormula::Linear:
  case LightFormula::Inverse:
  case LightFormula::Inverse2:
  case LightFormula::Inverse2A: return true;
  default: return false;
  }
}

std::vector<Landing> landings(const RenderScene& rs, const GpuLight& light) {
  const float r = reach(light, rs.world.scaledist);
  std::vector<Landing> out;
  out.reserve(landingDirections().size());
  for (const glm::vec3& dir : landingDirections()) {
    if (faithful::spotTerm(light, -dir) == 0.0f) continue; // outside a spotlight's cone
    if (const std::optional<Landing> l = land(rs, light.origin, dir, r)) out.push_back(*l);
  }
  return out;
}

std::optional<float> landedIntensity(const GpuLight& light, std::span<const Landing> landed, float scaledist) {
  const float r = reach(light, scaledist);
  double compiled = 0.0, windowed = 0.0;
  for (const Landing& l : landed) {
    const float d = std::max(l.distance, kLandingMinDistance), cosine = std::max(l.cosine, kLandingMinCosine);
    compiled += double(faithful::copyDistanceValue(light, d, scaledist)) * faithful::angleTerm(cosine, light.anglescale) / cosine * d * d;
    windowed += std::isfinite(r) ? window(d, r) : 1.0f;
  }
  if (!(compiled > 0.0) || !(windowed > 0.0)) return std::nullopt;
  return float(compiled / windowed);
}

float landedFraction(const GpuLight& light, const Landing& l, const WorldLighting& world) {
  const float d = std::max(l.distance, kLandingMinDistance), cosine = std::max(l.cosine, kLandingMinCosine);
  return faithful::distanceValue(light, d, world.scaledist) * faithful::angleTerm(cosine, light.anglescale) *
      faithful::maxChannel(light.color) * world.range / world.overbrightOne;
}

namespace {

// The cube and side a landing counts in (LandedLightmap): the cube's coordinates, 16 bits each,
// and the side, packed into one key.
uint64_t cellOf(const Landing& l) {
  const glm::ivec3 c = glm::ivec3(glm::floor(l.position / kLightmapCell)) & 0xffff;
  return uint64_t(c.x) | uint64_t(c.y) << 16 | uint64_t(c.z) << 32 | uint64_t(l.side) << 48;
}

// The patch of surface a landing stands for, per unit solid angle (landedIntensity).
float patchArea(const Landing& l) {
  const float d = std::max(l.distance, kLandingMinDistance);
  return d * d / std::max(l.cosine, kLandingMinCosine);
}

// One light's mean lightmap fraction over its landings in each cell, each weighed by the patch
// it stands for: a light's rays are densest near it, where its light is brightest.
std::unordered_map<uint64_t, float> meanPerCell(const GpuLight& light, std::span<const Landing> landed, const WorldLighting& world) {
  std::unordered_map<uint64_t, glm::vec2> sums; // area x fraction, area
  for (const Landing& l : landed) {
    const float area = patchArea(l);
    sums[cellOf(l)] += glm::vec2(area * landedFraction(light, l, world), area);
  }
  std::unordered_map<uint64_t, float> means;
  for (const auto& [cell, sum] : sums) means[cell] = sum.x / sum.y;
  return means;
}

} // namespace

void LandedLightmap::add(const GpuLight& light, std::span<const Landing> landed, const WorldLighting& world) {
  for (const auto& [cell, mean] : meanPerCell(light, landed, world)) cells_[cell] += mean;
}

float LandedLightmap::at(const Landing& l) const {
  const auto it = cells_.find(cellOf(l));
  return it == cells_.end() ? 0.0f : it->second;
}

std::optional<float> landedDisplayMatch(const GpuLight& light, std::span<const Landing> landed, const WorldLighting& world,
                                        const LandedLightmap& lightmap) {
  if (world.luxelDisplay != BT_LUXEL_DISPLAY_IDENTITY) return std::nullopt;
  // The lightmap stores at most 255 of the brightest channel, which the display shows at 255 / overbrightOne.
  const float maxFraction = 255.0f / world.overbrightOne;
  const std::unordered_map<uint64_t, float> own = meanPerCell(light, landed, world);
  double shown = 0.0, linear = 0.0;
  for (const Landing& l : landed) {
    const float s = landedFraction(light, l, world);
    if (!(s > 0.0f)) continue;
    // The lightmap here: this light's own fraction at the landing, the others' as their means in its cell.
    const float total = std::max(lightmap.at(l) - own.at(cellOf(l)) + s, s);
    // Where the display is clipped (the lightmap at 255, or the texture shown white), no k
    // follows it: physical light has no ceiling, and matched there the light would be dimmed
    // everywhere to pay for its hot spot.
    if (total >= maxFraction || l.texture * total >= 1.0f) continue;
    const float area = patchArea(l);
    // This light's share of what the display shows there (texture x lightmap in the display's
    // gamma space, at most white), and what physical light gives there at k = 1.
    shown += double(area) * s / total * srgbToLinear(l.texture * total);
    linear += double(area) * s * srgbToLinear(l.texture);
  }
  if (!(linear > 0.0) || !(shown > 0.0)) return std::nullopt;
  return float(shown / linear);
}

void prepareWhereTheyLand(const RenderScene& rs, std::span<GpuLight> lights) {
  std::vector<std::vector<Landing>> landed(lights.size());
  parallelFor(lights.size(), 0, [&](size_t i) {
    prepare(lights[i], rs.world.scaledist);
    if (matchedWhereItLands(lights[i])) landed[i] = landings(rs, lights[i]);
  });
  LandedLightmap lightmap;
  for (size_t i = 0; i < lights.size(); ++i)
    if (lights[i].value > 0.0f) lightmap.add(lights[i], landed[i], rs.world);
  parallelFor(lights.size(), 0, [&](size_t i) {
    GpuLight& light = lights[i];
    const std::optional<float> intensity = landedIntensity(light, landed[i], rs.world.scaledist);
    if (!intensity) return;
    const std::optional<float> k = landedDisplayMatch(light, landed[i], rs.world, lightmap);
    light.physicalIntensity = *intensity * (k ? *k / BT_PHYSICAL_DISPLAY_MATCH : 1.0f);
  });
}

} // namespace bt::physical
