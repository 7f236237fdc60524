// C++ mirrors of the GL tracer's own std430/std140 structs in shaders/structs.glsl and
// shaders/camera.glsl (the shared ones are in scene/gpu_structs.h). Every size and offset is
// asserted: a mismatch with the GLSL side is a compile error here.
#pragma once

#include "shaders/gl_bindings.glsl" // binding points, texture and image units, shared with the shaders
#include "scene/gpu_structs.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstddef>
#include <cstdint>

namespace bt::gl {

// Binding points of the storage buffers (their numbers: shaders/gl_bindings.glsl).
enum Binding : uint32_t {
  kBindingNodes = BT_BINDING_NODES,
  kBindingBrushes = BT_BINDING_BRUSHES,
  kBindingFaces = BT_BINDING_FACES,
  kBindingMaterials = BT_BINDING_MATERIALS,
  kBindingLights = BT_BINDING_LIGHTS,
  kBindingSurfaceLights = BT_BINDING_SURFACE_LIGHTS,
  kBindingEmitters = BT_BINDING_EMITTERS,
  kBindingSides = BT_BINDING_SIDES,
  kBindingFaceFlags = BT_BINDING_FACE_FLAGS,
  kBindingLightGrid = BT_BINDING_LIGHT_GRID,       // GpuLightGrid, then its GpuLightCell array (shaders/light_select.glsl)
  kBindingLightIndices = BT_BINDING_LIGHT_INDICES, // the grid's uint index array into the light buffer
  // The wavefront path tracer's per-pixel state (shaders/wavefront.glsl, pathtrace.comp's shade kernel).
  kBindingWavefrontRays = BT_BINDING_WAVEFRONT_RAYS,
  kBindingWavefrontHits = BT_BINDING_WAVEFRONT_HITS,
  kBindingWavefrontPaths = BT_BINDING_WAVEFRONT_PATHS,
  kBindingWavefrontEndedCount = BT_BINDING_WAVEFRONT_ENDED_COUNT,
  kBindingLightmaps = BT_BINDING_LIGHTMAPS, // faithful mode's baked luxels, packed (scene/gpu_structs.h; shaders/lightmaps.glsl)
  // The faithful bake (shaders/bake.comp, gl_bake.h) runs without the wavefront's buffers and
  // takes their points: drivers need offer only 16 storage blocks to a compute shader.
  kBindingBakeSamples = BT_BINDING_BAKE_SAMPLES, // GpuLuxelSample per sample point
  kBindingBakeSums = BT_BINDING_BAKE_SUMS,       // 4 vec4 per sample point (lighting/faithful_light.h LuxelSums)
  // vec4 per direction: the dome's (lighting/faithful.h skyDomeDirections), then the penumbra
  // suns' table (RenderScene::sunTable)
  kBindingBakeSkyDome = BT_BINDING_BAKE_SKY_DOME,
};

// The brushes, slanted-side lists and faces are bvh/trace_scene.h's TraceScene arrays
// (scene/gpu_structs.h GpuBrush, GpuFace), uploaded unchanged; the BVH nodes are GlBvhNodes made
// from TraceScene's tree (below). The shaders read the face classes (kFace*) and lighting
// channels from a separate per-face buffer, RenderScene::faceFlags and faceChannels packed by
// gpuFaceWord.

// The BVH as the GL traversal reads it, made from TraceScene::nodes() at upload (gl_scene.h
// bvhForGl, linear time): one node per interior node of that tree, holding both children's boxes,
// so that one visit reads 4 texels and tests both children (the Aila-Laine / tinybvh BVH_GPU
// layout) where TraceScene's nodes take 2 texels per child plus 2 for the node itself. Leaves
// get no node: a parent's child reference names the leaf's brush range itself.
//   left, right: a child reference, kGlNoChild, or kGlLeafRef | count << 24 | first brush for a
//   leaf of `count` brushes (1 .. 127) from `first` (< 2^24), or an interior child's GlBvhNode
//   index. Node 0 is the root; kGlNoChild (0) marks the missing children of a root that has
//   fewer than two (a scene of one leaf, or of none).
//
//   4 texels (shaders/trace.glsl nodeRow): (leftMin, left), (leftMax, pad), (rightMin, right),
//   (rightMax, pad).
// Mesh triangles (TraceScene::triangleNodes(), scene/gpu_structs.h GpuTriangle; gl_scene.h
// sceneBvhForGl) travel in the
// same two buffers, so that they need no binding of their own: their tree's GlBvhNodes follow
// the brushes' (child references offset by where they start; leaf references name triangles),
// and the triangles follow the brushes in the brush buffer, 3 rows (texels) each. The root's
// pads say where: node 0's pad0 is the triangle tree's root node (kGlNoChild: no triangles),
// its pad1 the brush-buffer row of the first triangle (shaders/trace.glsl traceRay).
inline constexpr uint32_t kGlNoChild = BT_GL_NO_CHILD;
inline constexpr uint32_t kGlLeafRef = BT_GL_LEAF_REF;
inline constexpr uint32_t kGlLeafMaxCount = 127;
inline constexpr uint32_t kGlLeafMaxFirst = (1u << 24) - 1;
struct GlBvhNode {
  float leftMin[3];
  uint32_t left;
  float leftMax[3];
  uint32_t pad0;
  float rightMin[3];
  uint32_t right;
  float rightMax[3];
  uint32_t pad1;
};
static_assert(sizeof(GlBvhNode) == 64);
static_assert(offsetof(GlBvhNode, left) == 12 && offsetof(GlBvhNode, leftMax) == 16);
static_assert(offsetof(GlBvhNode, rightMin) == 32 && offsetof(GlBvhNode, right) == 44);
static_assert(offsetof(GlBvhNode, rightMax) == 48 && offsetof(GlBvhNode, pad1) == 60);

// Texture units of the buffer textures through which the traversal reads those arrays
// (shaders/scene_buffers.glsl says why), after the material texture arrays' units
// 0 .. kMaxTextureArrays - 1 (gl_textures.h). Each is a view of the storage buffer above, one
// 16-byte texel per row of the struct: a GpuBvhNode is 2 texels, a GpuBrush 4, a GpuFace 4 (its
// plane first), a side index 1 (R32UI); the nodes are GlBvhNodes, 4 texels each.
enum TexelUnit : uint32_t {
  kTexelNodes = BT_TEXEL_NODES,
  kTexelBrushes = BT_TEXEL_BRUSHES,
  kTexelSides = BT_TEXEL_SIDES,
  kTexelFaces = BT_TEXEL_FACES,
  kTexelUnitEnd = BT_TEXEL_UNIT_END,         // one past the last buffer texture
  kTextureSky = BT_TEXTURE_SKY,              // not a buffer: the sky's 2D array texture (gl_scene.h)
  kTextureUnitCount = BT_TEXTURE_UNIT_COUNT, // the context must offer this many compute texture units
};
static_assert(sizeof(GlBvhNode) == 4 * 16 && sizeof(GpuBrush) == 4 * 16 && sizeof(GpuFace) == 4 * 16 && sizeof(GpuTriangle) == 3 * 16);
static_assert(offsetof(GpuFace, plane) == 0);

// GlMaterial::flags. Not the bits of bt::GpuMaterial::flags (scene/gpu_structs.h: the CPU
// reference's shading parameters, never uploaded); lightingFor() (gl_lighting.cpp) translates.
enum MaterialFlags : uint32_t {
  kMaterialHasBase = BT_GL_MATERIAL_HAS_BASE,
  kMaterialHasNormal = BT_GL_MATERIAL_HAS_NORMAL,
  kMaterialHasEmissive = BT_GL_MATERIAL_HAS_EMISSIVE,   // scene/gpu_structs.h kMaterialEmissive
  kMaterialGgx = BT_GL_MATERIAL_GGX,                    // scene/gpu_structs.h kMaterialSpecular
  kMaterialBlendAddGl = BT_GL_MATERIAL_BLEND_ADD,       // scene/gpu_structs.h kMaterialBlendAdd
  kMaterialBlendFilterGl = BT_GL_MATERIAL_BLEND_FILTER, // scene/gpu_structs.h kMaterialBlendFilter
};

// A material as the shaders read it (shaders/structs.glsl GlMaterial): its textures on either
// path and the flags above.
struct GlMaterial {
  uint64_t baseHandle; // bindless texture handles, 0 on the arrays path
  uint64_t normalHandle;
  uint64_t emissiveHandle;
  uint32_t baseArray; // arrays path: which sampler2DArray, and the layer in it
  uint32_t baseLayer;
  uint32_t normalArray;
  uint32_t normalLayer;
  uint32_t emissiveArray;
  uint32_t emissiveLayer;
  glm::vec2 size; // Material::width, height
  uint32_t flags; // MaterialFlags
  float roughness;
  float metallic;
  float opacity;           // scene/gpu_structs.h GpuMaterial::opacity (liquids)
  glm::uvec2 baseTexels;   // each map's Image width, height: the arrays path may store it in a
  glm::uvec2 normalTexels; // larger layer (gl_textures.h), and the shaders wrap at this size
  glm::uvec2 emissiveTexels;
  glm::vec4 liquid; // physical mode's liquid: rgb the transmission tint (additive: its light), a GpuMaterial::physicalOpacity
};
static_assert(sizeof(GlMaterial) == 112);
static_assert(offsetof(GlMaterial, baseHandle) == 0 && offsetof(GlMaterial, normalHandle) == 8 &&
              offsetof(GlMaterial, emissiveHandle) == 16 && offsetof(GlMaterial, baseArray) == 24 &&
              offsetof(GlMaterial, baseLayer) == 28 && offsetof(GlMaterial, normalArray) == 32 && offsetof(GlMaterial, normalLayer) == 36 &&
              offsetof(GlMaterial, emissiveArray) == 40 && offsetof(GlMaterial, emissiveLayer) == 44 && offsetof(GlMaterial, size) == 48 &&
              offsetof(GlMaterial, flags) == 56 && offsetof(GlMaterial, roughness) == 60 && offsetof(GlMaterial, metallic) == 64 &&
              offsetof(GlMaterial, opacity) == 68 && offsetof(GlMaterial, baseTexels) == 72 && offsetof(GlMaterial, normalTexels) == 80 &&
              offsetof(GlMaterial, emissiveTexels) == 88 && offsetof(GlMaterial, liquid) == 96);

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
  uint32_t pad4;
  glm::ivec2 pixelOffset; // the top-left pixel of the piece a dispatch draws (shaders/camera.glsl dispatchPixel)
};
static_assert(sizeof(GpuCamera) == 96);
static_assert(offsetof(GpuCamera, origin) == 0 && offsetof(GpuCamera, pad0) == 12 && offsetof(GpuCamera, forward) == 16 &&
              offsetof(GpuCamera, pad1) == 28 && offsetof(GpuCamera, right) == 32 && offsetof(GpuCamera, pad2) == 44 &&
              offsetof(GpuCamera, up) == 48 && offsetof(GpuCamera, pad3) == 60 && offsetof(GpuCamera, imageSize) == 64 &&
              offsetof(GpuCamera, frameIndex) == 72 && offsetof(GpuCamera, seed) == 76 && offsetof(GpuCamera, firstFrame) == 80 &&
              offsetof(GpuCamera, pad4) == 84 && offsetof(GpuCamera, pixelOffset) == 88);

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
  // Faithful dirt (lighting/lights.h DirtSettings); read only by a program built with BT_FAITHFUL_DIRT.
  uint32_t dirtMode;
  float dirtDepth;
  float dirtAngle; // the cone's half-angle, radians
  float dirtScale; // worldspawn _dirtscale / _dirtgain, for minlight
  float dirtGain;
  uint32_t minlightDirt;
  float overbrightOne;   // WorldLighting::overbrightOne: the per-pixel view shows texture × stored / this
  glm::vec3 ambient;     // WorldLighting::ambient: q3map2's `_ambient`, added to the light sum
  uint32_t skySize;      // lighting/sky.h SkyMap::size: the sky texture's face edge, 0 without sky images
  uint32_t luxelDisplay; // WorldLighting::luxelDisplay: the per-pixel view's engine luxel table (BT_LUXEL_DISPLAY_*)
  float clampIndirect;   // IntegratorSettings::clampIndirect: physical mode's firefly clamp, units
  uint32_t pad[2];
};
static_assert(sizeof(GpuWorld) == 112);
static_assert(offsetof(GpuWorld, luxelDisplay) == 96);
static_assert(offsetof(GpuWorld, clampIndirect) == 100);
static_assert(offsetof(GpuWorld, ambient) == 80);
static_assert(offsetof(GpuWorld, skySize) == 92);
static_assert(offsetof(GpuWorld, minlight) == 0 && offsetof(GpuWorld, range) == 12 && offsetof(GpuWorld, scaledist) == 16 &&
              offsetof(GpuWorld, bouncescale) == 20 && offsetof(GpuWorld, faithfulBounces) == 24 && offsetof(GpuWorld, litwater) == 28 &&
              offsetof(GpuWorld, lightCount) == 32 && offsetof(GpuWorld, emitterCount) == 36 && offsetof(GpuWorld, emitterArea) == 40 &&
              offsetof(GpuWorld, physical) == 44 && offsetof(GpuWorld, bounces) == 48 && offsetof(GpuWorld, dirtMode) == 52 &&
              offsetof(GpuWorld, dirtDepth) == 56 && offsetof(GpuWorld, dirtAngle) == 60 && offsetof(GpuWorld, dirtScale) == 64 &&
              offsetof(GpuWorld, dirtGain) == 68 && offsetof(GpuWorld, minlightDirt) == 72 && offsetof(GpuWorld, overbrightOne) == 76);

} // namespace bt::gl

namespace bt::gl {
// Uniform blocks and image units (shaders/gl_bindings.glsl).
inline constexpr uint32_t kUniformCamera = BT_UNIFORM_CAMERA;
inline constexpr uint32_t kUniformWorld = BT_UNIFORM_WORLD;
inline constexpr uint32_t kImageAccumulation = BT_IMAGE_ACCUMULATION;
inline constexpr uint32_t kImageDisplay = BT_IMAGE_DISPLAY;
inline constexpr uint32_t kImageAlbedo = BT_IMAGE_ALBEDO;
inline constexpr uint32_t kImageNormalDepth = BT_IMAGE_NORMAL_DEPTH;
inline constexpr uint32_t kImageFace = BT_IMAGE_FACE;
inline constexpr uint32_t kImagePrimaryHits = BT_IMAGE_PRIMARY_HITS;
inline constexpr uint32_t kImageBounceT = BT_IMAGE_BOUNCE_T;
} // namespace bt::gl
