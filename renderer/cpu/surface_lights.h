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
// The compiler works on the faces of the compiled BSP, which qbsp has already clipped against
// the world; we work on the source brush sides, so a point that lands inside a solid brush
// (a side pressed against a wall) is dropped instead.
#pragma once

#include "renderer/cpu/lights.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <vector>

namespace bt {

// `solidBrush[b]`: brush b stops light and takes up space in the compiled map (world, opaque).
// `materials`: the per-material parameters (averageAlbedo gives a radiosity template without
// `_color` the texture's colour).
std::vector<GpuLight> spreadSurfaceLights(const Scene& scene, const std::vector<SurfaceTemplate>& templates,
                                          const std::vector<bool>& solidBrush, const std::vector<GpuMaterial>& materials,
                                          const WorldLighting& world);

// GLQuake's SubdividePolygon: cut `winding` at multiples of `size` on each axis, the cut
// nearest the middle first, unless it would leave a piece thinner than 8 units.
std::vector<std::vector<dvec3>> subdivideOnGrid(const std::vector<dvec3>& winding, double size);

} // namespace bt
