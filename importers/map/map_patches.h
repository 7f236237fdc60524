// Quake 3 curves in .map files. The parser keeps patchDef2/patchDef3 blocks verbatim (so that
// `convert` writes them back unchanged); the scene builder reads their control grids from that
// text with these functions.
//
//   patchDef2 { TEXTURE ( W H 0 0 0 ) ( ( ( x y z s t ) ... H points ) ... W columns ) }
//   patchDef3 { TEXTURE ( W H subdivX subdivY 0 0 0 ) ( ... the same ... ) }
//
// Column j, point i is control point (row i, column j), as q3map2's ParsePatch stores it; s and
// t are in texture units (0..1 across the image).
#pragma once

#include "scene/curves.h"

#include <optional>
#include <string>
#include <string_view>

namespace bt::map {

struct MapPatch {
  std::string texture;
  PatchGrid control;  // st in texture units
  int lineOffset = 0; // lines from the block's keyword to where a problem was found
};

// Whether a verbatim block is a patch (its keyword is patchDef2 or patchDef3).
bool isPatchBlock(std::string_view verbatim);

// The patch a verbatim block holds, or the reason it cannot be read (`error`, with lineOffset
// set to where the reader stopped). The grid is not checked for tessellation here.
std::optional<MapPatch> parsePatchBlock(std::string_view verbatim, std::string& error, int& lineOffset);

} // namespace bt::map
