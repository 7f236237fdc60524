// Material texture sampling, in two variants chosen at run time from the context:
//   BT_TEXTURES_BINDLESS: GL_ARB_bindless_texture, one sampler2D handle per material map;
//   BT_TEXTURES_ARRAYS:   one sampler2DArray per size class, the material naming (array, layer);
//                         a map may sit in the corner of a larger layer (gl_textures.h).
// Both wrap at the map's own size (GlMaterial's *Texels), never at the layer's.
// Both filter the same way as the CPU reference (bvh sampleBilinearRepeat, renderer/cpu
// bilinearRepeat): bilinear with repeat, texel centres at (i + 0.5) / size, on the stored 8-bit
// values (GL_RGBA8; sRGB decoded after filtering). The four texels are fetched and weighted
// here in fp32 rather than by the sampler, whose filter weights have 8 fractional bits on
// NVIDIA and llvmpipe alike: that would put the GPU image up to ~1 % away from the CPU's.

#include "gl_bindings.glsl"
#if defined(BT_TEXTURES_BINDLESS)
// The program enables GL_ARB_bindless_texture right after #version (extensions come first).

vec4 fetchTexel(uvec2 handle, uint layer, ivec2 texel) { return texelFetch(sampler2D(handle), texel, 0); }
#define MAP_REF uvec2
#define BASE_REF(m) (m).baseHandle, 0u
#define EMISSIVE_REF(m) (m).emissiveHandle, 0u

#elif defined(BT_TEXTURES_ARRAYS)

// Must equal kMaxTextureArrays in renderer/gl/gl_textures.h.
layout(binding = BT_TEXTURE_ARRAYS_UNIT) uniform sampler2DArray textureArrays[BT_MAX_TEXTURE_ARRAYS];

// GLSL 4.50 allows indexing a sampler array only with a dynamically uniform index; neighbouring
// pixels see different materials, so each array is named by a constant in a switch instead.
#define BT_EACH_ARRAY(EXPR) \
  switch (array) { \
  case 0u: return EXPR(textureArrays[0]); case 1u: return EXPR(textureArrays[1]); \
  case 2u: return EXPR(textureArrays[2]); case 3u: return EXPR(textureArrays[3]); \
  case 4u: return EXPR(textureArrays[4]); case 5u: return EXPR(textureArrays[5]); \
  case 6u: return EXPR(textureArrays[6]); case 7u: return EXPR(textureArrays[7]); \
  case 8u: return EXPR(textureArrays[8]); case 9u: return EXPR(textureArrays[9]); \
  case 10u: return EXPR(textureArrays[10]); case 11u: return EXPR(textureArrays[11]); \
  case 12u: return EXPR(textureArrays[12]); case 13u: return EXPR(textureArrays[13]); \
  case 14u: return EXPR(textureArrays[14]); case 15u: return EXPR(textureArrays[15]); \
  }

#define FETCH_FROM(s) texelFetch(s, ivec3(texel, int(layer)), 0)
vec4 fetchTexel(uint array, uint layer, ivec2 texel) {
  BT_EACH_ARRAY(FETCH_FROM)
  return vec4(1.0, 0.0, 1.0, 1.0);
}
#define MAP_REF uint
#define BASE_REF(m) (m).baseArray, (m).baseLayer
#define EMISSIVE_REF(m) (m).emissiveArray, (m).emissiveLayer

#else
#error "define BT_TEXTURES_BINDLESS or BT_TEXTURES_ARRAYS"
#endif

// Bilinear with repeat over the map's `size` texels; uv in texture repeats (s / width,
// t / height), v = 0 at the first row.
vec4 sampleBilinearRepeat(MAP_REF map, uint layer, uvec2 mapTexels, vec2 uv) {
  ivec2 size = max(ivec2(mapTexels), ivec2(1));
  vec2 x = uv * vec2(size) - 0.5;
  vec2 f = floor(x);
  vec2 a = x - f;
  // Wrap the integer texel index (GLSL's % is undefined for negative operands); the two
  // corrections catch the float division's rounding at exact multiples of the size.
  ivec2 i0 = ivec2(f - vec2(size) * floor(f / vec2(size)));
  i0 -= size * ivec2(greaterThanEqual(i0, size));
  i0 += size * ivec2(lessThan(i0, ivec2(0)));
  ivec2 i1 = i0 + 1;
  i1 -= size * ivec2(greaterThanEqual(i1, size));
  // The four texels in a loop, at one call of fetchTexel: on the arrays path each call is a
  // switch over the sampler array, and four calls made the driver compile four of them (per
  // place a texture is read), most of the path tracer's build time on llvmpipe.
  vec4 texels[4]; // (i0.x, i0.y), (i1.x, i0.y), (i0.x, i1.y), (i1.x, i1.y)
  for (int k = 0; k < 4; ++k)
    texels[k] = fetchTexel(map, layer, ivec2((k & 1) == 0 ? i0.x : i1.x, (k & 2) == 0 ? i0.y : i1.y));
  vec4 top = texels[0] * (1.0 - a.x) + texels[1] * a.x;
  vec4 bottom = texels[2] * (1.0 - a.x) + texels[3] * a.x;
  return top * (1.0 - a.y) + bottom * a.y;
}

vec4 sampleBase(GlMaterial m, vec2 uv) { return sampleBilinearRepeat(BASE_REF(m), m.baseTexels, uv); }
vec4 sampleEmissive(GlMaterial m, vec2 uv) { return sampleBilinearRepeat(EMISSIVE_REF(m), m.emissiveTexels, uv); }

