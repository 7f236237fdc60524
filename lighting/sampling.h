// Random numbers and sampling routines of both tracers, GLSL-portable: a per-sample PCG
// stream seeded from (pixel, sample index, seed), so an image depends only on those.
#pragma once

#include "shaders/light_constants.glsl" // BT_PI, shared with the shaders

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>

namespace bt {

inline constexpr float kPi = BT_PI;

// PCG-RXS-M-XS hash (Jarzynski & Olano, "Hash Functions for GPU Rendering", 2020).
inline uint32_t pcgHash(uint32_t v) {
  const uint32_t state = v * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

struct Rng {
  uint32_t state = 0;

  // Uniform in [0, 1): 24 random bits, exactly representable as a float.
  float next() {
    state = state * 747796405u + 2891336453u;
    const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return float(((word >> 22u) ^ word) >> 8) * (1.0f / 16777216.0f);
  }
  glm::vec2 next2() {
    const float a = next();
    return {a, next()};
  }
};

inline Rng pixelRng(uint32_t x, uint32_t y, uint32_t sample, uint32_t seed) {
  return Rng{pcgHash(x ^ pcgHash(y ^ pcgHash(sample ^ pcgHash(seed))))};
}

// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
inline void basisAround(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

inline glm::vec3 toWorld(const glm::vec3& local, const glm::vec3& n) {
  glm::vec3 t, b;
  basisAround(n, t, b);
  return local.x * t + local.y * b + local.z * n;
}

// Cosine-weighted hemisphere around n; pdf = cos / pi.
inline glm::vec3 sampleCosineHemisphere(const glm::vec3& n, glm::vec2 u) {
  const float r = std::sqrt(u.x);
  const float phi = 2.0f * kPi * u.y;
  const glm::vec3 local{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x))};
  return toWorld(local, n);
}

// Uniform over the hemisphere around n; pdf = 1 / (2 pi).
inline glm::vec3 sampleUniformHemisphere(const glm::vec3& n, glm::vec2 u) {
  const float z = u.x;
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return toWorld({r * std::cos(phi), r * std::sin(phi), z}, n);
}

// Uniform inside the cone of half-angle `halfAngle` around axis; for soft sun shadows.
inline glm::vec3 sampleCone(const glm::vec3& axis, float halfAngle, glm::vec2 u) {
  const float cosMax = std::cos(halfAngle);
  const float z = 1.0f - u.x * (1.0f - cosMax);
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * u.y;
  return toWorld({r * std::cos(phi), r * std::sin(phi), z}, axis);
}

// Uniform on a triangle (barycentric square-root warp).
inline glm::vec3 sampleTriangle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, glm::vec2 u) {
  const float su = std::sqrt(u.x);
  return a * (1.0f - su) + b * (su * (1.0f - u.y)) + c * (su * u.y);
}

inline float powerHeuristic(float a, float b) {
  const float a2 = a * a;
  return a2 / (a2 + b * b);
}

} // namespace bt
