// Faithful-mode `_surface` lights: the point lights ericw-tools `light` creates from a template
// (entities.cc MakeSurfaceLights, surflight.cc MakeSurfaceLight), as ordinary GpuLights so that
// both tracers treat them like any other light.
//
// Two kinds, chosen per template by `_surface_radiosity` (worldspawn `_surflight_radiosity`):
//   - Q1 kind (the default): every face with the template's texture is cut on a 128-unit world
//     grid (GLQuake's SubdividePolygon, `light -surflight_subdivide` 128); each piece gets a copy
//     of the template, with its full value, at the piece's centroid lifted `_surface_offset`
//     (2) units along the face normal; `_surface_spotlight` turns the copies into spotlights
//     along the normal.
//   - radiosity kind: one point per face (`-emissivequality low`, the default) at the mean of
//     its vertices lifted 1 unit, carrying value x face area (LightFormula::SurfaceRadiosity).
//
// The compiler works on the faces of the compiled BSP. A Quake 1 / Half-Life .bsp import has
// them (Scene::compiledLighting): the points go on those faces, as `light` puts them (the Q1 kind
// only on faces a leaf lists, a liquid's face only from outside the liquid). From a .map,
// qbsp_faces.h rebuilds them from the brush sides; faces that look into the void outside a sealed
// level are dropped, as qbsp drops them.
#pragma once

#include "bvh/trace_scene.h"
#include "lighting/lights.h"
#include "lighting/qbsp_faces.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <vector>

namespace bt {

// `contents[b]` for every brush of `scene`; `worldTree` qbsp's tree of its world (RenderScene::worldTree). A radiosity template without `_color` takes the
// texture's colour (scene materials). A template that would make more than kMaxSurfaceLights
// points (a huge face) stops there, with a warning in `diagnostics`. `tracer` (the level's
// brushes) tells which faces look into the void, which qbsp removes (looksIntoVoid).
inline constexpr size_t kMaxSurfaceLights = kMaxPiecesPerFace - 1;
std::vector<GpuLight> spreadSurfaceLights(const Scene& scene, const std::vector<SurfaceTemplate>& templates,
                                          const std::vector<BrushContents>& contents, const QbspTree& worldTree, const WorldLighting& world,
                                          const TraceScene& tracer, Diagnostics& diagnostics);

} // namespace bt
