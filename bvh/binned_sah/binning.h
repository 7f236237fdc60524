// Binning (Wald 2007) for the binned SAH builder (see builder.h): a node's boxes counted into
// bins along the three axes at once, and the cheapest plane between bins.
#pragma once

#include "bvh/binned_sah/simd_box.h"

#include <cstddef>

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

constexpr int kMaxBins = 256;
constexpr uint32_t kTwoBinSetsMin = 64; // see binBoxes()

// Maps doubled centroids to bins, all three axes at once. The partition step calls the same
// function, so a box always lands on the side its bin was counted on.
struct BinMapping {
  __m128 origin;
  __m128 scale;   // 0 on an axis whose centroids all coincide
  __m128 lastBin; // binCount - 1

  // (c - origin) * scale clamped to [0, binCount - 1], truncated. A NaN (0 * inf, for an
  // extent so small that its scale overflows) comes out of _mm_max_ps as 0.
  __m128i bins(__m128 centroid2) const {
    const __m128 f = _mm_mul_ps(_mm_sub_ps(centroid2, origin), scale);
    return _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), lastBin));
  }
};

enum class SplitKind {
  kBinned,  // left = bin <= lastLeftBin, every box binned
  kSampled, // left = bin <= lastLeftBin, a sample of the boxes binned (see sampleStrideFor())
};

struct Split {
  int axis = -1; // -1: no split found (all centroids coincide)
  SplitKind kind = SplitKind::kBinned;
  int lastLeftBin = 0;
  uint32_t leftCount = 0; // of a sampled split, the sample's; the partition counts the boxes
  double childCost = 0.0; // area(left) * count(left) + area(right) * count(right), half-areas
  BinMapping mapping{};
  Box4 leftBounds, rightBounds; // kBinned only: the children's bounds, from the bins
};

// Bins of one node, the three axes side by side: box[a][b] and count[b][a] are bin b of axis a.
// Raw storage, so that only the bins in use are cleared. A box's three bins are addressed from
// one number each, the bin times 16 bytes (a row of count): box[a] is 32 bytes a bin, so that
// both are an addressing mode away from it, with no index arithmetic per box.
struct Bins {
  struct Bounds {
    __m128 min, max;
  };
  Bounds box[3][kMaxBins];
  alignas(16) int32_t count[kMaxBins][4];

  void clear(int binCount) {
    const Bounds empty{_mm_set1_ps(kFloatMax), _mm_set1_ps(-kFloatMax)};
    for (int b = 0; b < binCount; ++b) { // one loop: a call to memset for the counts cost more
      box[0][b] = box[1][b] = box[2][b] = empty;
      _mm_store_si128(reinterpret_cast<__m128i*>(count[b]), _mm_setzero_si128());
    }
  }
  // Adds lo, hi to bin rowOffset / 16 of `axis`.
  void add(uint32_t rowOffset, int axis, __m128 lo, __m128 hi) {
    static_assert(sizeof(Bounds) == 2 * sizeof(count[0]));
    Bounds& b = *reinterpret_cast<Bounds*>(reinterpret_cast<char*>(box[axis]) + 2 * size_t{rowOffset});
    b.min = _mm_min_ps(b.min, lo);
    b.max = _mm_max_ps(b.max, hi);
    ++*reinterpret_cast<int32_t*>(reinterpret_cast<char*>(&count[0][axis]) + rowOffset);
  }
  void add(const BoxRef& ref, const BinMapping& mapping) {
    const __m128 lo = ref.lo(), hi = ref.hi();
    const __m128i rowOffset = _mm_slli_epi32(mapping.bins(_mm_add_ps(lo, hi)), 4);
    add(static_cast<uint32_t>(_mm_cvtsi128_si32(rowOffset)), 0, lo, hi);
    add(static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_shuffle_epi32(rowOffset, 0x55))), 1, lo, hi);
    add(static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_shuffle_epi32(rowOffset, 0xaa))), 2, lo, hi);
  }
  void merge(const Bins& other, int binCount) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < binCount; ++b) {
        box[a][b].min = _mm_min_ps(box[a][b].min, other.box[a][b].min);
        box[a][b].max = _mm_max_ps(box[a][b].max, other.box[a][b].max);
      }
    }
    for (int b = 0; b < binCount; ++b)
      _mm_store_si128(reinterpret_cast<__m128i*>(count[b]),
                      _mm_add_epi32(_mm_load_si128(reinterpret_cast<const __m128i*>(count[b])),
                                    _mm_load_si128(reinterpret_cast<const __m128i*>(other.count[b]))));
  }
};

// The bin mapping of a node whose doubled centroids span `centroids`.
BinMapping binMappingFor(const Box4& centroids, int binCount) {
  const __m128 extent = _mm_sub_ps(centroids.max, centroids.min);
  // One division for the three axes; 0 where the extent is not positive (lane 3 among them).
  const __m128 positive = _mm_cmpgt_ps(extent, _mm_setzero_ps());
  const __m128 scale = _mm_and_ps(positive, _mm_div_ps(_mm_set1_ps(static_cast<float>(binCount)), extent));
  return {centroids.min, scale, _mm_set1_ps(static_cast<float>(binCount - 1))};
}

