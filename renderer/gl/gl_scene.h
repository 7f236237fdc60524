// A scene's geometry, materials and lights in GPU storage buffers: bvh/trace_scene.h's
// TraceScene arrays (its tree as gl_structs.h GlBvhNodes), plus the per-face classes,
// materials, lights and emitters, and the buffer-texture views the traversal reads.
#pragma once

#include "bvh/trace_scene.h"
#include "lighting/light_grid.h"
#include "lighting/sky.h"
#include "renderer/gl/gl_structs.h"

#include <span>
#include <vector>

namespace bt::gl {

struct GlLighting;

// gl_structs.h GlBvhNode from TraceScene's tree (TraceScene::nodes()), in linear time. Throws
// GlError for a leaf beyond GlBvhNode's reference limits (kGlLeafMaxCount, kGlLeafMaxFirst).
std::vector<GlBvhNode> bvhForGl(std::span<const GpuBvhNode> nodes);
// Both trees of a TraceScene, the triangles' after the brushes' with node 0's pads set
// (gl_structs.h GlBvhNode says how).
std::vector<GlBvhNode> sceneBvhForGl(const TraceScene& tracer);

class GlSceneBuffers {
public:
  // faceFlags in GlLighting: one per TraceScene face (= Scene face), or empty for none.
  GlSceneBuffers(const TraceScene& tracer, const std::vector<GlMaterial>& materials, const GlLighting& lighting, size_t materialCount);
  ~GlSceneBuffers();
  GlSceneBuffers(const GlSceneBuffers&) = delete;
  GlSceneBuffers& operator=(const GlSceneBuffers&) = delete;

  void bind() const;                                      // to the Binding points and TexelUnits of gl_structs.h
  void setLightmaps(const std::vector<uint32_t>& packed); // kBindingLightmaps; empty: none
  unsigned lightmapBuffer() const { return lightmaps_; }  // what a GPU bake writes its luxels into
  // Replaces the lights and their grid (kBindingLights, kBindingLightGrid, kBindingLightIndices):
  // the same lights with other colours (the viewer's style sliders), their grid built anew.
  void setLights(const std::vector<GpuLight>& lights, const LightGrid& grid, float scaledist);
  // Replaces the `_surface` templates (kBindingSurfaceLights), one per material: the same with
  // other colours (the viewer's style sliders on physical mode's emitters).
  void setSurfaceLights(const std::vector<GpuLight>& surfaceLights);

private:
  static constexpr int kBufferCount = 11; // Binding 0..10
  static constexpr int kTexelViewCount = kTexelUnitEnd - kTexelNodes;
  unsigned buffers_[kBufferCount] = {};
  unsigned texelViews_[kTexelViewCount] = {}; // buffer textures, by TexelUnit - kTexelNodes
  unsigned lightmaps_ = 0;                    // kBindingLightmaps
  unsigned sky_ = 0;                          // kTextureSky
  size_t materialCount_ = 0;                  // the surface templates' count at least

  void uploadSky(const SkyMap& sky);
  void uploadLights(const std::vector<GpuLight>& lights, const LightGrid& grid, float scaledist);
  void uploadSurfaceLights(const std::vector<GpuLight>& surfaceLights);
};

} // namespace bt::gl
