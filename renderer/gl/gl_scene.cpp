#include "renderer/gl/gl_scene.h"

#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_tracer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cfloat>
#include <span>

namespace bt::gl {

namespace {

template <typename T>
void upload(GLuint buffer, std::span<const T> v) {
  // A zero-sized buffer cannot be bound as an SSBO; an empty array uploads one zero element.
  const T zero{};
  const T* data = v.empty() ? &zero : v.data();
  const size_t bytes = std::max<size_t>(v.size(), 1) * sizeof(T);
  BT_GL(glNamedBufferStorage(buffer, static_cast<GLsizeiptr>(bytes), data, 0));
}

// The root the shaders start from when the scene has nothing to trace: an interior node whose
// children would start at itself, which no built tree has (shaders/trace.glsl returns a miss
// on seeing it, before any slab test).
constexpr GpuBvhNode kEmptyRoot{{FLT_MAX, FLT_MAX, FLT_MAX}, 0, {-FLT_MAX, -FLT_MAX, -FLT_MAX}, 0};

} // namespace

GlSceneBuffers::GlSceneBuffers(const TraceScene& tracer, const std::vector<GpuMaterial>& materials,
                               const GlLighting& lighting, size_t materialCount) {
  BT_GL(glCreateBuffers(kBufferCount, buffers_));
  upload(buffers_[kBindingNodes], tracer.nodes().empty() ? std::span<const GpuBvhNode>(&kEmptyRoot, 1) : tracer.nodes());
  upload(buffers_[kBindingBrushes], tracer.brushes());
  upload(buffers_[kBindingSides], tracer.sides());
  upload(buffers_[kBindingFaces], tracer.faces());
  std::vector<uint32_t> faceFlags = lighting.faceFlags;
  faceFlags.resize(tracer.faces().size(), 0u);
  upload(buffers_[kBindingFaceFlags], std::span<const uint32_t>(faceFlags));
  upload(buffers_[kBindingMaterials], std::span<const GpuMaterial>(materials));
  upload(buffers_[kBindingLights], std::span<const GpuLight>(lighting.lights));
  // One template per material, so the shader indexes it by a face's material; value 0 = none.
  std::vector<GpuLight> surfaceLights = lighting.surfaceLights;
  surfaceLights.resize(std::max(surfaceLights.size(), materialCount), GpuLight{.value = 0.0f});
  upload(buffers_[kBindingSurfaceLights], std::span<const GpuLight>(surfaceLights));
  upload(buffers_[kBindingEmitters], std::span<const GpuEmitter>(lighting.emitters));

  // Light selection: the grid header and its cells in one buffer, as light_select.glsl reads
  // them. A lighting without a grid (tests that list lights by hand) gets one built here.
  const LightGrid grid = lighting.lightGrid.cells.empty()
                             ? buildLightGrid(lighting.lights, tracer.bounds(), lighting.scaledist)
                             : lighting.lightGrid;
  const auto* header = reinterpret_cast<const uint8_t*>(&grid.header);
  const auto* cells = reinterpret_cast<const uint8_t*>(grid.cells.data());
  std::vector<uint8_t> gridBytes(header, header + sizeof(GpuLightGrid));
  gridBytes.insert(gridBytes.end(), cells, cells + grid.cells.size() * sizeof(GpuLightCell));
  upload(buffers_[kBindingLightGrid], std::span<const uint8_t>(gridBytes));
  upload(buffers_[kBindingLightIndices], std::span<const uint32_t>(grid.indices));
}

GlSceneBuffers::~GlSceneBuffers() { glDeleteBuffers(kBufferCount, buffers_); }

void GlSceneBuffers::bind() const {
  for (GLuint i = 0; i < kBufferCount; ++i) BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, buffers_[i]));
}

} // namespace bt::gl
