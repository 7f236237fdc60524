// The CPU tracer's integrator: radiance along one camera ray, in two lighting modes. Faithful mode
// shows lighting/faithful_light.h's light model through the engine's display rules; physical mode
// path-traces. pathtrace.comp follows it (formulas and units: lighting/README.md).
#pragma once

#include "lighting/faithful_light.h"
#include "lighting/render_scene.h"
#include "lighting/sampling.h"
#include "lighting/visibility.h"
#include "renderer/render.h" // IntegratorSettings

#include <glm/vec3.hpp>

#include <optional>
#include <span>
#include <vector>

namespace bt {

// Physical mode's shading normal at a hit seen from wo (unit, towards the viewer): the face
// normal, or where the face's material has a normal map, the map's normal in the face's texture
// frame (DarkPlaces' `_norm` convention, integrator.cpp), bent where needed so that it faces wo
// and light reflected about it leaves the face (Iray's fix). Faithful mode and the normal AOV
// keep the face normal: ericw-tools' `light` has no normal maps.
glm::vec3 shadingNormal(const RenderScene& rs, const SurfaceHit& hit, const glm::vec3& wo);

// The random numbers of sample `sample` of pixel (x, y): physical mode's pixelSampler (with
// IntegratorSettings::lowDiscrepancy), else pixelRng. Its first two draws are the camera's
// subpixel; then atPcg() before radiance().
inline Rng pathRng(const IntegratorSettings& settings, uint32_t x, uint32_t y, uint32_t sample, uint32_t seed) {
  return settings.mode == LightingMode::Physical && settings.lowDiscrepancy ? pixelSampler(x, y, sample, seed)
                                                                            : pixelRng(x, y, sample, seed);
}

// Linear radiance along the ray.
glm::vec3 radiance(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, Rng& rng);

// The near-list pick's weight of each light of origin's near list (LightGrid::physicalNearLights)
// for a surface of shading normal n, as the pick computes them: for tests, which hold them to
// the scalar selectionWeight's floats.
std::vector<float> nearListWeights(const RenderScene& rs, const glm::vec3& origin, const glm::vec3& n);

// Physical mode's light leaving the camera ray's surface towards the camera, broken down by light
// (the viewer's pick says why a spot is lit): each point light's and sun's direct light with its
// own shadow rays (the exhaustive loop's terms, unclamped, as at the camera's surface), the
// worldspawn minlight, and the rest, the sky, emitting surfaces and the light bounced off other
// surfaces, as the mean of `samples` paths along the ray less those terms, so that the shares add
// up to the light shown. No shares on sky and liquids (only `shown`).
struct PhysicalShares {
  std::vector<glm::vec3> perLight; // in rs.lights' order
  glm::vec3 minlight{0.0f};        // worldspawn minlight on the surface (radiancePhysical)
  glm::vec3 rest{0.0f};            // sky, emitters and bounced light: noisy, may dip below 0
  glm::vec3 shown{0.0f};           // the mean radiance along the ray, linear, before exposure
  int samples = 0;                 // the paths of `shown`
};
PhysicalShares physicalLightShares(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, int samples, Rng& rng);

// Physical-mode scale from Quake light units: a point light of intensity I (light units x
// distance^2, lighting/physical_light.h) has radiant intensity I * kPhysicalPointScale * _range,
// a sun of value V gives irradiance V * kPhysicalSunScale * _range. Chosen so that a white
// surface head-on to a point light at its match distance (or a sun, anglescale 0) shows in
// linear light what the game shows there at a typical lightmap value: the light's own fraction
// times the display match (BT_PHYSICAL_DISPLAY_MATCH; lighting/README.md, "Physical mode").
inline constexpr float kPhysicalPointScale = kPi * BT_PHYSICAL_DISPLAY_MATCH / BT_PHYSICAL_LIGHT_UNIT;
inline constexpr float kPhysicalSunScale = kPi * BT_PHYSICAL_DISPLAY_MATCH / BT_PHYSICAL_LIGHT_UNIT;

} // namespace bt
