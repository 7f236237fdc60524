#include "renderer/cpu/sky.h"

#include "bvh/trace_scene.h"
#include "shaders/sky_constants.glsl" // the engine's numbers, shared with the shaders

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdlib>

namespace bt {

glm::vec2 skyLayerUv(const glm::vec3& dir) {
  const glm::vec3 flattened(dir.x, dir.y, dir.z * BT_SKY_FLATTEN);
  const float length = glm::length(flattened);
  if (!(length > 0.0f)) return glm::vec2(0.0f);
  const float scale = BT_SKY_RADIUS / length;
  return glm::vec2(flattened.x, flattened.y) * scale / BT_SKY_LAYER_SCALE;
}

namespace {
constexpr int kStToVec[18] = {BT_SKY_ST_TO_VEC};
constexpr int kSkyTexOrder[6] = {BT_SKY_TEX_ORDER};
} // namespace

int skyBoxSide(const glm::vec3& d) {
  const glm::vec3 a = glm::abs(d);
  if (a.x > a.y && a.x > a.z) return d.x < 0.0f ? 1 : 0;
  if (a.y > a.z && a.y > a.x) return d.y < 0.0f ? 3 : 2;
  return d.z < 0.0f ? 5 : 4;
}

glm::vec2 skyBoxUv(int side, const glm::vec3& d, int width, int height, bool clamped) {
  glm::vec3 b(0.0f);
  for (int j = 0; j < 3; ++j) {
    const int k = kStToVec[side * 3 + j];
    b[std::abs(k) - 1] = k < 0 ? -d[j] : d[j];
  }
  const glm::vec2 size(std::max(width, 1), std::max(height, 1));
  glm::vec2 st = (glm::vec2(b) / b.z + 1.0f) * 0.5f;
  st = clamped ? glm::clamp(st, 0.5f / size, 1.0f - 0.5f / size) : st * (size - 1.0f) / size + 0.5f / size;
  return glm::vec2(st.x, 1.0f - st.y);
}

glm::vec3 skyColor(const Scene& scene, const glm::vec3& dir) {
  const Sky& sky = *scene.sky;
  if (sky.kind == Sky::Kind::QuakeLayers) {
    // Both layers scroll by 0 at time 0, so they share the coordinates. The front layer's clear
    // texels are black, so its filtered colour is already weighted by its alpha (GL_DECAL).
    const glm::vec2 uv = skyLayerUv(dir);
    const glm::vec4 back = sampleBilinearRepeat(scene.materials[sky.firstMaterial].baseColor, uv.x, uv.y);
    const glm::vec4 front = sampleBilinearRepeat(scene.materials[sky.firstMaterial + 1].baseColor, uv.x, uv.y);
    return glm::vec3(front) + glm::vec3(back) * (1.0f - front.a);
  }
  const int side = skyBoxSide(dir);
  const Image& image = scene.materials[sky.firstMaterial + uint32_t(kSkyTexOrder[side])].baseColor;
  const glm::vec2 uv = skyBoxUv(side, dir, image.width, image.height, sky.kind == Sky::Kind::BoxClamped);
  return glm::vec3(sampleBilinearRepeat(image, uv.x, uv.y));
}

} // namespace bt
