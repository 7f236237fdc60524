// Faithful mode's light model: the light ericw-tools `light` (2.0.0-alpha11, ltface.cc) computes at
// a surface point, asked in one way (FaithfulQuery) whichever set of lights is summed, in the way
// pbrt-v4 puts every light sampler behind one interface. The CPU tracer shows it at each hit, the
// bounce pass (bounce.h) and the luxel bake (lightmap_bake.h) compile with it, and
// shaders/faithful.glsl, pathtrace.comp and bake.comp compute the same on the GPU.
// Formulas and units: lighting/README.md.
#pragma once

#include "lighting/render_scene.h"
#include "shaders/light_constants.glsl" // BT_BOUNCE_SHADOW_RAYS, shared with the shaders
#include "lighting/sampling.h"
#include "lighting/shadow_groups.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bt {

// The shadow rays a shown point spends on its cell's bounce lights (bounce.h) when the cell lists
// more than this many; with fewer each gets its own, as any light. A level's bounce lights reach
// most of it (their gate at value / d^2), so a cell of a large level lists hundreds of them.
// 16, not fewer: the shown pixel bends the estimate (LightSet::GridSampledBounce), and with 8
// lq_e3m1's image mean came out visibly low in blue (lighting/README.md has the figures).
inline constexpr size_t kBounceShadowRays = BT_BOUNCE_SHADOW_RAYS;

// Which lights a faithful query sums.
enum class LightSet {
  // Every light of the level: the reference the others must reproduce
  // (tests/render/light_selection_test.cpp), which the lit-oracle test holds to the compiler.
  All,
  // The light grid's lists only (light_grid.h): suns, domes, local minlights and infinite-reach
  // lights, then the finite-reach lights of p's cell. Lights left out give exactly 0 at p, so for
  // lights without soft shadows the result equals All's (up to float summation order); soft
  // lights draw their random numbers in list order instead.
  //
  // Why every candidate is shadow-tested instead of one picked at random, as physical mode does:
  // the faithful pixel is a non-linear function of this sum (minlight and local-minlight floors,
  // the 255 overbright clamp, the max with fullbright texels, and above all the sRGB decode of
  // texture x lightmap / 128). A random but unbiased estimate S of the sum converges to the mean
  // of f(S), which differs from f(sum) wherever f bends (Jensen), so the image would not converge
  // to the exhaustive one. The grid keeps the result exact and drops the per-light loop from
  // O(lights) to the few lights that can reach the point.
  Grid,
  // What the renderer shows (lightSelection on): Grid, with the cell's bounce lights, when it lists
  // more than kBounceShadowRays, drawn among by their unshadowed share (the estimate of
  // GivenLights::maxShadowRays) instead of each shadow-tested. Unbiased for the bounce lights' sum,
  // exact where all of them are visible and of one hue; the pixel, a bent function of the sum,
  // converges to the mean of that function over the estimate, which differs from Grid's pixel where
  // the estimate spreads (a cell's bounce lights partly shadowed) and the pixel bends there, above
  // all at the 255 clamp (the figures on lq_e3m1: lighting/README.md).
  GridSampledBounce,
  // What ericw-tools' bounce re-emits of the light at p (ltface.cc's bounce_color, from the grid's
  // lists): the positive lights of style 0 (any style with `_bouncestyled`), no local minlight, no
  // floors, no bounce lights. bounce.h averages it over each face.
  BounceSources,
  // FaithfulQuery::given alone (each with its shadow ray and dirt), no floors: a later bounce pass
  // takes what the previous pass's bounce lights brought.
  Given,
};

// A list of point lights without jitter (bounce lights) for LightSet::Given.
struct GivenLights {
  std::span<const GpuLight> lights;
  // The only lights that can have a share at p (indices into `lights`, increasing; light_grid.h's
  // lists over `lights` are such), or nullopt for all. Every light left out must give exactly 0
  // there: the draw sums the same shares in the same order, so the result is bit for bit the one
  // over every light, and the bounce pass sweeps a few thousand lights instead of all.
  std::optional<std::span<const uint32_t>> candidates;
  // With more lights than this (counting all of `lights`, not the candidates), an unbiased estimate
  // that casts this many shadow rays: targets drawn one in each equal stratum of the lights'
  // unshadowed shares at p laid end to end (the compiler's 0.01 gate applied to each light's own
  // share), and each light a target falls on counts its share / (rays x probability) per target
  // where it is visible. Exact where every candidate is visible and of one hue. The bounce pass
  // averages it over a face, a linear mean, so the estimate stays unbiased there.
  size_t maxShadowRays = SIZE_MAX;
};

// ericw-tools' light cull without vis data at a receiver (shadow_groups.h GroupCull, one type for
// a luxel and its group).
using VisCull = GroupCull;

// One question to the faithful light model: the light sum at surface point p with normal n (light
// units, per colour channel; before _range). Stochastic only for soft lights (deviance, penumbra,
// domes) and drawn bounce lights, exact otherwise; `_surface` lights are point lights here.
struct FaithfulQuery {
  glm::vec3 p{0.0f};
  glm::vec3 n{0.0f, 0.0f, 1.0f};
  // The surface is a lit liquid, which ericw-tools lights from both sides (a light below it
  // counts with |cos|, ltface.cc "twosided"); the renderer sets it on kFaceLiquid faces.
  bool twoSided = false;
  uint32_t channels = kDefaultChannels; // the receiving face's objectChannels (render_scene.h)
  VisCull cull;                         // the compiler's light cull without vis data at p
  LightSet lights = LightSet::Grid;
  const GivenLights* given = nullptr; // LightSet::Given only
  // A floor under the sum beside worldspawn minlight: faithfulFaceMinlight of the receiver's face
  // (All, Grid, GridSampledBounce). `_minlight_dirt` dims both floors.
  glm::vec3 faceMinlight{0.0f};
  // faithfulDirtOcclusion's value at p, when known already: only with `_dirtmode 0`, whose rays
  // draw no random numbers, so that the result is the same as without it (bounce.cpp samples a
  // luxel in several passes). BounceSources and Given only.
  std::optional<float> occlusion;
  int* bounceShadowRays = nullptr; // raised by the shadow rays it may cast to bounce lights (tests)
};