// Bins n boxes, boxes[0], boxes[stride], ..., boxes[(n - 1) * stride], into `bins` (cleared here).
void binBoxes(const BoxRef* boxes, uint32_t n, ptrdiff_t stride, const BinMapping& mapping, int binCount, Bins& bins) {
  // Neighbouring boxes tend to fall in the same bins, and each add waits for the previous one's
  // store to that bin; two sets of bins, for even and odd boxes, halve those chains where a
  // node has enough boxes to pay for merging them.
  bins.clear(binCount);
  uint32_t i = 0;
  if (n >= kTwoBinSetsMin) {
    Bins oddBins;
    oddBins.clear(binCount);
    for (; i + 1 < n; i += 2, boxes += 2 * stride) {
      bins.add(boxes[0], mapping);
      oddBins.add(boxes[stride], mapping);
    }
    bins.merge(oddBins, binCount);
  }
  for (; i < n; ++i, boxes += stride) bins.add(boxes[0], mapping);
}

// Binned SAH split of a node of n boxes from its bins (Wald 2007). For each candidate plane,
// the cost of the three axes is computed in the lanes of one register; `leftCost` keeps the
// prefix costs.
Split bestBinnedSplit(const Bins& bins, uint32_t n, const BinMapping& mapping, int binCount) {
  Split best;
  best.kind = SplitKind::kBinned;
  best.mapping = mapping;
  // Left of plane b: bins [0, b]; right: bins (b, binCount).
  __m128 leftCost[kMaxBins];
  Box4 box[3];
  __m128i count = _mm_setzero_si128();
  for (int b = 0; b < binCount - 1; ++b) {
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) box[a].grow(bins.box[a][b].min, bins.box[a][b].max);
    count = _mm_add_epi32(count, _mm_load_si128(reinterpret_cast<const __m128i*>(bins.count[b])));
    leftCost[b] = _mm_mul_ps(halfAreas(box[0], box[1], box[2]), _mm_cvtepi32_ps(count));
  }
  const __m128i total = _mm_set1_epi32(static_cast<int32_t>(n));
  __m128 bestCost = _mm_set1_ps(kFloatInf);
  __m128i bestBin = _mm_setzero_si128(), found = _mm_setzero_si128();
  box[0] = box[1] = box[2] = Box4{};
  count = _mm_setzero_si128();
  for (int b = binCount - 1; b > 0; --b) {
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) box[a].grow(bins.box[a][b].min, bins.box[a][b].max);
    count = _mm_add_epi32(count, _mm_load_si128(reinterpret_cast<const __m128i*>(bins.count[b])));
    const __m128 cost = _mm_add_ps(leftCost[b - 1], _mm_mul_ps(halfAreas(box[0], box[1], box[2]), _mm_cvtepi32_ps(count)));
    // Both sides must hold boxes; lane 3 never does (its counts stay 0).
    const __m128i valid = _mm_and_si128(_mm_cmpgt_epi32(count, _mm_setzero_si128()), _mm_cmplt_epi32(count, total));
    const __m128i better = _mm_and_si128(valid, _mm_castps_si128(_mm_cmplt_ps(cost, bestCost)));
    bestCost = _mm_or_ps(_mm_and_ps(_mm_castsi128_ps(better), cost), _mm_andnot_ps(_mm_castsi128_ps(better), bestCost));
    bestBin = _mm_or_si128(_mm_and_si128(better, _mm_set1_epi32(b - 1)), _mm_andnot_si128(better, bestBin));
    found = _mm_or_si128(found, better);
  }
  best.axis = cheapestAxis(bestCost, found);
  if (best.axis < 0) return best;
  best.lastLeftBin = laneOf(bestBin, best.axis);
  for (int b = 0; b <= best.lastLeftBin; ++b) {
    best.leftCount += bins.count[b][best.axis];
    best.leftBounds.grow(bins.box[best.axis][b].min, bins.box[best.axis][b].max);
  }
  for (int b = best.lastLeftBin + 1; b < binCount; ++b) best.rightBounds.grow(bins.box[best.axis][b].min, bins.box[best.axis][b].max);
  best.childCost = kSahBrushCost * laneOf(bestCost, best.axis);
  return best;
}

// The binned split of boxes[0, n), from every stride-th box (see sampleStrideFor()).
[[gnu::noinline]] Split findBinnedSplit(const BoxRef* boxes, uint32_t n, uint32_t stride, const Box4& centroids, int binCount) {
  const BinMapping mapping = binMappingFor(centroids, binCount);
  const uint32_t samples = (n + stride - 1) / stride;
  Bins bins;
  binBoxes(boxes, samples, stride, mapping, binCount, bins);
  Split split = bestBinnedSplit(bins, samples, mapping, binCount);
  split.kind = stride > 1 ? SplitKind::kSampled : SplitKind::kBinned;
  return split;
}

Box4 boundsOf(const BoxRef* boxes, uint32_t n) {
  Box4 bounds;
  for (uint32_t i = 0; i < n; ++i) bounds.grow(boxes[i].lo(), boxes[i].hi());
  return bounds;
}

// The bounds of the boxes' doubled centroids, which map them to bins. Two sets of bounds, for
// even and odd boxes, halve the chains of min and max that each box waits for.
Box4 centroidBoundsOf(const BoxRef* boxes, uint32_t n) {
  Box4 even, odd;
  uint32_t i = 0;
  for (; i + 1 < n; i += 2) {
    const __m128 c0 = boxes[i].centroid2(), c1 = boxes[i + 1].centroid2();
    even.grow(c0, c0);
    odd.grow(c1, c1);
  }
  if (i < n) even.grow(boxes[i].centroid2(), boxes[i].centroid2());
  even.grow(odd);
  return even;
}

} // namespace
} // namespace bt::BT_SAH_ISA
