// std430 mirrors of scene/gpu_structs.h and renderer/gl/gl_structs.h. Keep both sides in step:
// the C++ headers have static_asserts on every size and offset below.

// The BVH as trace.glsl reads it, through buffer textures (scene_buffers.glsl), 16 bytes per
// texel. The nodes are renderer/gl/gl_structs.h GlBvhNode, made from TraceScene's tree at
// upload; 4 texels each (trace.glsl nodeRow):
//   struct GlBvhNode {
//     vec3 leftMin;  uint left;   // offset 0, 12: a child reference (trace.glsl LEAF_REF)
//     vec3 leftMax;  uint pad0;   // offset 16, 28
//     vec3 rightMin; uint right;  // offset 32, 44
//     vec3 rightMax; uint pad1;   // offset 48, 60
//   };                            // 64 bytes
// The brushes are bvh/trace_scene.h's TraceScene::brushes() unchanged, scene/gpu_structs.h
// GpuBrush, 4 texels each (trace.glsl brushRow):
//   struct GpuBrush {
//     vec3 boundsMin;     // offset 0
//     uint firstSide;     // offset 12: sides[firstSide .. firstSide + sideCount) are the slanted faces
//     vec3 boundsMax;     // offset 16
//     uint sideCount;     // offset 28
//     uint axialFace[6];  // offset 32: the face on each box side -X, +X, -Y, +Y, -Z, +Z, or NO_FACE
//     uint sceneBrush;    // offset 56
//     uint pad;           // offset 60
//   };                    // 64 bytes

// One brush side, faces[i] = Scene::faces[i]: plane.xyz the outward normal, plane.w the
// distance (dot(normal, p) == dist on it); texture frame s = dot(p - origin, tangent),
// t = dot(p - origin, bitangent), in texels.
#include "scene_constants.glsl"
struct GpuFace {
  vec4 plane;       // offset 0
  vec3 origin;      // offset 16
  uint material;    // offset 28
  vec3 tangent;     // offset 32
  uint brush;       // offset 44
  vec3 bitangent;   // offset 48
  uint pad;         // offset 60: a Quake 2 glass face's alpha as a float's bits, else 0 (textures.glsl glassAlpha)
};                  // 64 bytes

// faceFlags[] (RenderScene::faceFlags): the face classes of scene/gpu_structs.h kFace*.
const uint FACE_HIDDEN = BT_FACE_HIDDEN;
const uint FACE_SKY = BT_FACE_SKY;
const uint FACE_LIQUID = BT_FACE_LIQUID;
const uint FACE_NO_SHADOW = BT_FACE_NO_SHADOW;
const uint FACE_EMISSIVE = BT_FACE_EMISSIVE;
const uint FACE_MASKED = BT_FACE_MASKED;
const uint FACE_MASK_GT0 = BT_FACE_MASK_GT0;
const uint FACE_MASK_LT128 = BT_FACE_MASK_LT128;
const uint FACE_CLASS_BITS = BT_FACE_CLASS_BITS;
const uint FACE_CHANNEL_SHIFT = BT_FACE_CHANNEL_SHIFT;
const uint FACE_CHANNEL_BITS = BT_FACE_CHANNEL_BITS;
const uint FACE_ANY_CHANNEL = BT_FACE_ANY_CHANNEL;
const uint DEFAULT_CHANNELS = 1u; // scene/gpu_structs.h kDefaultChannels

const uint MATERIAL_HAS_BASE = BT_GL_MATERIAL_HAS_BASE;
const uint MATERIAL_HAS_NORMAL = BT_GL_MATERIAL_HAS_NORMAL;
const uint MATERIAL_HAS_EMISSIVE = BT_GL_MATERIAL_HAS_EMISSIVE;
const uint MATERIAL_SPECULAR = BT_GL_MATERIAL_GGX;
const uint MATERIAL_BLEND_ADD = BT_GL_MATERIAL_BLEND_ADD;
const uint MATERIAL_BLEND_FILTER = BT_GL_MATERIAL_BLEND_FILTER;

// Texture references for both paths (bindless handles, or (array, layer) in the texture
// arrays) and the shading parameters of renderer/cpu's GpuMaterial.
struct GlMaterial {
  uvec2 baseHandle;     // offset 0
  uvec2 normalHandle;   // offset 8
  uvec2 emissiveHandle; // offset 16
  uint baseArray;       // offset 24
  uint baseLayer;       // offset 28
  uint normalArray;     // offset 32
  uint normalLayer;     // offset 36
  uint emissiveArray;   // offset 40
  uint emissiveLayer;   // offset 44
  vec2 size;            // offset 48: width, height in texels (texture coordinates are divided by it)
  uint flags;           // offset 56
  float roughness;      // offset 60
  float metallic;       // offset 64
  float opacity;        // offset 68: a liquid's blend (lighting/liquids.h), 1 = opaque
  uvec2 baseTexels;     // offset 72: each map's width and height in texels, which its array
  uvec2 normalTexels;   // offset 80  layer may exceed (textures.glsl); 0 where there is no map
  uvec2 emissiveTexels; // offset 88
  vec4 liquid;          // offset 96: physical mode's liquid, rgb transmission tint (additive: its light), a opacity
};                      // 112 bytes

