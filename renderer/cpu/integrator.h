// The integrator: radiance along one camera ray, in two lighting modes. This file and
// faithful.h are the contract the GL tracer follows (see README.md for formulas and units).
#pragma once

#include "renderer/cpu/render_scene.h"
#include "renderer/cpu/sampling.h"

#include <glm/vec3.hpp>

#include <optional>
#include <span>

namespace bt {

enum class LightingMode { Faithful, Physical };

struct IntegratorSettings {
  LightingMode mode = LightingMode::Faithful;
  int bounces = 3; // physical: indirect bounces after the first hit (faithful mode bounces as the
                   // level's `_bounce` asks, through bounce lights: bounce.h)
  // true: the light grid's lists (faithful) and one selected point light per hit (physical);
  // false: every light at every hit, the reference both converge to (tests, benchmarks).
  bool lightSelection = true;
};

// A hit after skipping faces that are never drawn (hidden textures, back faces).
struct SurfaceHit {
  bool found = false;
  float t = 0.0f;
  uint32_t face = 0;
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 0.0f, 1.0f}; // the face plane's normal (faces the ray)
};

SurfaceHit traceVisible(const RenderScene& rs, const Ray& ray);

// True when something that casts shadows in `mode` lies between the ray's tmin and tmax.
bool occluded(const RenderScene& rs, const Ray& ray, LightingMode mode);

// True when the ray reaches a sky face (or leaves the level) before anything else: sunlight.
// `skyMaterial`: 1 + the only sky material that counts (a sun's `_suntexture`), 0 any sky.
bool reachesSky(const RenderScene& rs, const Ray& ray, LightingMode mode, uint32_t skyMaterial = 0);

// Base colour at a face point: rgb as stored (sRGB-encoded, 0..1), a = coverage.
glm::vec4 baseColorAt(const RenderScene& rs, uint32_t face, const glm::vec3& p);
glm::vec3 emissiveAt(const RenderScene& rs, uint32_t face, const glm::vec3& p); // sRGB-encoded

// Physical mode's shading normal at a hit seen from wo (unit, towards the viewer): the face
// normal, or where the face's material has a normal map, the map's normal in the face's texture
// frame (DarkPlaces' `_norm` convention, integrator.cpp), bent where needed so that it faces wo
// and light reflected about it leaves the face (Iray's fix). Faithful mode and the normal AOV
// keep the face normal: ericw-tools' `light` has no normal maps.
glm::vec3 shadingNormal(const RenderScene& rs, const SurfaceHit& hit, const glm::vec3& wo);

// Faithful mode: the light sum ericw-tools `light` would compute at surface point p with
// normal n (light units, per colour channel; before _range). Stochastic only for soft
// lights (deviance, penumbra, domes), exact otherwise; `_surface` lights are point lights here.
// Every light of the level is looked at: the reference that faithfulLightFromGrid must reproduce
// (tests/render/light_selection_test.cpp), which the lit-oracle test then holds to the compiler.
// `twoSided`: the surface is a lit liquid, which ericw-tools lights from both sides (a light
// below it counts with |cos|, ltface.cc "twosided"); the renderer sets it on kFaceLiquid faces.
glm::vec3 faithfulLightAt(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided = false);

// Faithful dirt (worldspawn `_dirt`, ericw-tools' ambient occlusion) at surface point p with
// normal n: 0 in the open .. 1 enclosed, 0 when the level uses no dirt. faithfulLightAt and
// faithfulLightFromGrid compute it first (drawing `_dirtmode 1`'s random numbers before any
// light's) and dim each light that has kLightFlagDirt by faithful::lightDirtFactor.
float faithfulDirtOcclusion(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng);

// The same sum over the light grid's lists only (light_grid.h): suns, domes, local minlights
// and infinite-reach lights, then the finite-reach lights of p's cell. Lights left out give
// exactly 0 at p, so for lights without soft shadows the result equals faithfulLightAt's (up
// to float summation order); soft lights draw their random numbers in list order instead.
//
// Why every candidate is shadow-tested here instead of one picked at random, as physical mode
// does: the faithful pixel is a non-linear function of this sum (minlight and local-minlight
// floors, the 255 overbright clamp, the max with fullbright texels, and above all the sRGB
// decode of texture x lightmap / 128). A random but unbiased estimate S of the sum converges to
// the mean of f(S), which differs from f(sum) wherever f bends (Jensen), so the image would
// not converge to the exhaustive one. The grid keeps the result exact and drops the per-light
// loop from O(lights) to the few lights that can reach the point.
glm::vec3 faithfulLightFromGrid(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided = false);

// The shadow rays a shown point spends on its cell's bounce lights (bounce.h) when the cell lists
// more than this many; with fewer each gets its own, as any light. A level's bounce lights reach
// most of it (their gate at value / d^2), so a cell of a large level lists hundreds of them.
// 16, not fewer: the shown pixel bends the estimate (faithfulLightSampled), and with 8 lq_e3m1's
// image mean came out 0.8 % low in blue (16: 0.2 %, 32: 0.03 %, at 7 % and 18 % more render
// time than 8). shaders/faithful.glsl BOUNCE_SHADOW_RAYS is the same.
inline constexpr size_t kBounceShadowRays = 16;

// What the renderer shows at p (radiance(), lightSelection on): faithfulLightFromGrid with the
// cell's bounce lights, when it lists more than kBounceShadowRays, drawn among by their unshadowed
// share (faithfulLightFromSampled's estimate, kBounceShadowRays rays) instead of each
// shadow-tested. An unbiased estimate of the bounce lights' sum, exact where all of them are
// visible and of one hue; the pixel, a bent function of the sum (see above), converges to the
// mean of that function over the estimate, which differs from faithfulLightFromGrid's pixel
// where the estimate spreads (a cell's bounce lights partly shadowed) and the pixel bends there,
// above all at the 255 clamp: a rarely drawn visible light counts total / kBounceShadowRays
// (measured on lq_e3m1's image mean: -0.06 % green, -0.23 % blue; renderer/cpu/README.md).
// `bounceShadowRays`, when given, is raised by the shadow rays it may cast to bounce lights (tests).
glm::vec3 faithfulLightSampled(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided = false,
                               int* bounceShadowRays = nullptr);

