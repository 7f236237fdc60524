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
// The compiler works on the faces of the compiled BSP. We rebuild what qbsp's CSG leaves of each
// source brush side (visibleFragments), split it as a BSP tree grown on that surface alone
// would (qbsp3's choice of split planes among the edges of the brushes that reach the surface),
// merge what is left in each cell and apply the 240-texel subdivision. The compiler's tree is
// grown over the whole level, so its planes also cut a surface where nothing near it does: our
// faces are close to, not the same as, the compiler's (surface_lights.cpp, compilerFaces).
// Faces that look into the void outside a sealed level are dropped, as qbsp drops them.
#pragma once

#include "bvh/trace_scene.h"
#include "renderer/cpu/lights.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <vector>

namespace bt {

// What a brush is to qbsp's CSG: world brushes are solid or liquid; brush entities and
// clip/trigger/skip brushes carve nothing out of the world's faces.
enum class BrushContents : uint8_t { Empty, Solid, Liquid };

// `contents[b]` for every brush of `scene`. A radiosity template without `_color` takes the
// texture's colour (scene materials). A template that would make more than kMaxSurfaceLights
// points (a huge face) stops there, with a warning in `diagnostics`. `tracer` (the level's
// brushes) tells which faces look into the void, which qbsp removes (looksIntoVoid).
inline constexpr size_t kMaxSurfaceLights = 65536;
std::vector<GpuLight> spreadSurfaceLights(const Scene& scene, const std::vector<SurfaceTemplate>& templates,
                                          const std::vector<BrushContents>& contents, const WorldLighting& world, const TraceScene& tracer,
                                          Diagnostics& diagnostics);

// qbsp fills the void around a sealed level ("outside filling") and makes no face that looks
// into it. A point is in the void when some ray from it leaves the level (inside a sealed
// level every ray meets a brush); a level with a point entity in the void leaks, and qbsp then
// fills nothing: so does this.
class VoidTest {
public:
  VoidTest(const Scene& scene, const TraceScene& tracer);
  bool inVoid(const dvec3& p) const;

private:
  bool escapes(const dvec3& p) const;
  const TraceScene& tracer_;
  bool sealed_ = true;
};

// The parts of brush side `face` that qbsp's CSG keeps: outside every other solid brush (and,
// for a liquid's side, outside the other liquid brushes), as convex fragments.
std::vector<std::vector<dvec3>> visibleFragments(const Scene& scene, uint32_t face, const std::vector<BrushContents>& contents);

// The faces qbsp makes of brush side `face` (a Quake 1 level): what its CSG keeps, split as a
// tree grown on that side alone would split it, then cut every 224 texels once wider than 240
// (qbsp's SubdivideFace). The faces ericw-tools `light` bounces light from (bounce.h).
std::vector<std::vector<dvec3>> compiledFacePolygons(const Scene& scene, uint32_t face, const std::vector<BrushContents>& contents);

// GLQuake's SubdividePolygon: cut `winding` at multiples of `size` on each axis, the cut
// nearest the middle first, unless it would leave a piece thinner than 8 units. Stops cutting
// at kMaxSurfaceLights + 1 pieces (the rest stays whole), as the 240-texel subdivision of
// compiledFacePolygons does.
std::vector<std::vector<dvec3>> subdivideOnGrid(const std::vector<dvec3>& winding, double size);

} // namespace bt
