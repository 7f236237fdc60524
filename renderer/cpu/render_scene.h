// Everything the integrator reads, as flat arrays of the structs in gpu_lights.h: per-face
// shading data, per-material parameters, lights and emitter triangles, plus the ray tracer.
#pragma once

#include "renderer/cpu/brush_tracer.h"
#include "renderer/cpu/gpu_lights.h"
#include "renderer/cpu/lights.h"
#include "scene/scene.h"

#include <memory>
#include <vector>

namespace bt {

struct RenderSceneOptions {
  LightOptions lights;
  bool showHidden = false; // draw clip/trigger/skip/hint/origin faces instead of skipping them
};

struct RenderScene {
  const Scene* scene = nullptr;           // images are read from scene->materials
  std::vector<GpuShadeFace> faces;        // parallel to scene->faces
  std::vector<GpuMaterial> materials;     // parallel to scene->materials
  std::vector<GpuLight> lights;
  std::vector<GpuLight> surfaceLights;    // per material: the _surface template (value 0 = none)
  std::vector<GpuEmitter> emitters;       // triangles of emitting faces, cdf by area
  float emitterArea = 0.0f;
  WorldLighting world;
  std::unique_ptr<BrushTracer> tracer;
};

// Classifies faces by texture name (Quake conventions, see README), reads the lights, and
// builds the tracer. `scene` must outlive the result.
RenderScene buildRenderScene(const Scene& scene, const RenderSceneOptions& options, Diagnostics& diagnostics);

// Face classification from a texture name and its Q2/Q3 surface attributes.
uint32_t classifyTexture(std::string_view texture, const std::optional<SurfaceAttributes>& surface);

} // namespace bt