glm::vec3 faithfulLight(const RenderScene& rs, const FaithfulQuery& query, Rng& rng);

// Why a spot is lit (the viewer's pick): each light's share of the faithful light at query.p, in
// rs.lights' order, with the floors that lift the sum to what the surface shows, so that
//   shown = sum of perLight + ambient + floors   (per channel).
// Every light of the level is asked (query.lights is ignored) and soft lights (`_deviance`,
// penumbra suns, domes) are averaged over `samples` draws; dirt is drawn once, as one pixel does.
struct LightShares {
  std::vector<glm::vec3> perLight; // one per rs.lights, zero where a light adds nothing
  glm::vec3 ambient{0.0f};         // worldspawn `_ambient` (q3map2)
  glm::vec3 floors{0.0f};          // what minlight, a face's template minlight or delay-4 lights add on top
  glm::vec3 shown{0.0f};           // the light the surface shows there
  float occlusion = 0.0f;          // the dirt at p (0 in the open)
};
LightShares faithfulLightShares(const RenderScene& rs, const FaithfulQuery& query, int samples, Rng& rng);

// Faithful dirt (worldspawn `_dirt`, ericw-tools' ambient occlusion) at surface point p with
// normal n: 0 in the open .. 1 enclosed, 0 when the level uses no dirt. faithfulLight computes it
// first (drawing `_dirtmode 1`'s random numbers before any light's) and dims each light that has
// kLightFlagDirt by faithful::lightDirtFactor.
float faithfulDirtOcclusion(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, Rng& rng);

// The floor a face's own radiosity `_surface` template puts under its light (zero for every other
// face): what a query at that face's points passes as FaithfulQuery::faceMinlight.
glm::vec3 faithfulFaceMinlight(const RenderScene& rs, uint32_t face);

// A point light's position for one sample: one of ericw-tools' `_samples` jittered copies, uniform
// in the cube of half-size `_deviance` around the light. Physical mode jitters the same way.
glm::vec3 jitteredOrigin(const GpuLight& light, Rng& rng);

// A luxel's sky rays of one penumbra sun or one dome for all its passes, cast as packets
// (visibility.h reachSky) when pass 0 first asks, since they leave one point in nearby
// directions: bit k of `reaches` answers pass k's ray of `light`. Another such light of the
// same luxel casts ray by ray.
struct LuxelSky {
  const GpuLight* light = nullptr;
  std::array<uint64_t, 2> reaches{};
};

// The light ericw-tools `light` stores at a luxel whose sample point is p (already lifted off the
// face as the compiler lifts it: lightmap_bake.h), computed in passes so that both tracers bake
// it the same way and a bake can show its luxels before the last pass:
//   pass 0   the dirt occlusion (cast from p itself), then every light of one fixed position
//            (point lights without `_deviance`, suns without a penumbra, each bounce light),
//            negative ones apart (LuxelSums::negative);
//   pass k   the k-th of the compiler's sky dome directions (faithful::skyDomeDirections) and
//            the k-th of `softSamples` samples of each soft light (a sun's penumbra or
//            `_deviance` jitter), for k below those counts.
// Pass k draws only from its own stream (the caller's pixelRng(sample, k)). The light is then
// the fixed part plus the mean of the dome and soft samples so far, under the floors (minlight,
// `faceMinlight`): faithfulLuxelLight.
struct LuxelSums {
  glm::vec3 fixed{0.0f};
  float occlusion = 0.0f;
  glm::vec3 localMin{0.0f};      // delay-4 lights: a floor, not a term
  glm::vec3 negative{0.0f};      // faithful::subtractedLight lights: taken off after the floors
  glm::vec3 dome{0.0f};          // sum over the passes so far of each pass's dome direction
  glm::vec3 soft{0.0f};          // sum over the passes so far of each pass's soft samples
  LuxelSky penumbraSky, domeSky; // their sky rays, cast ahead
};
// How many passes a level's luxels take: 1, the dome's directions, or `softSamples`.
int luxelPasses(const RenderScene& rs, int softSamples);

// `channels`: the receiving face's objectChannels; `cull`: FaithfulQuery::cull.
// `style`: only the lights of that light style (lightStyle), as the compiler lights each style's
// lightmap of a face apart; kAllStyles: every light.
inline constexpr int kAllStyles = -1;
void faithfulLuxelPass(const RenderScene& rs, const glm::vec3& p, const glm::vec3& n, bool twoSided, int pass, int softSamples, Rng& rng,
                       LuxelSums& sums, uint32_t channels = kDefaultChannels, ShadowCache* cache = nullptr, VisCull cull = {},
                       int style = kAllStyles);
// The light after `passes` passes. With `floors` off (a lightmap of a style other than 0: the
// compiler puts minlight, a face's template minlight and `_ambient` into style 0's alone), the sum
// with its negative lights taken off, at least 0.
glm::vec3 faithfulLuxelLight(const RenderScene& rs, const LuxelSums& sums, int passes, int softSamples, const glm::vec3& faceMinlight,
                             bool floors = true);
// What an occluded luxel (its sample point in solid, or too far off its face) stores: the floors.
glm::vec3 faithfulLuxelFloor(const RenderScene& rs, const glm::vec3& faceMinlight);

} // namespace bt
