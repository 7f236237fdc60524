// Random numbers and sampling routines of both tracers, GLSL-portable: a per-sample PCG
// stream seeded from (pixel, sample index, seed), so an image depends only on those, and for
// physical mode's main decisions a low-discrepancy sequence per pixel (pixelSampler).
#pragma once

#include "shaders/light_constants.glsl" // BT_PI, shared with the shaders

#include <glm/geometric.hpp>
#include <glm/integer.hpp> // bitfieldReverse, as GLSL's
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

// A random base-2 nested permutation (Owen scrambling) of the bits of v, from the most
// significant down, by `seed`: Burley 2020, "Practical Hash-based Owen Scrambling", its
// improved Laine-Karras hash on the reversed bits.
// owenScrambleReversed: the same given bitfieldReverse(v), the reversal that the caller's own
// cancels left out.
inline uint32_t owenScrambleReversed(uint32_t reversed, uint32_t seed) {
  uint32_t v = reversed + seed;
  v ^= v * 0x6c50b47cu;
  v ^= v * 0xb82f1e52u;
  v ^= v * 0xc7afe638u;
  v ^= v * 0x8d22f6e6u;
  return glm::bitfieldReverse(v);
}
inline uint32_t owenScramble(uint32_t v, uint32_t seed) {
  return owenScrambleReversed(glm::bitfieldReverse(v), seed);
}

// Sobol's second dimension at `index` (the first is bitfieldReverse(index)). Its direction numbers
// v(k+1) = v(k) ^ v(k) >> 1 from the top bit make its matrix Pascal's triangle mod 2, so bit
// 31 - j of the result is the XOR of the index bits k whose bits hold all of j's (Lucas): a
// superset sum over the bit positions, five shifts instead of a loop over the index's bits.
inline uint32_t sobolSecondReversed(uint32_t index) { // sobolSecond before its final reversal
  index ^= (index >> 1u) & 0x55555555u;
  index ^= (index >> 2u) & 0x33333333u;
  index ^= (index >> 4u) & 0x0f0f0f0fu;
  index ^= (index >> 8u) & 0x00ff00ffu;
  index ^= (index >> 16u) & 0x0000ffffu;
  return index;
}
inline uint32_t sobolSecond(uint32_t index) {
  return glm::bitfieldReverse(sobolSecondReversed(index));
}

// Dimension `dim` of sample `index` of a pixel's sequence (pbrt-v4's PaddedSobolSampler, with
// Burley's shuffle): dimensions are taken in pairs, each pair the first two Sobol dimensions,
// with the pixel's own shuffle of the sample order (an Owen scramble of the index: the first
// 2^k samples stay a 2^k-point net, so every power-of-two count is stratified) and its own
// scramble of the values, so that pairs and pixels are uncorrelated. In [0, 1), 24 bits.
// sobolPair: both of an even dimension's pair at once (the same numbers, half the hashing).
inline uint32_t sobolPairSeed(uint32_t pixelSeed, uint32_t dim) {
  return pcgHash(pixelSeed ^ pcgHash(dim >> 1u));
}
inline float sobolValue(uint32_t sobol, uint32_t pairSeed, uint32_t component) {
  return float(owenScramble(sobol, pcgHash(pairSeed + 1u + component)) >> 8) * (1.0f / 16777216.0f);
}
// sobolValue(bitfieldReverse(reversed), ...) without the two reversals that cancel, the same bits
// (shaders/sampling.glsl keeps the long form): the reversals were a third of a draw's work.
inline float sobolValueReversed(uint32_t reversed, uint32_t pairSeed, uint32_t component) {
  return float(owenScrambleReversed(reversed, pcgHash(pairSeed + 1u + component)) >> 8) * (1.0f / 16777216.0f);
}
inline float sobolDraw(uint32_t pixelSeed, uint32_t index, uint32_t dim) {
  const uint32_t seed = sobolPairSeed(pixelSeed, dim);
  const uint32_t shuffled = owenScramble(index, seed);
  return (dim & 1u) == 0u ? sobolValueReversed(shuffled, seed, 0u) : sobolValueReversed(sobolSecondReversed(shuffled), seed, 1u);
}
inline glm::vec2 sobolPair(uint32_t pixelSeed, uint32_t index, uint32_t dim) {
  const uint32_t seed = sobolPairSeed(pixelSeed, dim);
  const uint32_t shuffled = owenScramble(index, seed);
  return {sobolValueReversed(shuffled, seed, 0u), sobolValueReversed(sobolSecondReversed(shuffled), seed, 1u)};
}

struct Rng {
  uint32_t state = 0;
  // A pixelSampler's: the pixel's scramble (the top 22 bits) and, in the low BT_DIM_BITS, the
  // dimension of the pixel's scrambled Sobol sequence (sobolDraw) the next draw takes, or
  // BT_DIM_PCG: then it takes the PCG stream. One word because the GL tracer carries it in a
  // register along the whole path (its sample index is the dispatch's). A pixelRng draws from
  // PCG only.
  uint32_t seedDim = BT_DIM_PCG;
  uint32_t sampleIndex = 0;
  bool lowDiscrepancy = false;

  uint32_t dim() const { return seedDim & BT_DIM_PCG; }
  // Uniform in [0, 1): 24 random bits, exactly representable as a float.
  float next() {
    if (const uint32_t d = dim(); d != BT_DIM_PCG) {
      ++seedDim;
      return sobolDraw(seedDim >> BT_DIM_BITS, sampleIndex, d);
    }
    state = state * 747796405u + 2891336453u;
    const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return float(((word >> 22u) ^ word) >> 8) * (1.0f / 16777216.0f);
  }
  glm::vec2 next2() {
    if (dim() != BT_DIM_PCG) {
      seedDim += dim() & 1u; // a Sobol pair, stratified in 2D
      const glm::vec2 u = sobolPair(seedDim >> BT_DIM_BITS, sampleIndex, dim());
      seedDim += 2u;
      return u;
    }
    const float a = next();
    return {a, next()};
  }
  // The draws that follow take dimensions offset, offset + 1, ... of the block of the path's
  // surface `depth` (BT_DIM_*); no-op for a pixelRng.
  void at(int depth, uint32_t offset) {
    if (lowDiscrepancy) seedDim = (seedDim & ~BT_DIM_PCG) | (BT_DIM_FIRST_SURFACE + uint32_t(depth) * BT_DIMS_PER_SURFACE + offset);
  }
  // The draws that follow take the PCG stream.
  void atPcg() { seedDim |= BT_DIM_PCG; }
};

inline Rng pixelRng(uint32_t x, uint32_t y, uint32_t sample, uint32_t seed) {
  return Rng{pcgHash(x ^ pcgHash(y ^ pcgHash(sample ^ pcgHash(seed))))};
}

// Physical mode's random numbers: pixelRng's stream, and the pixel's Sobol sequence for the
// draws the integrator places (Rng::at), starting at the camera's subpixel.
inline Rng pixelSampler(uint32_t x, uint32_t y, uint32_t sample, uint32_t seed) {
  Rng rng = pixelRng(x, y, sample, seed);
  rng.lowDiscrepancy = true;
  rng.seedDim = (pcgHash(x ^ pcgHash(y ^ pcgHash(pcgHash(seed) + 1u))) & ~BT_DIM_PCG) | BT_DIM_CAMERA;
  rng.sampleIndex = sample;
  return rng;
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
