// ericw-tools `light`'s light culling without vis data ("visapprox rays"): before lighting a
// face, the compiler drops every light whose box lies apart from the face's, the box being the
// bounds of where 32 x 32 rays cast from the light stop, grown by a quarter of its size on each
// side (2.0.0-alpha11: light.cc picks `-visapprox auto` = `rays` for a .bsp without vis data,
// entities.cc EstimateVisibleBoundsAtPoint, ltface.cc CullLight). It is a shortcut that the
// compiled lightmaps show: a face lit through a gap that few of the rays find stays black.
// Faithful mode's bakes (lightmap_bake.h on the CPU, shaders/bake.comp on the GPU) apply it,
// each light's box computed once: here, on the CPU (RenderScene::visBoxes, GpuLight::visBox),
// bounce lights' too, or by the GL bake before its first pass (renderer/gl/gl_bake.h), whose
// rays walk the same BVH.
#pragma once

#include "scene/gpu_structs.h"
#include "scene/scene.h"
#include "scene/winding.h"
#include "shaders/light_constants.glsl" // the rays and the growth, shared with bake.comp

#include <glm/vec3.hpp>

#include <vector>

namespace bt {

struct RenderScene;

// Whether the compiler culls this level's lights by rays: a level it compiles for Quake, Hexen II,
// Quake 2 or Half-Life from its .map (qbsp leaves no vis data, so `auto` takes `rays`). Not a
// compiled .bsp (run through `vis`, the compiler culls by its PVS instead: not modelled) nor a
// Quake 3 level (q3map2 has no such cull).
bool compilerCullsByRays(const Scene& scene);

// The compiler's 32 x 32 ray directions (UniformPointOnSphere(x / 31, y / 31), in double, then
// rounded to float), x-major: what both tracers cast, the GPU reading this table.
inline constexpr int kVisRays = BT_VIS_RAYS;
const std::vector<glm::vec3>& visRayDirections();
inline constexpr float kVisRayLength = BT_VIS_RAY_LENGTH; // EstimateVisibleBoundsAtPoint's reach
inline constexpr float kVisBoxGrowth = BT_VIS_BOX_GROWTH; // the bounds grow by this share of their size on each side

// The box a light at `point` is culled by (EstimateVisibleBoundsAtPoint): rays along
// visRayDirections, each stopping at the first face that blocks faithful light or at sky, else
// after kVisRayLength; the bounds of the point and where they stop (point + dir * t, in float,
// each product and sum rounded apart, as shaders/bake.comp computes them), grown by kVisBoxGrowth.
GpuVisBox visibleBounds(const RenderScene& rs, const glm::vec3& point);

// The bounds of a compiled face's polygon (faceextents_t::bounds).
GpuVisBox polygonBounds(const Winding& polygon);

// CullLight's test: the boxes lie apart by more than BT_VIS_BOX_EPSILON on some axis.
bool visBoxesApart(const GpuVisBox& light, const GpuVisBox& face);

// Numbers the lights the compiler culls (GpuLight::visBox = 1 + their place in
// RenderScene::visBoxLights), where compilerCullsByRays: point lights (entities, `_surface`
// points) on the default lighting and shadow channels (CullLight skips the others: its rays see
// the default channel only). Not bounce lights: they come later (assignBounceVisBoxes). Their boxes are left to computeVisBoxes (RenderScene::visBoxes stays empty).
void numberVisBoxLights(RenderScene& rs);
// The boxes of rs.visBoxLights from `first` on, in that order, on `threads` cores (0: all).
std::vector<GpuVisBox> computeVisBoxes(const RenderScene& rs, unsigned threads = 0, size_t first = 0);
// Both: every culled light numbered and its box in RenderScene::visBoxes.
void assignVisBoxes(RenderScene& rs, unsigned threads = 0);

// Gives the bounce lights rs.lights[firstBounce..] their boxes, appended to rs.visBoxLights and
// rs.visBoxes, where
// compilerCullsByRays: the compiler culls a bounce light as it culls an entity light
// (ltface.cc SurfaceLight_SphereCull: the face is skipped when its bounds lie apart from the
// light's box, EstimateVisibleBoundsAtPoint at the light's one point, `-emissivequality low`), on
// every channel (its rays see the default one). A light that stands for several merged ones
// (bounce.h clusterBounceLights, large levels only) gets the box of its own point. The gather of
// a later `_bounce` pass does not cull (the compiler's does). All cores.
void assignBounceVisBoxes(RenderScene& rs, uint32_t firstBounce, unsigned threads = 0);

} // namespace bt