// What ericw-tools' bounce re-emits of the light at p (ltface.cc's bounce_color, from the grid's
// lists): the positive lights of style 0 (any style with `_bouncestyled`), no local minlight, no
// floors, no bounce lights. bounce.h averages it over each face. `occlusion`, when given, is
// faithfulDirtOcclusion's at p, known already: only with `_dirtmode 0`, whose rays draw no random
// numbers, so that the result is the same as without it (bounce.cpp samples a luxel in several
// passes).
glm::vec3 faithfulBounceSourceLight(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided = false,
                                    std::optional<float> occlusion = std::nullopt);

// The sum of `lights` alone at p (each with its shadow ray and dirt), no floors: a later bounce
// pass takes what the previous pass's bounce lights brought.
glm::vec3 faithfulLightFrom(const RenderScene& rs, std::span<const GpuLight> lights, const glm::vec3& p, const glm::vec3& n, Rng& rng,
                            bool twoSided = false);

// An unbiased estimate of faithfulLightFrom for point lights without jitter (bounce lights) that
// casts at most `maxShadowRays` shadow rays: when more lights are given, that many targets are
// drawn, one in each equal stratum of their unshadowed shares at p laid end to end (the
// compiler's 0.01 gate applied to each light's own share), and each light a target falls on
// counts its share / (rays x probability) per target where it is visible. Exact where every
// candidate is visible and of one hue. The bounce pass averages it over a face, a linear mean, so
// the estimate stays unbiased there; faithfulLightSampled draws the same way at a shown point.
glm::vec3 faithfulLightFromSampled(const RenderScene& rs, std::span<const GpuLight> lights, const glm::vec3& p, const glm::vec3& n,
                                   Rng& rng, bool twoSided, size_t maxShadowRays);

// The same number, from only the `candidates` among `lights` (indices, increasing) that can have
// a share at p: every light left out must give exactly 0 there (light_grid.h's lists for a grid
// of `lights` do). The draw sums the same shares in the same order, so the result is bit for bit
// the one over every light; the bounce pass sweeps a few thousand lights instead of all. With
// `occlusion`, as faithfulBounceSourceLight.
glm::vec3 faithfulLightFromSampled(const RenderScene& rs, std::span<const GpuLight> lights, std::span<const uint32_t> candidates,
                                   const glm::vec3& p, const glm::vec3& n, Rng& rng, bool twoSided, size_t maxShadowRays,
                                   std::optional<float> occlusion = std::nullopt);

// The light ericw-tools `light` stores at a luxel whose sample point is p (already lifted off the
// face as the compiler lifts it: lightmap_bake.h), computed in passes so that both tracers bake
// it the same way and a bake can show its luxels before the last pass:
//   pass 0   the dirt occlusion (cast from p itself), then every light of one fixed position
//            (point lights without `_deviance`, suns without a penumbra, each bounce light);
//   pass k   the k-th of the compiler's sky dome directions (faithful::skyDomeDirections) and
//            the k-th of `softSamples` samples of each soft light (a sun's penumbra or
//            `_deviance` jitter), for k below those counts.
// Pass k draws only from its own stream (the caller's pixelRng(sample, k)). The light is then
// the fixed part plus the mean of the dome and soft samples so far, under the floors (minlight,
// `faceMinlight`): faithfulLuxelLight.
struct LuxelSums {
  glm::vec3 fixed{0.0f};
  float occlusion = 0.0f;
  glm::vec3 localMin{0.0f}; // delay-4 lights: a floor, not a term
  glm::vec3 dome{0.0f};     // sum over the passes so far of each pass's dome direction
  glm::vec3 soft{0.0f};     // sum over the passes so far of each pass's soft samples
};
// How many passes a level's luxels take: 1, the dome's directions, or `softSamples`.
int luxelPasses(const RenderScene& rs, int softSamples);
void faithfulLuxelPass(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, bool twoSided, int pass, int softSamples, Rng& rng,
                       LuxelSums& sums);
// The light after `passes` passes.
glm::vec3 faithfulLuxelLight(const RenderScene& rs, const LuxelSums& sums, int passes, int softSamples, const glm::vec3& faceMinlight);
// What an occluded luxel (its sample point in solid, or too far off its face) stores: the floors.
glm::vec3 faithfulLuxelFloor(const RenderScene& rs, const glm::vec3& faceMinlight);

// Faithful mode: the floor a face's own radiosity `_surface` template puts under its light
// (zero for every other face); the caller takes max(faithfulLightAt, this), with the minlight
// dirt of `_minlight_dirt` where the level has it (radiance() does).
glm::vec3 faithfulFaceMinlight(const RenderScene& rs, uint32_t face);

// Linear radiance along the ray.
glm::vec3 radiance(const RenderScene& rs, const IntegratorSettings& settings, const Ray& ray, Rng& rng);

// Physical-mode scale from Quake light units: a point light of value V has radiant intensity
// V * kPhysicalPointScale * _range, a sun of value V gives irradiance V * kPhysicalSunScale *
// _range. Chosen so that a white surface head-on to a delay-2 light (or a sun, anglescale 0)
// shows the same brightness in both modes.
inline constexpr float kPhysicalPointScale = kPi * 128.0f;
inline constexpr float kPhysicalSunScale = kPi / 128.0f;

} // namespace bt
