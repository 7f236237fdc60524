// A ray, and the same ray prepared for the BVH's queries (RayContext). Most callers pass a Ray;
// one that asks several questions of one ray (a shadow ray tried against a light's recent
// blockers, then walked: lighting/shadow_groups.cpp) prepares it once and passes the context.
#pragma once

#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <limits>

// SSE2 (every x86-64) takes a box's three slabs in one register; elsewhere the scalar code.
#if defined(__SSE2__)
#define BT_SSE_NODE_TEST 1
#include <emmintrin.h>
#else
#define BT_SSE_NODE_TEST 0
#endif

namespace bt {

struct Ray {
  glm::vec3 origin{0.0f};
  float tMin = 0.0f;
  glm::vec3 direction{0.0f, 0.0f, 1.0f}; // need not be unit length; t is in its units
  float tMax = std::numeric_limits<float>::infinity();
};

// A ray prepared for traversal. Direction components below 2^-100 are flushed to zero, so that
// 1 / d stays finite for the rest; zero components are handled by their own branch (the ray
// lies in the slab or misses it), never through 0 * inf.
struct RayContext {
  glm::vec3 origin;
  glm::vec3 direction;
  glm::vec3 invDirection;
  std::array<int, 3> negative; // 1 where the direction component is < 0
  bool hasZeroComponent = false;
  float tMin, tMax;
#if BT_SSE_NODE_TEST
  __m128 origin4, invDirection4; // (x, y, z, 0): the box tests' lanes (bvh/ray_brush.h)
#endif

  RayContext() = default; // a packet's slot (ray_packet.cpp), filled before use
  explicit RayContext(const Ray& ray) : origin(ray.origin), direction(ray.direction), tMin(ray.tMin), tMax(ray.tMax) {
    for (int a = 0; a < 3; ++a) {
      if (std::abs(direction[a]) < 0x1p-100f) direction[a] = 0.0f;
      hasZeroComponent |= direction[a] == 0.0f;
      invDirection[a] = direction[a] != 0.0f ? 1.0f / direction[a] : 0.0f;
      negative[a] = direction[a] < 0.0f ? 1 : 0;
    }
#if BT_SSE_NODE_TEST
    origin4 = _mm_setr_ps(origin.x, origin.y, origin.z, 0.0f);
    invDirection4 = _mm_setr_ps(invDirection.x, invDirection.y, invDirection.z, 0.0f);
#endif
  }
};

} // namespace bt
