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

const uint MATERIAL_HAS_BASE = 1u;
const uint MATERIAL_HAS_NORMAL = 2u;

// Texture references for both paths: bindless handles, or (array, layer) in the texture arrays.
struct GpuMaterial {
  uvec2 baseHandle;   // offset 0
  uvec2 normalHandle; // offset 8
  uint baseArray;     // offset 16
  uint baseLayer;     // offset 20
  uint normalArray;   // offset 24
  uint normalLayer;   // offset 28
  vec2 size;          // offset 32: width, height in texels (texture coordinates are divided by it)
  uint flags;         // offset 40
  float roughness;    // offset 44
};                    // 48 bytes
