// C++ mirrors of the std430/std140 structs in shaders/structs.glsl and shaders/camera.glsl.
// Every size and offset is asserted: a mismatch with the GLSL side is a compile error here.
//
// The BVH node and brush layouts are the GL tracer's own until the shared bvh/trace_scene.h
// lands; they are the layout issue 3 describes (bounds + first/count, 32 bytes).
#pragma once

#include "scene/gpu_structs.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>

namespace bt::gl {

// Binding points of the storage buffers (shaders/scene_buffers.glsl).
enum Binding : uint32_t {
  kBindingNodes = 0,
  kBindingBrushes = 1,
  kBindingFaces = 2,
  kBindingMaterials = 3,
  kBindingLights = 4,
  kBindingSurfaceLights = 5,
  kBindingEmitters = 6,
  kBindingLightGrid = 7,    // GpuLightGrid, then its GpuLightCell array (shaders/light_select.glsl)
  kBindingLightIndices = 8, // the grid's uint index array into the light buffer
};

struct GpuBvhNode {
  glm::vec3 boundsMin;
  uint32_t leftOrFirst; // leaf: first brush; interior: left child (right = left + 1)
  glm::vec3 boundsMax;
  uint32_t count;       // brushes in a leaf, 0 for an interior node
};
static_assert(sizeof(GpuBvhNode) == 32);
static_assert(offsetof(GpuBvhNode, leftOrFirst) == 12 && offsetof(GpuBvhNode, boundsMax) == 16 &&
              offsetof(GpuBvhNode, count) == 28);

struct GpuBrush {
  glm::vec3 boundsMin;
  uint32_t firstFace; // into the face buffer
  glm::vec3 boundsMax;
  uint32_t faceCount;
};
static_assert(sizeof(GpuBrush) == 32);
static_assert(offsetof(GpuBrush, firstFace) == 12 && offsetof(GpuBrush, boundsMax) == 16 &&
              offsetof(GpuBrush, faceCount) == 28);

struct GpuFace {
  glm::vec3 normal; // out of the brush
  float dist;
  glm::vec3 origin; // texture frame, see scene.h TextureFrame
  uint32_t material;
  glm::vec3 tangent;
  uint32_t sceneFace; // index into Scene::faces
  glm::vec3 bitangent;
  uint32_t flags;
};
static_assert(sizeof(GpuFace) == 64);
static_assert(offsetof(GpuFace, dist) == 12 && offsetof(GpuFace, origin) == 16 && offsetof(GpuFace, material) == 28 &&
              offsetof(GpuFace, tangent) == 32 && offsetof(GpuFace, sceneFace) == 44 &&
              offsetof(GpuFace, bitangent) == 48 && offsetof(GpuFace, flags) == 60);

// GpuFace::flags: renderer/cpu's face classes (kFaceHidden, kFaceSky, ... in scene/gpu_structs.h).

enum MaterialFlags : uint32_t {
  kMaterialHasBase = 1,
  kMaterialHasNormal = 2,
  kMaterialHasEmissive = 4, // renderer/cpu kMaterialEmissive
  kMaterialGgx = 8,         // renderer/cpu kMaterialSpecular
};

struct GpuMaterial {
  uint64_t baseHandle;   // bindless texture handles, 0 on the arrays path
  uint64_t normalHandle;
  uint64_t emissiveHandle;
  uint32_t baseArray;    // arrays path: which sampler2DArray, and the layer in it
  uint32_t baseLayer;
  uint32_t normalArray;
  uint32_t normalLayer;
  uint32_t emissiveArray;
  uint32_t emissiveLayer;
  glm::vec2 size;        // Material::width, height
  uint32_t flags;        // MaterialFlags
  float roughness;
  float metallic;
  uint32_t pad0;
};
static_assert(sizeof(GpuMaterial) == 72);
static_assert(offsetof(GpuMaterial, normalHandle) == 8 && offsetof(GpuMaterial, emissiveHandle) == 16 &&
              offsetof(GpuMaterial, baseArray) == 24 && offsetof(GpuMaterial, emissiveLayer) == 44 &&
              offsetof(GpuMaterial, size) == 48 && offsetof(GpuMaterial, flags) == 56 &&
              offsetof(GpuMaterial, roughness) == 60 && offsetof(GpuMaterial, metallic) == 64);

// std140 uniform block `Camera` (shaders/camera.glsl), binding 0.
struct GpuCamera {
  glm::vec3 origin;
  float pad0;
  glm::vec3 forward;
  float pad1;
  glm::vec3 right;
  float pad2;
  glm::vec3 up;
  float pad3;
  glm::ivec2 imageSize;
  uint32_t frameIndex; // the sample index a dispatch takes
  uint32_t seed;
  uint32_t firstFrame; // the first sample index of the accumulation (it clears the sum)
  uint32_t pad4[3];
};
static_assert(sizeof(GpuCamera) == 96);
static_assert(offsetof(GpuCamera, forward) == 16 && offsetof(GpuCamera, right) == 32 && offsetof(GpuCamera, up) == 48 &&
              offsetof(GpuCamera, imageSize) == 64 && offsetof(GpuCamera, frameIndex) == 72);

// Lights and emitters are scene/gpu_structs.h's GpuLight and GpuEmitter, uploaded unchanged
// (shaders/structs.glsl mirrors them).

// std140 uniform block `World` (shaders/scene_buffers.glsl), binding 1.
struct GpuWorld {
  glm::vec3 minlight;
  float range;
  float scaledist;
  float bouncescale;
  int32_t faithfulBounces;
  uint32_t litwater;
  uint32_t lightCount;
  uint32_t emitterCount;
  float emitterArea;
  uint32_t physical;
  int32_t bounces;
  uint32_t pad[3];
};
static_assert(sizeof(GpuWorld) == 64);
static_assert(offsetof(GpuWorld, range) == 12 && offsetof(GpuWorld, faithfulBounces) == 24 &&
              offsetof(GpuWorld, emitterArea) == 40 && offsetof(GpuWorld, bounces) == 48);

} // namespace bt::gl
