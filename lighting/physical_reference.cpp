#include "lighting/physical_reference.h"

#include "bvh/trace_scene.h"
#include "lighting/faithful.h"
#include "lighting/physical_light.h"
#include "lighting/render_scene.h"
#include "scene/parallel_for.h"

#include <algorithm>
#include <cmath>

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
    return Landing{hit->t, std::abs(glm::dot(faceNormal(rs, hit->face), dir))};
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

void prepareWhereTheyLand(const RenderScene& rs, std::span<GpuLight> lights) {
  parallelFor(lights.size(), 0, [&](size_t i) {
    GpuLight& light = lights[i];
    prepare(light, rs.world.scaledist);
    if (!matchedWhereItLands(light)) return;
    if (const std::optional<float> landed = landedIntensity(light, landings(rs, light), rs.world.scaledist))
      light.physicalIntensity = *landed;
  });
}

} // namespace bt::physical
