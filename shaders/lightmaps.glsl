// Faithful mode's baked luxels (lighting/lightmaps.h lightmapValue, the CPU reference): the
// stored lightmap value at a texel point of a face, filtered bilinearly as the engine filters its
// lightmaps. Layout of the packed buffer: scene/gpu_structs.h (GpuLightmapFragment).
#include "gl_bindings.glsl"
#include "luxel_display_constants.glsl"
layout(std430, binding = BT_BINDING_LIGHTMAPS) readonly buffer Lightmaps { uint lightmapData[]; };

// (first fragment, count) of face `face`; count 0: not baked.
uvec2 lightmapRange(uint face) {
  if (face >= lightmapData[3]) return uvec2(0u);
  return uvec2(lightmapData[8u + 2u * face], lightmapData[9u + 2u * face]);
}

// shown = texture × luxel × this (lighting/lightmaps.h Lightmaps::displayScale).
float lightmapDisplayScale() { return uintBitsToFloat(lightmapData[4]); }

// The fragment holding st, else the one st lies least outside of (lightmapFragmentAt).
uint lightmapFragmentAt(uvec2 range, vec2 st) {
  uint best = range.x;
  float bestOutside = -1e30;
  for (uint f = range.x; f < range.x + range.y; ++f) {
    uint at = lightmapData[0] + 16u * f;
    uint firstEdge = lightmapData[at + 5u], edgeCount = lightmapData[at + 6u];
    float inside = 1e30;
    for (uint e = firstEdge; e < firstEdge + edgeCount; ++e) {
      uint ea = lightmapData[1] + 4u * e;
      vec3 l = uintBitsToFloat(uvec3(lightmapData[ea], lightmapData[ea + 1u], lightmapData[ea + 2u]));
      inside = min(inside, l.x * st.x + l.y * st.y + l.z);
    }
    if (inside >= 0.0) return f;
    if (inside > bestOutside) {
      bestOutside = inside;
      best = f;
    }
  }
  return best;
}

vec3 unpackLuxel(uint v) { return vec3(float(v & 255u), float((v >> 8) & 255u), float((v >> 16) & 255u)); }

// lighting/luxel_display.cpp shownLuxel: the luxel the engine draws for a stored value, read from
// the table the C++ built (packLightmaps puts it after the luxels).
float shownLuxel(uint display, float stored) {
  if (display != BT_LUXEL_DISPLAY_GOLDSRC) return stored;
  float s = clamp(stored, 0.0, float(BT_LUXEL_TABLE_SIZE - 1));
  int i = min(int(s), BT_LUXEL_TABLE_SIZE - 2);
  float w = s - float(i);
  uint at = lightmapData[5] + uint(i);
  return uintBitsToFloat(lightmapData[at]) * (1.0 - w) + uintBitsToFloat(lightmapData[at + 1u]) * w;
}
// The channels in a loop: each call of the table read is a copy for the driver's back end to
// compile, and three per luxel made the lightmap's part a sixth of the faithful shade kernel.
vec3 shownLuxel(uint display, vec3 stored) {
  vec3 shown;
  for (int c = 0; c < 3; ++c) shown[c] = shownLuxel(display, stored[c]);
  return shown;
}
vec3 shownLuxel(uint v) { return shownLuxel(lightmapData[6], unpackLuxel(v)); }

// The luxel value (0..255 per channel, through the engine's luxel display) shown at texel point st
// of a face with `range`.
vec3 lightmapValue(uvec2 range, vec2 st) {
  uint at = lightmapData[0] + 16u * lightmapFragmentAt(range, st);
  int minS = int(lightmapData[at]), minT = int(lightmapData[at + 1u]);
  int width = int(lightmapData[at + 2u]), height = int(lightmapData[at + 3u]);
  uint firstLuxel = lightmapData[2] + lightmapData[at + 4u];
  vec3 luxelU = uintBitsToFloat(uvec3(lightmapData[at + 8u], lightmapData[at + 9u], lightmapData[at + 10u]));
  vec3 luxelV = uintBitsToFloat(uvec3(lightmapData[at + 12u], lightmapData[at + 13u], lightmapData[at + 14u]));
  // Written as the CPU writes it (a s + b t + c, left to right) so that both round alike.
  float u = luxelU.x * st.x + luxelU.y * st.y + luxelU.z - float(minS);
  float v = luxelV.x * st.x + luxelV.y * st.y + luxelV.z - float(minT);
  float fu = floor(u), fv = floor(v);
  float wu = u - fu, wv = v - fv;
  int x0 = clamp(int(fu), 0, width - 1), x1 = clamp(int(fu) + 1, 0, width - 1);
  int y0 = clamp(int(fv), 0, height - 1), y1 = clamp(int(fv) + 1, 0, height - 1);
  // The four luxels in a loop, at one call of shownLuxel (as the channels above).
  vec3 luxels[4]; // (x0, y0), (x1, y0), (x0, y1), (x1, y1)
  for (int k = 0; k < 4; ++k)
    luxels[k] = shownLuxel(lightmapData[firstLuxel + uint(((k & 2) == 0 ? y0 : y1) * width + ((k & 1) == 0 ? x0 : x1))]);
  vec3 top = luxels[0] * (1.0 - wu) + luxels[1] * wu;
  vec3 bottom = luxels[2] * (1.0 - wu) + luxels[3] * wu;
  return top * (1.0 - wv) + bottom * wv;
}
