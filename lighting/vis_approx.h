// ericw-tools `light`'s light culling without vis data ("visapprox rays"): before lighting a
// face, the compiler drops every light whose box lies apart from the face's, the box being the
// bounds of where 32 x 32 rays cast from the light stop, grown by a quarter of its size on each
// side (2.0.0-alpha11: light.cc picks `-visapprox auto` = `rays` for a .bsp without vis data,
// entities.cc EstimateVisibleBoundsAtPoint, ltface.cc CullLight). It is a shortcut that the
// compiled lightmaps show: a face lit through a gap that few of the rays find stays black.
// Faithful mode's bakes (lightmap_bake.h on the CPU, shaders/bake.comp on the GPU) apply it,
// each light's box computed once here (RenderScene::visBoxes, GpuLight::visBox), bounce lights'
// too.
#pragma once

#include "scene/gpu_structs.h"
#include "scene/scene.h"
#include "scene/winding.h"

#include <glm/vec3.hpp>

#include <vector>

namespace bt {

struct RenderScene;

// Whether the compiler culls this level's lights by rays: a level it compiles for Quake, Hexen II,
// Quake 2 or Half-Life from its .map (qbsp leaves no vis data, so `auto` takes `rays`). Not a
// compiled .bsp (run through `vis`, the compiler culls by its PVS instead: not modelled) nor a
// Quake 3 level (q3map2 has no such cull).
bool compilerCullsByRays(const Scene& scene);

// The box a light at `point` is culled by (EstimateVisibleBoundsAtPoint): rays along the
// compiler's 32 x 32 directions (UniformPointOnSphere(x / 31, y / 31)), each stopping at the first
// face that blocks faithful light or at sky, else after 65,536 units; the bounds of the point and
// where they stop, grown by a quarter of their size on each side.
GpuVisBox visibleBounds(const RenderScene& rs, const glm::vec3& point);

// The bounds of a compiled face's polygon (faceextents_t::bounds).
GpuVisBox polygonBounds(const Winding& polygon);

// CullLight's test: the boxes lie apart by more than BT_VIS_BOX_EPSILON on some axis.
bool visBoxesApart(const GpuVisBox& light, const GpuVisBox& face);

// Gives every light the compiler culls its box (RenderScene::visBoxes, GpuLight::visBox), where
// compilerCullsByRays: point lights (entities, `_surface` points) on the default lighting and
// shadow channels (CullLight skips the others: its rays see the default channel only). Bounce
// lights come later (assignBounceVisBoxes). All cores.
void assignVisBoxes(RenderScene& rs, unsigned threads = 0);

// Gives the bounce lights rs.lights[firstBounce..] their boxes, appended to rs.visBoxes, where
// compilerCullsByRays: the compiler culls a bounce light as it culls an entity light
// (ltface.cc SurfaceLight_SphereCull: the face is skipped when its bounds lie apart from the
// light's box, EstimateVisibleBoundsAtPoint at the light's one point, `-emissivequality low`), on
// every channel (its rays see the default one). A light that stands for several merged ones
// (bounce.h clusterBounceLights, large levels only) gets the box of its own point. The gather of
// a later `_bounce` pass does not cull (the compiler's does). All cores.
void assignBounceVisBoxes(RenderScene& rs, uint32_t firstBounce, unsigned threads = 0);

} // namespace bt
