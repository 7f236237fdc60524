// Brushes from compiled BSP files: what the tracer intersects.
//
//  - Quake 2 / Quake 3: the brushes and brush sides lumps hold the mapper's brushes directly.
//  - Quake 1 / Half-Life with ericw-tools' BSPX BRUSHLIST lump (qbsp -wrbrushes): from it.
//  - Quake 1 / Half-Life otherwise: every non-empty leaf of hull 0 is a convex cell bounded by
//    the planes on its path from the root; those cells are the brushes (what a decompiler does,
//    cf. ericw-tools' bsputil --decompile). They are fragments of the original brushes, not the
//    brushes themselves, but they fill exactly the same space.
//
// Every side gets the texture frame of the compiled surface lying on it; sides no surface lies
// on (buried against other brushes, or facing the void) get a "skip" texture like the
// decompiler gives them, and a paraxial frame.
#pragma once

#include "importers/bsp/bsp_file.h"
#include "scene/winding.h"

#include <optional>
#include <string>
#include <vector>

namespace bt::bsp {

struct CompiledSide {
  Plane plane;     // outward
  Winding winding; // counter-clockwise seen from outside
  std::string texture;
  TextureFrame frame;
  // Quake 3 frames come from draw vertices' st, which count texture widths rather than texels;
  // scaleFrameToTexels() turns them into texels once the texture's size is known.
  bool frameInTextureUnits = false;
  bool hasSurface = false; // a compiled face/draw surface lies on this side
  std::optional<SurfaceAttributes> surface;
};

struct CompiledBrush {
  std::vector<CompiledSide> sides;
  int32_t contents = 0; // Q1 CONTENTS_* or Q2/Q3 contents bits
};

// False for a brush thinner than the on-plane epsilon (0.01 units) behind one of its sides: a
// corrupt tree or brush lump can name two planes that close to each other, face to face, and
// clipping, which counts such distances as "on the plane", then keeps both as sides of a sliver
// that has no inside to trace.
bool hasVolume(const CompiledBrush& brush);

// Q1/HL: convex cells of hull 0 of `model` (non-empty leafs).
std::vector<CompiledBrush> hullBrushes(const BspFile& bsp, size_t model);

// Q1/HL: the brushes of `model` from a BSPX BRUSHLIST lump; nullopt when the lump does not list
// that model. Throws ImportError when the lump is malformed.
std::optional<std::vector<CompiledBrush>> brushListBrushes(const BspFile& bsp, size_t model);

// Q2: the brushes reachable from `model`'s node tree.
std::vector<CompiledBrush> quake2Brushes(const BspFile& bsp, size_t model);

// Q3: the brushes of `model`; frames from the draw surfaces lying on each side.
std::vector<CompiledBrush> quake3Brushes(const BspFile& bsp, size_t model);

// Quake's paraxial texture frame (the .map "standard" base axes at scale 1, no offset).
TextureFrame paraxialFrame(const Plane& plane);

// The frame of Q1/Q2 texinfo on `plane`: tangent/bitangent are vecs[0]/vecs[1].xyz, the origin
// is the point of the plane where both texel coordinates are 0.
TextureFrame texinfoFrame(const TexInfo& texinfo, const Plane& plane);

} // namespace bt::bsp
