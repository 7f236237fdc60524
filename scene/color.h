// sRGB transfer functions, for texels (stored sRGB-encoded) and for displays; the encoding's
// constants are shared with the shaders.
#pragma once

#include "shaders/tonemap_constants.glsl" // BT_SRGB_*: shared with shaders/tonemap.comp

#include <glm/vec3.hpp>

#include <cmath>

namespace bt {

inline float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
inline float linearToSrgb(float c) {
  return c <= BT_SRGB_LINEAR_LIMIT ? c * BT_SRGB_LINEAR_SLOPE : BT_SRGB_SCALE * std::pow(c, 1.0f / BT_SRGB_GAMMA) - BT_SRGB_OFFSET;
}
inline glm::vec3 srgbToLinear(const glm::vec3& c) {
  return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)};
}
inline glm::vec3 linearToSrgb(const glm::vec3& c) {
  return {linearToSrgb(c.x), linearToSrgb(c.y), linearToSrgb(c.z)};
}

} // namespace bt