// The base colour or the normal map, chosen at run time: a loop over both then reads them at one
// call site (physical mode's surfaces, pathtrace.comp physicalSurface).
const uint MAP_BASE = 0u;
const uint MAP_NORMAL = 1u;
vec4 sampleBaseOrNormal(GlMaterial m, uint map, vec2 uv) {
  uvec2 texels = map == MAP_BASE ? m.baseTexels : m.normalTexels;
#if defined(BT_TEXTURES_BINDLESS)
  return sampleBilinearRepeat(map == MAP_BASE ? m.baseHandle : m.normalHandle, 0u, texels, uv);
#else
  return sampleBilinearRepeat(map == MAP_BASE ? m.baseArray : m.normalArray, map == MAP_BASE ? m.baseLayer : m.normalLayer,
                              texels, uv);
#endif
}
// ... the base colour or the emissive texels, the same way for faithful surfaces (faithfulSurface).
// Its own function, not a third choice in the one above: with that choice in its surface loop the
// physical megakernel lost 6 % of its samples/s (bench/README.md, session 26).
vec4 sampleBaseOrEmissive(GlMaterial m, bool emissive, vec2 uv) {
#if defined(BT_TEXTURES_BINDLESS)
  return sampleBilinearRepeat(emissive ? m.emissiveHandle : m.baseHandle, 0u, emissive ? m.emissiveTexels : m.baseTexels, uv);
#else
  return sampleBilinearRepeat(emissive ? m.emissiveArray : m.baseArray, emissive ? m.emissiveLayer : m.baseLayer,
                              emissive ? m.emissiveTexels : m.baseTexels, uv);
#endif
}

// Texture coordinates of p on face f, in texture repeats: Quake's s/t in texels over the size.
vec2 faceUv(GpuFace f, GlMaterial m, vec3 p) {
  vec3 d = p - f.origin;
  return vec2(dot(d, f.tangent), dot(d, f.bitangent)) / m.size;
}

// The base colour as stored (sRGB-encoded, 0..1; filtered in that encoding like the CPU
// reference), a = coverage; a material without a texture is mid grey.
vec4 materialBaseColor(GlMaterial m, vec2 uv) {
  if ((m.flags & MATERIAL_HAS_BASE) == 0u) return vec4(0.5, 0.5, 0.5, 1.0);
  return sampleBase(m, uv);
}

// Normal maps, as renderer/cpu/integrator.cpp reads them (decodeNormalTexel, normalMapToWorld):
// DarkPlaces' `_norm` convention, red along +s, green up in the image (-t), blue along the face
// normal, a texel t holding 2 t - 1; (0, 0, 0) for a texel with no direction.
vec3 decodeNormalTexel(vec3 texel) {
  vec3 n = 2.0 * texel - 1.0;
  float length2 = dot(n, n);
  return length2 > 1e-8 ? n / sqrt(length2) : vec3(0.0);
}

// `local` in world space on a face with normal n and texture axes s, t (GpuFace tangent and
// bitangent): s's direction, the axis orthogonal to it, the handedness the axes have on the
// face (a mirrored texture mirrors its normal map); the face normal where s runs along it.
vec3 normalMapToWorld(vec3 local, vec3 s, vec3 t, vec3 n) {
  vec3 x = s - n * dot(n, s);
  float length2 = dot(x, x);
  if (!(length2 > 1e-6 * dot(s, s))) return n;
  x /= sqrt(length2);
  float handedness = dot(cross(s, t), n) > 0.0 ? -1.0 : 1.0;
  vec3 y = handedness * cross(n, x);
  return normalize(x * local.x + y * local.y + n * local.z);
}

// trace.glsl's alpha test reads the textures where this file comes first.
#define BT_ALPHA_TEST

vec3 srgbToLinear(vec3 c) {
  return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}
// scene/color.h linearToSrgb: where a liquid is blended as the engine blends, in gamma space.
#include "tonemap_constants.glsl"
vec3 linearToSrgb(vec3 c) {
  return mix(c * BT_SRGB_LINEAR_SLOPE, BT_SRGB_SCALE * pow(c, vec3(1.0 / BT_SRGB_GAMMA)) - BT_SRGB_OFFSET,
             greaterThan(c, vec3(BT_SRGB_LINEAR_LIMIT)));
}

// lighting/liquids.h liquidBlend on a liquid face: (self, behind), the weights of the liquid's
// own colour and of what lies behind it; behind is 0 for an opaque one.
vec2 liquidBlend(uint face) {
  GlMaterial m = materials[faces[face].material];
  if ((m.flags & MATERIAL_BLEND_FILTER) != 0u) return vec2(0.0, 1.0);
  return vec2(m.opacity, (m.flags & MATERIAL_BLEND_ADD) != 0u ? 1.0 : 1.0 - m.opacity);
}

#ifdef BT_QUAKE2_GLASS
// RenderScene::glassAlpha of a face: Quake 2's glass alpha (0.33, 0.66) from its pad word
// (renderer/gl/gl_scene.cpp), 0 for a face that is not glass.
float glassAlpha(uint face) { return uintBitsToFloat(faces[face].pad); }
#endif

// lighting/liquids.h behindWeight: what lies behind weighs, per channel, where the liquid shows
// `surfaceSrgb`; a filter (Quake 3's blendFunc filter) multiplies it by that colour.
vec3 behindWeight(uint face, vec2 blend, vec3 surfaceSrgb) {
  return (materials[faces[face].material].flags & MATERIAL_BLEND_FILTER) != 0u ? surfaceSrgb : vec3(blend.y);
}