// scene/gpu_structs.h GpuLight, byte for byte (Quake light units, colours 0..1).
const uint LIGHT_POINT = BT_LIGHT_POINT;
const uint LIGHT_SUN = BT_LIGHT_SUN;
const uint LIGHT_DOME = BT_LIGHT_DOME;
const uint FORMULA_LINEAR = BT_FORMULA_LINEAR;
const uint FORMULA_INVERSE = BT_FORMULA_INVERSE;
const uint FORMULA_INVERSE2 = BT_FORMULA_INVERSE2;
const uint FORMULA_INFINITE = BT_FORMULA_INFINITE;
const uint FORMULA_LOCAL_MIN = BT_FORMULA_LOCAL_MIN;
const uint FORMULA_INVERSE2A = BT_FORMULA_INVERSE2A;
const uint FORMULA_SURFACE_RADIOSITY = BT_FORMULA_SURFACE_RADIOSITY;
const uint FORMULA_BOUNCE = BT_FORMULA_BOUNCE; // an ericw-tools bounce light (lighting/bounce.h)
const uint FORMULA_Q3_POINT = BT_FORMULA_Q3_POINT;   // q3map2's point/spot light (lighting/q3map2_light.h)
const uint FORMULA_Q3_LINEAR = BT_FORMULA_Q3_LINEAR; // ... with spawnflags 1 (linear)
const uint FORMULA_Q3_AREA = BT_FORMULA_Q3_AREA;     // ... a piece of a q3map_surfacelight (lighting/q3map2_shader_light.h)
const uint LIGHT_FLAG_BLEED = BT_LIGHT_FLAG_BLEED;
const uint LIGHT_FLAG_FROM_SURFACE = BT_LIGHT_FLAG_FROM_SURFACE;
const uint LIGHT_FLAG_FACE_MINLIGHT = BT_LIGHT_FLAG_FACE_MINLIGHT;
const uint LIGHT_FLAG_DIRT = BT_LIGHT_FLAG_DIRT;
const uint LIGHT_FLAG_DIRT_RADIUS = BT_LIGHT_FLAG_DIRT_RADIUS;
const uint LIGHT_FLAG_Q3_SPOT = BT_LIGHT_FLAG_Q3_SPOT;
const uint LIGHT_FLAG_SUN_TABLE = BT_LIGHT_FLAG_SUN_TABLE;

struct GpuLight {
  vec3 origin;     // offset 0
  uint type;       // offset 12
  vec3 color;      // offset 16
  float value;     // offset 28
  vec3 direction;  // offset 32
  float cosOuter;  // offset 44
  uint formula;    // offset 48
  float atten;     // offset 52
  float falloff;   // offset 56
  float anglescale;// offset 60
  float cosInner;  // offset 64
  float deviance;  // offset 68
  uint flags;      // offset 72
  float faithfulScale; // offset 76
  float dirtScale;     // offset 80: faithful dirt (LIGHT_FLAG_DIRT), lighting/faithful.h
  float dirtGain;      // offset 84
  float dirtOffRadius; // offset 88: with LIGHT_FLAG_DIRT_RADIUS
  float dirtOnRadius;  // offset 92
  uint skyMaterial;    // offset 96: suns with _suntexture, 1 + the sky material (0: any sky)
  uint lightChannels;  // offset 100: _light_channel_mask (lighting/faithful_light.cpp; not read here yet)
  uint shadowChannels; // offset 104: _shadow_channel_mask
  uint sunTable;       // offset 108: with LIGHT_FLAG_SUN_TABLE, the first of its directions in the bake's sun table
  float physicalIntensity; // offset 112: lighting/physical_light.h prepare
  float physicalInvReach;  // offset 116: 0 = never ends
  uint visBox;             // offset 120: 1 + its box among the bake's vis boxes (lighting/vis_approx.h), 0 none
  float physicalHueSum;    // offset 124: lighting/physical_light.h prepare, the emitted hue's channels summed
};                 // 128 bytes: std430 rounds the array stride up to the vec3s' 16-byte alignment

// scene/gpu_structs.h GpuEmitter: one triangle of an emitting face, cdf by area.
struct GpuEmitter {
  vec3 v0;      // offset 0
  uint face;    // offset 12
  vec3 v1;      // offset 16
  float area;   // offset 28
  vec3 v2;      // offset 32
  float cdf;    // offset 44
};              // 48 bytes
