// Half-Life's display of lightmaps: GoldSrc passes each luxel through its light gamma table
// before uploading it (Xash3D FWGS, the open re-implementation of GoldSrc: engine/client/gamma.c
// BuildGammaTable, ref/gl/gl_rsurf.c R_BuildLightMap with `gl_overbright 0`, GoldSrc's look
// before the 2013 overbright option). For a luxel stored b in styles summing to bl = Σ b × style:
//   t = min(1023, bl × lightscale >> 14), lightscale = round(2^(1 / lightgamma) × 256) = 338
//   f = (t / 1023)^lightgamma, moved by `brightness` (a linear ramp below g3 = 0.125 at 0)
//   uploaded = int(1023 × f^(1 / gamma)) >> 2
// At the defaults (gamma = lightgamma = 2.5, brightness 0) the curve is the identity to a step, so
// what brightens the picture is lightscale and style 'm': stored × 264 × 338 / 2^16 = × 1.36.
// Both tracers read the one table built here: the CPU directly, the GL tracer from the lightmap
// buffer (packLightmaps), so they agree to the bit.
#pragma once

#include "shaders/luxel_display_constants.glsl"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>

namespace bt {

// BT_LUXEL_DISPLAY_IDENTITY or BT_LUXEL_DISPLAY_GOLDSRC.
using LuxelDisplay = uint32_t;

// What GoldSrc uploads for a luxel stored b (0..255) in a style at 'm' (style 0).
const std::array<float, BT_LUXEL_TABLE_SIZE>& goldSrcLuxelTable();

// GoldSrc's table for the given cvars (the defaults above are what the views use; tests build
// others to see that the choice shows).
std::array<float, BT_LUXEL_TABLE_SIZE> buildGoldSrcLuxelTable(float gamma, float lightgamma, float brightness);

// The luxel the engine draws for a stored value: per byte for baked luxels; a stored value
// between two bytes (faithful light at a pixel's own point) reads the table linearly between them.
float shownLuxel(LuxelDisplay display, float stored);
glm::vec3 shownLuxel(LuxelDisplay display, const glm::vec3& stored);

} // namespace bt
