#include "lighting/sky.h"

#include "bvh/trace_scene.h"
#include "scene/color.h"
#include "scene/parallel_for.h"
#include "shaders/sky_constants.glsl" // the engine's numbers, shared with the shaders

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/packing.hpp>

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

namespace {

// A direction's components with the face's axis first, then the face's u and v axes (the next
// two, cyclically), and back: the swizzles shaders/sky.glsl makes.
glm::vec3 toFaceAxes(const glm::vec3& d, int axis) {
  return axis == 0 ? d : axis == 1 ? glm::vec3(d.y, d.z, d.x) : glm::vec3(d.z, d.x, d.y);
}
glm::vec3 fromFaceAxes(const glm::vec3& p, int axis) {
  return axis == 0 ? p : axis == 1 ? glm::vec3(p.z, p.x, p.y) : glm::vec3(p.y, p.z, p.x);
}

} // namespace

int skyMapSize(const Scene& scene) {
  if (!scene.sky) return 0;
  if (scene.sky->kind == Sky::Kind::QuakeLayers) return BT_SKY_MAP_LAYERS_SIZE;
  int largest = 0;
  for (uint32_t i = 0; i < 6 && scene.sky->firstMaterial + i < scene.materials.size(); ++i) {
    const Image& image = scene.materials[scene.sky->firstMaterial + i].baseColor;
    largest = std::max({largest, image.width, image.height});
  }
  return std::clamp(largest, BT_SKY_MAP_MIN_SIZE, BT_SKY_MAP_MAX_SIZE);
}

SkyMap bakeSkyMap(const Scene& scene, unsigned threads) {
  SkyMap map;
  map.size = skyMapSize(scene);
  const size_t n = size_t(map.size);
  map.texels.resize(6 * n * n * 4);
  // One row of one face per item: 3072 items of 512 texels for Quake's layers.
  parallelFor(6 * n, threads, [&](size_t row) {
    const int face = int(row / n), j = int(row % n);
    for (int i = 0; i < map.size; ++i) {
      const glm::vec3 linear = srgbToLinear(skyColor(scene, skyMapTexelDirection({i, j, face}, map.size)));
      uint16_t* texel = &map.texels[(row * n + size_t(i)) * 4];
      for (int c = 0; c < 3; ++c) texel[c] = glm::packHalf1x16(linear[c]);
      texel[3] = glm::packHalf1x16(1.0f);
    }
  });
  return map;
}

// The arithmetic of shaders/sky.glsl skyMapTexel, step for step: the largest component picks the
// face (ties to x, then y), the other two over it are u, v in [-1, 1], and the texel is the one
// they fall in. A zero direction reads face +x's middle rather than dividing by zero.
glm::ivec3 skyMapTexel(const glm::vec3& dir, int size) {
  const glm::vec3 a = glm::abs(dir);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
  const glm::vec3 p = toFaceAxes(dir, axis);
  const float major = std::max(std::abs(p.x), BT_SKY_MAP_TINY);
  const float half = 0.5f * float(size);
  const int i = std::clamp(int(std::floor((p.y / major + 1.0f) * half)), 0, size - 1);
  const int j = std::clamp(int(std::floor((p.z / major + 1.0f) * half)), 0, size - 1);
  return {i, j, 2 * axis + (p.x < 0.0f ? 1 : 0)};
}

glm::vec3 skyMapTexelDirection(const glm::ivec3& texel, int size) {
  const float half = 0.5f * float(size);
  const glm::vec3 p((texel.z & 1) ? -1.0f : 1.0f, (float(texel.x) + 0.5f) / half - 1.0f, (float(texel.y) + 0.5f) / half - 1.0f);
  return fromFaceAxes(p, texel.z / 2);
}

glm::vec3 skyRadiance(const SkyMap& map, const glm::vec3& dir) {
  const glm::ivec3 t = skyMapTexel(dir, map.size);
  const size_t n = size_t(map.size);
  const uint16_t* texel = &map.texels[((size_t(t.z) * n + size_t(t.y)) * n + size_t(t.x)) * 4];
  return {glm::unpackHalf1x16(texel[0]), glm::unpackHalf1x16(texel[1]), glm::unpackHalf1x16(texel[2])};
}

} // namespace bt
