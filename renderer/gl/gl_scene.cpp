#include "renderer/gl/gl_scene.h"

#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_tracer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace bt::gl {

namespace {

glm::vec3 toFloat(const dvec3& v) { return glm::vec3(v); }

// Bounds in float, rounded outward so that they still contain what the double bounds held:
// a box rounded inward would cull rays that hit the brush's faces exactly at its edges.
glm::vec3 roundDown(const dvec3& v) {
  glm::vec3 f(v);
  for (int i = 0; i < 3; ++i)
    if (double(f[i]) > v[i]) f[i] = std::nextafter(f[i], -INFINITY);
  return f;
}
glm::vec3 roundUp(const dvec3& v) {
  glm::vec3 f(v);
  for (int i = 0; i < 3; ++i)
    if (double(f[i]) < v[i]) f[i] = std::nextafter(f[i], INFINITY);
  return f;
}

struct Builder {
  const Scene& scene;
  int leafSize;
  std::vector<uint32_t> order; // brush indices, partitioned in place
  GpuSceneArrays& out;

  Bounds boundsOf(uint32_t first, uint32_t count) const {
    Bounds b;
    for (uint32_t i = first; i < first + count; ++i) b.grow(scene.brushes[order[i]].bounds);
    return b;
  }

  void build(uint32_t nodeIndex, uint32_t first, uint32_t count) {
    const Bounds bounds = boundsOf(first, count);
    out.nodes[nodeIndex].boundsMin = roundDown(bounds.min);
    out.nodes[nodeIndex].boundsMax = roundUp(bounds.max);
    if (count <= static_cast<uint32_t>(leafSize)) {
      out.nodes[nodeIndex].leftOrFirst = first;
      out.nodes[nodeIndex].count = count;
      return;
    }
    Bounds centres;
    for (uint32_t i = first; i < first + count; ++i) centres.grow(scene.brushes[order[i]].bounds.center());
    const dvec3 extent = centres.extent();
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t half = count / 2;
    std::nth_element(order.begin() + first, order.begin() + first + half, order.begin() + first + count,
                     [&](uint32_t a, uint32_t b) {
                       return scene.brushes[a].bounds.center()[axis] < scene.brushes[b].bounds.center()[axis];
                     });
    const auto left = static_cast<uint32_t>(out.nodes.size());
    out.nodes.resize(out.nodes.size() + 2);
    out.nodes[nodeIndex].leftOrFirst = left;
    out.nodes[nodeIndex].count = 0;
    build(left, first, half);
    build(left + 1, first + half, count - half);
  }
};

} // namespace

GpuSceneArrays buildGpuSceneArrays(const Scene& scene, const std::vector<uint32_t>& faceFlags, int leafSize) {
  // nodes[0] is the root, so a scene of one brush must still fit a leaf: leafSize >= 1.
  GpuSceneArrays out;
  out.faces.reserve(scene.faces.size());
  for (size_t i = 0; i < scene.faces.size(); ++i) {
    const Face& f = scene.faces[i];
    GpuFace g{};
    g.normal = toFloat(f.plane.normal);
    g.dist = static_cast<float>(f.plane.dist);
    g.origin = toFloat(f.frame.origin);
    g.tangent = toFloat(f.frame.tangent);
    g.bitangent = toFloat(f.frame.bitangent);
    g.material = f.material;
    g.sceneFace = static_cast<uint32_t>(i);
    g.flags = i < faceFlags.size() ? faceFlags[i] : 0u;
    out.faces.push_back(g);
  }

  Builder builder{scene, std::max(leafSize, 1), {}, out};
  for (uint32_t i = 0; i < scene.brushes.size(); ++i)
    if (scene.brushes[i].faceCount > 0 && !scene.brushes[i].bounds.empty()) builder.order.push_back(i);
  out.nodes.resize(1);
  if (builder.order.empty()) {
    // Nothing to trace. The root must still be a leaf (count 0 would make it an interior node
    // with children past the end): one brush without planes, which no ray can hit.
    out.nodes[0] = {glm::vec3(0.0f), 0, glm::vec3(0.0f), 1};
    out.brushes.push_back({glm::vec3(0.0f), 0, glm::vec3(0.0f), 0});
    return out;
  }
  builder.build(0, 0, static_cast<uint32_t>(builder.order.size()));

  out.brushes.reserve(builder.order.size());
  for (uint32_t index : builder.order) {
    const Brush& b = scene.brushes[index];
    out.brushes.push_back({roundDown(b.bounds.min), b.firstFace, roundUp(b.bounds.max), b.faceCount});
  }
  return out;
}

GlSceneBuffers::GlSceneBuffers(const GpuSceneArrays& arrays, const std::vector<GpuMaterial>& materials,
                               const GlLighting& lighting, size_t materialCount) {
  BT_GL(glCreateBuffers(kBufferCount, buffers_));
  auto upload = [](GLuint buffer, const auto& v) {
    // A zero-sized buffer cannot be bound as an SSBO; an empty array uploads one dummy element.
    const size_t bytes = std::max<size_t>(v.size(), 1) * sizeof(v[0]);
    std::vector<uint8_t> zero;
    const void* data = v.data();
    if (v.empty()) {
      zero.resize(bytes);
      data = zero.data();
    }
    BT_GL(glNamedBufferStorage(buffer, static_cast<GLsizeiptr>(bytes), data, 0));
  };
  upload(buffers_[kBindingNodes], arrays.nodes);
  upload(buffers_[kBindingBrushes], arrays.brushes);
  upload(buffers_[kBindingFaces], arrays.faces);
  upload(buffers_[kBindingMaterials], materials);
  upload(buffers_[kBindingLights], lighting.lights);
  // One template per material, so the shader indexes it by a face's material; value 0 = none.
  std::vector<GpuLight> surfaceLights = lighting.surfaceLights;
  surfaceLights.resize(std::max(surfaceLights.size(), materialCount), GpuLight{.value = 0.0f});
  upload(buffers_[kBindingSurfaceLights], surfaceLights);
  upload(buffers_[kBindingEmitters], lighting.emitters);

  // Light selection: the grid header and its cells in one buffer, as light_select.glsl reads
  // them. A lighting without a grid (tests that list lights by hand) gets one cell over
  // everything, which selects exactly like a grid, only without culling.
  const LightGrid grid =
      lighting.lightGrid.cells.empty() ? buildLightGrid(lighting.lights, Bounds{}, lighting.scaledist) : lighting.lightGrid;
  const auto* header = reinterpret_cast<const uint8_t*>(&grid.header);
  const auto* cells = reinterpret_cast<const uint8_t*>(grid.cells.data());
  std::vector<uint8_t> gridBytes(header, header + sizeof(GpuLightGrid));
  gridBytes.insert(gridBytes.end(), cells, cells + grid.cells.size() * sizeof(GpuLightCell));
  upload(buffers_[kBindingLightGrid], gridBytes);
  upload(buffers_[kBindingLightIndices], grid.indices);
}

GlSceneBuffers::~GlSceneBuffers() { glDeleteBuffers(kBufferCount, buffers_); }

void GlSceneBuffers::bind() const {
  for (GLuint i = 0; i < kBufferCount; ++i) BT_GL(glBindBufferBase(GL_SHADER_STORAGE_BUFFER, i, buffers_[i]));
}

} // namespace bt::gl
