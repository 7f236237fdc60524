// The faces qbsp compiles of a Quake 1 level's brush sides, rebuilt from the .map: what its CSG
// keeps of each side, split as the BSP tree would split it, merged and subdivided as qbsp does.
// ericw-tools `light` spreads surface lights (surface_lights.h) and bounces light (bounce.h) over
// these faces, so the light models need them without a compile.
//
// We rebuild what qbsp's CSG leaves of each source brush side (visibleFragments). A side of the
// world is then handed down qbsp's tree of the whole world (qbsp_tree.h): the planes of the
// nodes above the node of its own plane cut it, and on that node qbsp makes its faces of the
// portals there and merges them (MergeFaceList), whatever planes below cut those portals: so a
// wall is whole across a doorway whose planes come below the wall's own in the tree, and cut
// where they come above it. What is left gets the 240-texel subdivision. Each face starts where
// the compiler's does (its portal's clips, its merges, its subdivision's clips), as the
// T-junction fix's fans break their ties by it. A side of a brush
// entity (its own model, its own tree) is split as a tree grown on that surface alone would
// split it (surfaceTreeFaces). qbsp's T-junction fix, which re-cuts a face with its neighbours'
// vertices on its edges (a quad and a triangle of a rectangle), needs every face of the world:
// qbsp_tjunc.h, run on them by the bounce (bounce.cpp). Not modelled: the merge of faces of
// different sides (each side is made on its own here, except a surface light's surface and,
// for its T-junction fix, the Quake 1 world's sides near it: surface_lights.cpp). Faces that
// look into the void outside a sealed level are dropped, as qbsp drops them.
#pragma once

#include "bvh/trace_scene.h"
#include "lighting/qbsp_tree.h"
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bt {

// What a brush is to qbsp's CSG: world brushes are solid or liquid; brush entities and
// clip/trigger/skip brushes carve nothing out of the world's faces.
enum class BrushContents : uint8_t { Empty, Solid, Liquid };

inline constexpr double kOnPlaneEpsilon = 0.01;   // qbsp's ON_EPSILON-like tolerance for touching planes
inline constexpr double kVoidProbeDistance = 1.0; // a face looks into the space this far in front of it

// A face may be cut into this many pieces at most, by either subdivision: as many as the whole
// level may have surface lights, and one more to tell that the cap was reached. A corrupt or
// absurd texture scale (a million texels a unit) or a face of a million units would otherwise
// cut into hundreds of millions of pieces: a hang and gigabytes before any cap on lights.
inline constexpr size_t kMaxPiecesPerFace = 65537;

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
// for a liquid's side, outside the other liquid brushes), and not under a coplanar side of a
// brush that comes later in the map and faces the same way (that one makes the face there), as
// convex fragments.
std::vector<std::vector<dvec3>> visibleFragments(const Scene& scene, uint32_t face, const std::vector<BrushContents>& contents);

// The faces qbsp makes of brush side `face` (a Quake 1 level): what its CSG keeps, split and
// merged as compilerFaces makes them, then cut every 224 texels once wider than 240 (qbsp's
// SubdivideFace). The faces ericw-tools `light` bounces light from (bounce.h).
std::vector<std::vector<dvec3>> compiledFacePolygons(const Scene& scene, uint32_t face, const std::vector<BrushContents>& contents,
                                                     const QbspTree& world);

// The world's tree: qbsp's BSP of the brushes that carve (contents not Empty).
QbspTree worldTree(const Scene& scene, const std::vector<BrushContents>& contents);

// A Quake 1 world's tree as ericw-tools qbsp grows it the second time (qbsp.cc ProcessEntity):
// after the void is filled, with the sides seen only from the void or from inside solid hidden
// (valued last), liquids and func_detail valued after the structural brushes. On
// testsurfacelight it has all 349 of the .bsp's nodes at their places (qbsp_tree.cpp
// axialSidesFirst decides the ties under its slanted brushes). Its faces are the ones `light` spreads a Quake 1
// `_surface` template's points over (surface_lights.h); the other Quake 1 faces keep their
// surface trees (worldTree), as this tree moved falloff's floor faces off the compiler's. Grown
// only where the polygons `around` (the templates' faces) are: QbspTree's `around`.
QbspTree quake1WorldTree(const Scene& scene, const std::vector<BrushContents>& contents, const VoidTest& voidTest,
                         std::vector<std::vector<dvec3>> around);

// Quake 2's qbsp makes brush `brush` detail: func_detail, CONTENTS_DETAIL, or translucent
// (SURF_TRANS33/66: qbsp3 ParseBrush).
bool qbspDetail(const Scene& scene, uint32_t brush);

// Which faces brush `brush`'s faces weld with in qbsp's T-junction fix (qbsp_tjunc.h; Welds):
// those of brushes of the same contents, detail only with detail (qbsp3's rule; the bounce's world
// faces take it in every game).
uint32_t weldGroup(const Scene& scene, const std::vector<BrushContents>& contents, uint32_t brush);
// The same in ericw-tools 2.0's Quake 1 qbsp, which gives a liquid the detail bit: detail welds
// with detail whatever the contents (the `_surface` spread's T-junction fix, surface_lights.cpp).
uint32_t quake1WeldGroup(const Scene& scene, const std::vector<BrushContents>& contents, uint32_t brush);

// GLQuake's SubdividePolygon: cut `winding` at multiples of `size` on each axis, the cut
// nearest the middle first, unless it would leave a piece thinner than 8 units. Stops cutting
// at kMaxPiecesPerFace pieces (the rest stays whole), as the 240-texel subdivision of
// compiledFacePolygons does.
std::vector<std::vector<dvec3>> subdivideOnGrid(const std::vector<dvec3>& winding, double size);

// What qbsp makes of one surface (coplanar sides `sides` with one texture projection, of which
// `fragments` survived its CSG), before subdivision: for the world's sides their pieces on the
// nodes of `world` (worldTree), merged on each node; otherwise surfaceTreeFaces.
std::vector<std::vector<dvec3>> compilerFaces(const Scene& scene, const std::vector<uint32_t>& sides,
                                              const std::vector<std::vector<dvec3>>& fragments, const std::vector<BrushContents>& contents,
                                              const QbspTree& world);

// A brush model's surface: a tree grown on that surface alone (qbsp3's choice of split planes
// among the edges of the brushes that reach it), its cells' pieces merged.
std::vector<std::vector<dvec3>> surfaceTreeFaces(const Scene& scene, const std::vector<uint32_t>& sides,
                                                 const std::vector<std::vector<dvec3>>& fragments,
                                                 const std::vector<BrushContents>& contents);

// qbsp's SubdivideFace: Quake 1 faces wider than 240 texels are cut every 224 texels (the
// subdivide size less 16) along each texture axis, from the smallest texel coordinate up, so
// that each one fits the engine's surface cache. ericw-tools `light` sees these pieces.
void subdivideForQbsp(const std::vector<dvec3>& w, const TextureFrame& frame, std::vector<std::vector<dvec3>>& pieces);

} // namespace bt
