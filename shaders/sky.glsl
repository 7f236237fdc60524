// The sky as renderer/cpu/sky.cpp draws it (QuakeSpasm, Quake/gl_sky.c; ioquake3 tr_sky.c): a
// sky face of a level with sky images (world.skyKind) shows them by the ray's direction, the
// same on every sky face, whatever point of it the ray meets. Comes after scene_buffers.glsl and
// textures.glsl.
//
// A path that meets such a face is handed to skyColor once, where the hit is read
// (pathtrace.comp advance), as a miss would be: the surface shading and the texture loop that
// every other hit runs hold no sky code, so levels without sky pay nothing for it.
#include "sky_constants.glsl"

const uint SKY_NONE = BT_SKY_NONE;
const uint SKY_QUAKE_LAYERS = BT_SKY_QUAKE_LAYERS;
const uint SKY_BOX_CLAMPED = BT_SKY_BOX_CLAMPED;

// Sky_GetTexCoord at time 0: repeats of a 128x128 layer seen along dir (from the eye).
vec2 skyLayerUv(vec3 dir) {
  vec3 flattened = vec3(dir.xy, dir.z * BT_SKY_FLATTEN);
  float len = length(flattened);
  if (!(len > 0.0)) return vec2(0.0);
  return flattened.xy * (BT_SKY_RADIUS / len) / BT_SKY_LAYER_SCALE;
}

const int SKY_ST_TO_VEC[18] = int[18](BT_SKY_ST_TO_VEC);
const uint SKY_TEX_ORDER[6] = uint[6](BT_SKY_TEX_ORDER);

// Sky_ProjectPoly's side for a direction (its ties included): +x, -x, +y, -y, +z, -z.
uint skyBoxSide(vec3 d) {
  vec3 a = abs(d);
  if (a.x > a.y && a.x > a.z) return d.x < 0.0 ? 1u : 0u;
  if (a.y > a.z && a.y > a.x) return d.y < 0.0 ? 3u : 2u;
  return d.z < 0.0 ? 5u : 4u;
}

// Where dir meets the side's image, in repeats (sky.cpp skyBoxUv): st_to_vec turned around,
// then [-1, 1] to [0, 1], pulled in by half a texel (Sky_EmitSkyBoxVertex) or clamped to the
// edge texels' centres (Quake 3's clamp to edge), and t flipped.
vec2 skyBoxUv(uint side, vec3 d, uvec2 texels, bool clamped) {
  vec3 b = vec3(0.0);
  for (int j = 0; j < 3; ++j) {
    int k = SKY_ST_TO_VEC[side * 3u + uint(j)];
    b[abs(k) - 1] = k < 0 ? -d[j] : d[j];
  }
  vec2 size = vec2(max(texels, uvec2(1u)));
  vec2 st = (b.xy / b.z + 1.0) * 0.5;
  st = clamped ? clamp(st, 0.5 / size, 1.0 - 0.5 / size) : st * (size - 1.0) / size + 0.5 / size;
  return vec2(st.x, 1.0 - st.y);
}

// The level's sky seen along dir, sRGB-encoded as stored: Quake's front layer over its back
// layer (the clear texels are black, so the filtered front is already weighted by its alpha),
// or the sky box's side. One call site of the sampling code for every layer (textures.glsl).
vec3 skyColor(vec3 dir) {
  bool layers = world.skyKind == SKY_QUAKE_LAYERS;
  uint side = skyBoxSide(dir);
  vec3 color = vec3(0.0);
  for (uint layer = 0u; layer < (layers ? 2u : 1u); ++layer) {
    GlMaterial m = materials[world.skyMaterial + (layers ? layer : SKY_TEX_ORDER[side])];
    vec2 uv = layers ? skyLayerUv(dir) : skyBoxUv(side, dir, m.baseTexels, world.skyKind == SKY_BOX_CLAMPED);
    vec4 texel = sampleBase(m, uv);
    color = texel.rgb + color * (1.0 - texel.a);
  }
  return color;
}
