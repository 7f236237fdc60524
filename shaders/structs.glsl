// std430 mirrors of renderer/gl/gl_structs.h. Keep both sides in step: the C++ header has
// static_asserts on every size and offset below.

// A BVH node over brushes. count > 0: a leaf holding brushes [leftOrFirst, leftOrFirst + count)
// of the brush buffer; count == 0: an interior node whose children are leftOrFirst and
// leftOrFirst + 1.
struct GpuBvhNode {
  vec3 boundsMin;   // offset 0
  uint leftOrFirst; // offset 12
  vec3 boundsMax;   // offset 16
  uint count;       // offset 28
};                  // 32 bytes

// A convex brush: the intersection of the half-spaces behind faces [firstFace, firstFace + faceCount).
struct GpuBrush {
  vec3 boundsMin;   // offset 0
  uint firstFace;   // offset 12
  vec3 boundsMax;   // offset 16
  uint faceCount;   // offset 28
};                  // 32 bytes

// One brush side: its plane (normal points out of the brush, dot(normal, p) == dist on it) and
// its texture frame, s = dot(p - origin, tangent), t = dot(p - origin, bitangent), in texels.
struct GpuFace {
  vec3 normal;      // offset 0
  float dist;       // offset 12
  vec3 origin;      // offset 16
  uint material;    // offset 28
  vec3 tangent;     // offset 32
  uint sceneFace;   // offset 44: index into Scene::faces (the face AOV)
  vec3 bitangent;   // offset 48
  uint flags;       // offset 60
};                  // 64 bytes

// GpuFace.flags: renderer/cpu's face classes (scene/gpu_structs.h kFace*), from the texture name.
const uint FACE_HIDDEN = 1u;    // clip, trigger, skip, hint, origin, common/*: never seen
const uint FACE_SKY = 2u;       // sky*: the environment, and where sunlight comes from
const uint FACE_LIQUID = 4u;    // '*' textures: unlit unless _litwater
const uint FACE_NO_SHADOW = 8u; // faithful mode: does not block light
const uint FACE_EMISSIVE = 16u; // emissive texels or a _surface template

const uint MATERIAL_HAS_BASE = 1u;
const uint MATERIAL_HAS_NORMAL = 2u;
const uint MATERIAL_HAS_EMISSIVE = 4u; // an emissive map with lit texels (renderer/cpu kMaterialEmissive)
const uint MATERIAL_SPECULAR = 8u;     // a PBR set: GGX + diffuse (renderer/cpu kMaterialSpecular)

// Texture references for both paths (bindless handles, or (array, layer) in the texture
// arrays) and the shading parameters of renderer/cpu's GpuMaterial.
struct GpuMaterial {
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
  uint pad0;            // offset 68
};                      // 72 bytes

// scene/gpu_structs.h GpuLight, byte for byte (Quake light units, colours 0..1).
const uint LIGHT_POINT = 0u;
const uint LIGHT_SUN = 1u;
const uint LIGHT_DOME = 2u;
const uint FORMULA_LINEAR = 0u;
const uint FORMULA_INVERSE = 1u;
const uint FORMULA_INVERSE2 = 2u;
const uint FORMULA_INFINITE = 3u;
const uint FORMULA_LOCAL_MIN = 4u;
const uint FORMULA_INVERSE2A = 5u;
const uint FORMULA_SURFACE_RADIOSITY = 6u;
const uint LIGHT_FLAG_BLEED = 2u;
const uint LIGHT_FLAG_FROM_SURFACE = 4u;
const uint LIGHT_FLAG_FACE_MINLIGHT = 8u;

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
};                 // 80 bytes

// scene/gpu_structs.h GpuEmitter: one triangle of an emitting face, cdf by area.
struct GpuEmitter {
  vec3 v0;      // offset 0
  uint face;    // offset 12
  vec3 v1;      // offset 16
  float area;   // offset 28
  vec3 v2;      // offset 32
  float cdf;    // offset 44
};              // 48 bytes
