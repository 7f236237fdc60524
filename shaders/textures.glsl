// Material texture sampling, in two variants chosen at run time from the context:
//   BT_TEXTURES_BINDLESS: GL_ARB_bindless_texture, one sampler2D handle per material map;
//   BT_TEXTURES_ARRAYS:   one sampler2DArray per size class, the material naming (array, layer).
// Both sample with GL_LINEAR at level 0 and GL_REPEAT, which is bilinear filtering with repeat
// as the CPU reference does (sampleBilinearRepeat): texel centres at (i + 0.5) / size.
// Compute shaders have no derivatives, so no mip level is picked implicitly; level 0 keeps both
// backends exact. The textures still carry mipmaps for the viewer's ray cones.

#if defined(BT_TEXTURES_BINDLESS)
// The program enables GL_ARB_bindless_texture right after #version (extensions come first).

vec4 sampleBase(GpuMaterial m, vec2 uv) { return textureLod(sampler2D(m.baseHandle), uv, 0.0); }
vec4 sampleNormalMap(GpuMaterial m, vec2 uv) { return textureLod(sampler2D(m.normalHandle), uv, 0.0); }

#elif defined(BT_TEXTURES_ARRAYS)

// Must equal kMaxTextureArrays in renderer/gl/gl_textures.h.
#define BT_MAX_TEXTURE_ARRAYS 16
layout(binding = 0) uniform sampler2DArray textureArrays[BT_MAX_TEXTURE_ARRAYS];

// GLSL 4.50 allows indexing a sampler array only with a dynamically uniform index; neighbouring
// pixels see different materials, so each array is named by a constant in a switch instead.
vec4 sampleArray(uint array, uint layer, vec2 uv) {
  vec3 p = vec3(uv, float(layer));
  switch (array) {
  case 0u: return textureLod(textureArrays[0], p, 0.0);
  case 1u: return textureLod(textureArrays[1], p, 0.0);
  case 2u: return textureLod(textureArrays[2], p, 0.0);
  case 3u: return textureLod(textureArrays[3], p, 0.0);
  case 4u: return textureLod(textureArrays[4], p, 0.0);
  case 5u: return textureLod(textureArrays[5], p, 0.0);
  case 6u: return textureLod(textureArrays[6], p, 0.0);
  case 7u: return textureLod(textureArrays[7], p, 0.0);
  case 8u: return textureLod(textureArrays[8], p, 0.0);
  case 9u: return textureLod(textureArrays[9], p, 0.0);
  case 10u: return textureLod(textureArrays[10], p, 0.0);
  case 11u: return textureLod(textureArrays[11], p, 0.0);
  case 12u: return textureLod(textureArrays[12], p, 0.0);
  case 13u: return textureLod(textureArrays[13], p, 0.0);
  case 14u: return textureLod(textureArrays[14], p, 0.0);
  case 15u: return textureLod(textureArrays[15], p, 0.0);
  }
  return vec4(1.0, 0.0, 1.0, 1.0);
}

vec4 sampleBase(GpuMaterial m, vec2 uv) { return sampleArray(m.baseArray, m.baseLayer, uv); }
vec4 sampleNormalMap(GpuMaterial m, vec2 uv) { return sampleArray(m.normalArray, m.normalLayer, uv); }

#else
#error "define BT_TEXTURES_BINDLESS or BT_TEXTURES_ARRAYS"
#endif

// Texture coordinates of p on face f, in texture repeats: Quake's s/t in texels over the size.
vec2 faceUv(GpuFace f, GpuMaterial m, vec3 p) {
  vec3 d = p - f.origin;
  return vec2(dot(d, f.tangent), dot(d, f.bitangent)) / m.size;
}

// Linear base colour (the textures are GL_SRGB8_ALPHA8, so the sampler decodes before
// filtering); a material without a texture is mid grey.
vec4 materialBaseColor(GpuMaterial m, vec2 uv) {
  if ((m.flags & MATERIAL_HAS_BASE) == 0u) return vec4(0.5, 0.5, 0.5, 1.0);
  return sampleBase(m, uv);
}
