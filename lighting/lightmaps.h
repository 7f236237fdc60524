// Faithful mode as the game shows it: ericw-tools `light` computes the light once per luxel of
// each compiled face, and the engine shows those luxels filtered bilinearly across the face
// (GLQuake, QuakeSpasm). `Lightmaps` holds them in the layout both tracers read
// (scene/gpu_structs.h, GpuLightmapFragment); lightmap_bake.h fills it.
#pragma once

#include "lighting/luxel_display.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace bt {

// Texels per luxel: Quake's lightmaps, and the luxel grid ericw-tools `light` samples by default.
inline constexpr int kLuxelTexels = 16;

struct Lightmaps {
  std::vector<glm::uvec2> faceRanges; // per scene face: (first fragment, count); count 0 = not baked
  std::vector<GpuLightmapFragment> fragments;
  std::vector<glm::vec4> edges;             // (a, b, c, 0): a s + b t + c >= 0 inside the fragment
  std::vector<uint32_t> luxels;             // RGBA8, r in the low byte
  std::vector<std::vector<dvec3>> polygons; // per fragment: its world-space polygon (for the bake)
  std::vector<uint32_t> fragmentFace;       // per fragment: its scene face
  // What the engine draws: texture × luxel × displayScale, in the texture's (gamma) space.
  // Faithful luxels hold the stored value and Quake's overbright shows 128 as the texture's own
  // colour; a compiled view's luxels hold what its engine uploads (compiled_lightmaps.h).
  float displayScale = 1.0f / 128.0f;
  // What the engine makes of each luxel before filtering it (Half-Life's light gamma table).
  LuxelDisplay luxelDisplay = BT_LUXEL_DISPLAY_IDENTITY;

  bool empty() const { return fragments.empty(); }
  bool baked(uint32_t face) const { return face < faceRanges.size() && faceRanges[face].y > 0; }
};

// The fragment of `face` that shows texel point st: the one whose edges hold it, else the one it
// lies least outside of (the largest of its violated edge distances, smallest over fragments).
uint32_t lightmapFragmentAt(const Lightmaps& lightmaps, uint32_t face, const glm::vec2& st);

// The lightmap value (0..255 per channel) the engine shows at texel point st of `face`: its
// fragment's luxels (light × _range, as the compiler stores them) through luxelDisplay, filtered
// bilinearly with the edge luxels repeated outward; nullopt when `face` has no baked lightmap.
std::optional<glm::vec3> lightmapValue(const Lightmaps& lightmaps, uint32_t face, const glm::vec2& st);

// The single uint buffer the GL tracer reads (layout in scene/gpu_structs.h); a header with no
// face for empty lightmaps. Beyond scene/gpu_structs.h's layout, word [5] is the first word of
// GoldSrc's luxel table (BT_LUXEL_TABLE_SIZE floats, lighting/luxel_display.h), which always
// follows the luxels (the view at each pixel's point reads it too, baked luxels or not), and
// word [6] is luxelDisplay.
std::vector<uint32_t> packLightmaps(const Lightmaps& lightmaps);

inline uint32_t packLuxel(const glm::vec3& stored) {
  auto byte = [](float v) { return uint32_t(v < 0.0f ? 0.0f : v > 255.0f ? 255.0f : v); };
  return byte(stored.x) | byte(stored.y) << 8 | byte(stored.z) << 16 | 255u << 24;
}
inline glm::vec3 unpackLuxel(uint32_t v) {
  return {float(v & 255u), float((v >> 8) & 255u), float((v >> 16) & 255u)};
}

} // namespace bt
