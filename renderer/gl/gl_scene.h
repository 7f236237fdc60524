// A Scene's geometry and materials in GPU buffers: BVH nodes, brushes, faces, materials.
#pragma once

#include "renderer/gl/gl_structs.h"
#include "renderer/gl/gl_textures.h"
#include "scene/scene.h"

#include <memory>
#include <vector>

namespace bt::gl {

// The flat arrays the shaders read, built on the CPU.
struct GpuSceneArrays {
  std::vector<GpuBvhNode> nodes; // nodes[0] is the root; empty scene: one empty leaf
  std::vector<GpuBrush> brushes; // in BVH leaf order
  std::vector<GpuFace> faces;    // in Scene::faces order
};

// Median-split BVH over brush bounds, at most `leafSize` brushes a leaf. A stand-in with the
// shared node layout until the SAH builder of bvh/ lands; traversal does not depend on how the
// tree was split. Brushes without faces or bounds are left out.
// faceFlags: per Scene face, renderer/cpu's kFace* classes (empty: all 0).
GpuSceneArrays buildGpuSceneArrays(const Scene& scene, const std::vector<uint32_t>& faceFlags = {}, int leafSize = 4);

struct GlLighting;

class GlSceneBuffers {
public:
  GlSceneBuffers(const GpuSceneArrays& arrays, const std::vector<GpuMaterial>& materials, const GlLighting& lighting,
                 size_t materialCount);
  ~GlSceneBuffers();
  GlSceneBuffers(const GlSceneBuffers&) = delete;
  GlSceneBuffers& operator=(const GlSceneBuffers&) = delete;

  void bind() const; // to the Binding points of gl_structs.h

private:
  static constexpr int kBufferCount = 9; // Binding 0..8
  unsigned buffers_[kBufferCount] = {};
};

} // namespace bt::gl
