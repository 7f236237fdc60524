// The sky as renderer/cpu/sky.cpp draws it (QuakeSpasm, Quake/gl_sky.c): a sky face shows the
// level's sky box, else Quake's two layers (MATERIAL_SKY_LAYERS), by the ray's direction, else
// its texture mapped on the face. Comes after scene_buffers.glsl and textures.glsl.
#include "sky_constants.glsl"

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
// then Sky_EmitSkyBoxVertex's [-1, 1] to [0, 1], its half-texel inset and its flip of t.
vec2 skyBoxUv(uint side, vec3 d, uvec2 texels) {
  vec3 b = vec3(0.0);
  for (int j = 0; j < 3; ++j) {
    int k = SKY_ST_TO_VEC[side * 3u + uint(j)];
    b[abs(k) - 1] = k < 0 ? -d[j] : d[j];
  }
  vec2 size = vec2(max(texels, uvec2(1u)));
  vec2 st = (b.xy / b.z + 1.0) * 0.5;
  st = st * (size - 1.0) / size + 0.5 / size;
  return vec2(st.x, 1.0 - st.y);
}


// What a face shows along dir: the material and coordinates to sample, and whether they are
// Quake's two sky layers (sampleBaseOrNormal's skyLayers).
struct FaceView {
  GlMaterial m;
  vec2 uv;
  bool skyLayers;
};

// `flags`: the face's faceFlags.
FaceView faceView(uint face, uint flags, vec3 p, vec3 dir) {
  GpuFace f = faces[face];
  GlMaterial m = materials[f.material];
  bool sky = (flags & FACE_SKY) != 0u;
  if (sky && world.skyBoxMaterial != BT_NO_SKY_BOX) {
    uint side = skyBoxSide(dir);
    GlMaterial image = materials[world.skyBoxMaterial + SKY_TEX_ORDER[side]];
    return FaceView(image, skyBoxUv(side, dir, image.baseTexels), false);
  }
  if (sky && (m.flags & MATERIAL_SKY_LAYERS) != 0u) return FaceView(m, skyLayerUv(dir), true);
  return FaceView(m, faceUv(f, m, p), false);
}

// The colour a ray along dir sees at p on face (renderer/cpu baseOrSkyColor), sRGB-encoded as
// stored, a = coverage: the sky, else the base colour. One call site of the sampling code for
// both layers (textures.glsl explains why that matters).
vec4 baseOrSkyColor(uint face, vec3 p, vec3 dir) {
  FaceView view = faceView(face, faceFlags[face], p, dir);
  if ((view.m.flags & MATERIAL_HAS_BASE) == 0u) return vec4(0.5, 0.5, 0.5, 1.0);
  vec4 color = vec4(0.0);
  for (uint map = MAP_BASE; map <= (view.skyLayers ? MAP_NORMAL : MAP_BASE); ++map) {
    vec4 texel = sampleBaseOrNormal(view.m, map, view.uv, view.skyLayers);
    // The clear texels are black: the filtered front colour is already weighted by its alpha.
    color = map == MAP_BASE ? texel : vec4(texel.rgb + color.rgb * (1.0 - texel.a), 1.0);
  }
  return color;
}
