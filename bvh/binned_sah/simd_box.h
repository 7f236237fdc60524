// SSE boxes for the binned SAH builder (see builder.h): a box as two __m128, the per-axis
// lanes the sweeps compare, and the record the builder partitions.
#pragma once

#include "bvh/sah_builder.h"

#include <immintrin.h>

#include <bit>
#include <cstdint>
#include <limits>

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

constexpr float kFloatMax = std::numeric_limits<float>::max();
constexpr float kFloatInf = std::numeric_limits<float>::infinity();

// The builder's inner loops work on SSE registers (x86-64 baseline): a box is two __m128
// with x, y, z in lanes 0-2; lane 3 is masked to zero before any arithmetic.
// A function, not a constant: a namespace-scope __m128 may be initialised at start-up, which in
// the AVX2 compilation (binned_sah_avx2.cpp) would run AVX2 code on any CPU.
inline __m128 xyzMask() {
  return _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
}

struct Box4 {
  __m128 min = _mm_set1_ps(kFloatMax);
  __m128 max = _mm_set1_ps(-kFloatMax);

  void grow(__m128 lo, __m128 hi) {
    min = _mm_min_ps(min, lo);
    max = _mm_max_ps(max, hi);
  }
  void grow(const Box4& b) { grow(b.min, b.max); }
  float halfArea() const {
    alignas(16) float e[4];
    _mm_store_ps(e, _mm_sub_ps(max, min));
    if (e[0] < 0.0f || e[1] < 0.0f || e[2] < 0.0f) return 0.0f; // empty
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
  Aabb aabb() const {
    alignas(16) float lo[4], hi[4];
    _mm_store_ps(lo, min);
    _mm_store_ps(hi, max);
    return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  }
};

// The half-areas of three boxes, one per lane (lane 3 is zero): the split sweeps evaluate the
// candidate planes of the three axes side by side. Meaningless (inf or NaN) for an empty box;
// the sweeps mask those lanes out.
inline __m128 halfAreas(const Box4& a, const Box4& b, const Box4& c) {
  __m128 x = _mm_sub_ps(a.max, a.min), y = _mm_sub_ps(b.max, b.min), z = _mm_sub_ps(c.max, c.min);
  __m128 w = _mm_setzero_ps();
  _MM_TRANSPOSE4_PS(x, y, z, w); // x now holds the three boxes' extents along X, and so on
  return _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, y), _mm_mul_ps(y, z)), _mm_mul_ps(z, x));
}

// One input box as the builder moves it around: bounds plus the input index, 32 bytes, so that
// partitioning copies whole records instead of chasing an index.
struct BoxRef {
  glm::vec3 min;
  uint32_t index;
  glm::vec3 max;
  uint32_t pad; // always 0: max loads as a box corner with lane 3 zero, no masking

  __m128 lo() const { return _mm_and_ps(_mm_loadu_ps(&min.x), xyzMask()); }
  __m128 hi() const { return _mm_loadu_ps(&max.x); }
  // Twice the centroid: binning only needs positions relative to each other.
  __m128 centroid2() const { return _mm_add_ps(lo(), hi()); }
  float centroid2(int axis) const { return min[axis] + max[axis]; } // == lane `axis` of the above
};

// Lane `axis` (0..3) of a per-axis SSE result.
float laneOf(__m128 v, int axis) {
  alignas(16) float lanes[4];
  _mm_store_ps(lanes, v);
  return lanes[axis];
}
int32_t laneOf(__m128i v, int axis) {
  alignas(16) int32_t lanes[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(lanes), v);
  return lanes[axis];
}

// The lowest-cost lane of the per-axis sweep results, first axis on equal cost; -1 when no lane
// is valid. Valid lanes hold finite or infinite costs, never NaN (the sweeps only keep a cost
// that compares less than the best so far). Without branches: which axis wins is a coin toss
// that a branch predictor loses half the time.
int cheapestAxis(__m128 cost, __m128i valid) {
  const __m128 validCost =
      _mm_or_ps(_mm_and_ps(_mm_castsi128_ps(valid), cost), _mm_andnot_ps(_mm_castsi128_ps(valid), _mm_set1_ps(kFloatInf)));
  __m128 lowest = _mm_min_ps(validCost, _mm_shuffle_ps(validCost, validCost, _MM_SHUFFLE(3, 0, 2, 1)));
  lowest = _mm_min_ps(lowest, _mm_shuffle_ps(validCost, validCost, _MM_SHUFFLE(3, 1, 0, 2)));
  // lowest holds the minimum of the three lanes in each of lanes 0-2.
  const int cheapest = _mm_movemask_ps(_mm_and_ps(_mm_cmpeq_ps(validCost, lowest), _mm_castsi128_ps(valid))) & 7;
  return cheapest == 0 ? -1 : std::countr_zero(static_cast<unsigned>(cheapest));
}

} // namespace
} // namespace bt::BT_SAH_ISA
