// Compiled lightmaps: the lighting lump (with a .lit file or BSPX RGBLIGHTING for colour) cut
// into per-face luxel grids, the way Quake engines find them.
#pragma once

#include "importers/bsp/bsp_file.h"
#include "scene/compiled_lighting.h"
#include "scene/diagnostics.h"

#include <optional>
#include <vector>

namespace bt::bsp {

// Where a brush entity's model is drawn.
struct ModelPlacement {
  size_t model = 0;
  uint32_t entity = 0;
  glm::dvec3 origin{0.0};
};

// Quake's lightmap extents of a Q1/HL/Q2 face (CalcSurfaceExtents): the texel bounds of its
// vertices, in whole luxels of `luxelSize` texels (16, or 1 << shift with BSPX LMSHIFT).
struct LightmapExtents {
  std::array<int, 2> mins{0, 0}; // floor(min / luxelSize)
  int width = 0;                 // ceil(max / luxelSize) - mins + 1; 0 when the face has none
  int height = 0;
};
LightmapExtents lightmapExtents(const BspFile& bsp, size_t face, int luxelSize = 16);

// The lightmaps of every face of the placed models. `litFile` is the content of a .lit file
// beside the level, if any ("QLIT", version 1, RGB for every byte of the lighting lump); it wins
// over BSPX RGBLIGHTING, which wins over the grey lump. Luxels lie on Quake's 16-texel grid,
// on a per-face grid of 1 << shift texels with BSPX LMSHIFT (one byte per face), or where BSPX
// DECOUPLED_LM's per-face world-to-luxel projection puts them (it wins over LMSHIFT). Faces whose
// lightmap does not fit in the data, or whose BSPX record is unusable, are kept without one and
// counted in a single warning each; a BSPX lump of the wrong size is ignored with a warning.
CompiledLighting readCompiledLighting(const BspFile& bsp, const std::vector<ModelPlacement>& placements,
                                      const std::optional<std::vector<uint8_t>>& litFile, Diagnostics& diagnostics);

} // namespace bt::bsp
