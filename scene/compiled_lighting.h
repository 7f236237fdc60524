// The lighting a compiler baked into a .bsp, kept beside the Scene so that a view mode can show
// it next to the path-traced preview. Only .bsp imports have it (Scene::compiledLighting).
#pragma once

#include "scene/material.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bt {

// One compiled (drawn) face of a Q1/HL/Q2 level with its lightmaps.
struct LightmappedFace {
  uint32_t entity = 0;             // Scene::entities index of the entity whose model holds it
  std::vector<glm::dvec3> polygon; // world space (entity origin applied), counter-clockwise seen from the front
  glm::dvec3 normal{0.0, 0.0, 1.0};
  std::string texture;
  // The face's texture projection (texinfo, origin applied): texel s = dot(p, sAxis) + sOffset.
  glm::dvec3 sAxis{1.0, 0.0, 0.0}, tAxis{0.0, 1.0, 0.0};
  double sOffset = 0.0, tOffset = 0.0;
  // Quake's luxel grid: luxel (x, y) is centred on texel (luxelSize * (lightmapMins[0] + x),
  // luxelSize * (lightmapMins[1] + y)); width/height 0 when the face has no lightmap (sky,
  // liquids, unlit faces).
  std::array<int, 2> lightmapMins{0, 0};
  int width = 0;
  int height = 0;
  // Texels per luxel: 16, or 1 << shift with the BSPX LMSHIFT lump; 0 when the BSPX
  // DECOUPLED_LM lump places the luxels independently of the texture (lightmapMins unused).
  int luxelSize = 16;
  // Where luxels lie, whatever the layout: luxel (x, y) is centred on the point p of the face
  // where dot(p, luxelS) + luxelSOffset == x and dot(p, luxelT) + luxelTOffset == y (origin
  // applied). For Quake's grid that is sAxis / luxelSize and sOffset / luxelSize - lightmapMins[0].
  glm::dvec3 luxelS{1.0 / 16.0, 0.0, 0.0}, luxelT{0.0, 1.0 / 16.0, 0.0};
  double luxelSOffset = 0.0, luxelTOffset = 0.0;
  // Quake 3: the draw surface's triangles, three indices into `polygon` each (q3map2's planar
  // surfaces need not be convex); empty for Q1/HL/Q2, whose polygon is convex.
  std::vector<uint32_t> triangles;
  // Quake 1 / Hexen II / Half-Life: ericw-tools `light` spreads a `_surface` template's points
  // (the Q1 kind) over this face. Its MakeSurfaceLights walks the leaves' face lists and skips a
  // liquid's face in a leaf that is not empty (the liquid's underwater side), so a face no leaf
  // lists, or a liquid's face that only leaves in liquid list, gets none. False for Quake 2 / 3.
  bool takesSurfaceLights = false;
  std::array<uint8_t, 4> styles{255, 255, 255, 255}; // light styles in order, 255 = unused
  // For each used style in order, width * height RGB triples, rows top (t min) to bottom.
  // Values as stored: the light sum x 0.5 (_range), clamped to 255; grey levels are repeated
  // into R, G and B when the file has no colour.
  std::vector<uint8_t> rgb;
};

struct CompiledLighting {
  // Where the colours came from: "lighting lump" (Quake's 8-bit grey), ".lit file",
  // "BSPX RGBLIGHTING", "RGB lighting lump" (Half-Life, Quake 2), "lightmap pages" (Quake 3).
  std::string source;
  // The engine that shows these lightmaps: "quake", "hexen2" (Hexen II's 80-byte models),
  // "halflife", "quake2" or "quake3", from the file's version (lighting/compiled_lightmaps.h).
  std::string engine = "quake";
  // "16 texels per luxel", "per-face luxel size (BSPX LMSHIFT)" or "decoupled (BSPX DECOUPLED_LM)".
  std::string layout = "16 texels per luxel";
  int luxelSize = 16; // texels per luxel of faces that do not say otherwise
  std::vector<LightmappedFace> faces;
  // Quake 3 keeps its lightmaps as 128x128 RGB pages that draw vertices index; the pages are kept
  // here (alpha 255), and each planar draw surface's block of its page is one of `faces` (its
  // luxels copied out, luxel (x, y) the block's texel (x, y)). Patches and triangle soups,
  // vertex-lit surfaces and the light grid are not read yet.
  std::vector<Image> pages;
};

} // namespace bt
