// The partition step of the binned SAH builder (see builder.h): a node's boxes moved to the
// other buffer, left of the split first.
#pragma once

#include "bvh/binned_sah/binning.h"

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

// Partition of src[0, n): the boxes left of the split go to leftDst on, in their input order,
// the others to rightDst on, in input order too, or, for a sampled split, from rightDst
// backwards (where the bins did not count every box, the left side's size is known only at
// the end; the order still depends on the boxes alone). Returns the left side's count.
// A binned split has its children's bounds from the bins; a sampled one grows them here, index
// [1] the left child's, [0] the right's. The children's centroid bounds are left to the children
// that bin (see centroidBoundsOf()): most children are small subtrees, which need none.
//
// The bounds are grown in registers for both sides at once: a box counts for one side by adding
// 0 to it, for the other by adding infinity (so that min and max ignore it). Growing
// bounds[isLeft] in memory instead makes each box wait for the previous one's store.
template <SplitKind Kind>
uint32_t partition(const BoxRef* src, BoxRef* leftDst, BoxRef* rightDst, uint32_t n, const Split& split, Box4 bounds[2]) {
  constexpr ptrdiff_t rightStep = Kind == SplitKind::kSampled ? -1 : 1;
  uint32_t left = 0, right = 0;
  const __m128i firstRightBin = _mm_set1_epi32(split.lastLeftBin + 1);
  const __m128 ignoreUnless[2] = {_mm_set1_ps(kFloatInf), _mm_setzero_ps()}; // [isLeft]: + for left
  Box4 leftBox = bounds[1], rightBox = bounds[0];
  for (uint32_t i = 0; i < n; ++i) {
    const __m128 lo = src[i].lo(), hi = src[i].hi(), c = _mm_add_ps(lo, hi);
    const __m128 leftLanes = _mm_castsi128_ps(_mm_cmpgt_epi32(firstRightBin, split.mapping.bins(c)));
    const uint32_t isLeft = (_mm_movemask_ps(leftLanes) >> split.axis) & 1;
    (isLeft ? leftDst[left] : rightDst[rightStep * right]) = src[i];
    left += isLeft;
    right += 1 - isLeft;
    if constexpr (Kind != SplitKind::kBinned) {
      const __m128 toLeft = ignoreUnless[isLeft], toRight = ignoreUnless[1 - isLeft];
      leftBox.grow(_mm_add_ps(lo, toLeft), _mm_sub_ps(hi, toLeft));
      rightBox.grow(_mm_add_ps(lo, toRight), _mm_sub_ps(hi, toRight));
    }
  }
  bounds[1] = leftBox, bounds[0] = rightBox;
  return left;
}

// Partitions src[0, n) into dst[0, n) (see above); returns the left child's box count.
uint32_t partition(const BoxRef* src, BoxRef* dst, uint32_t n, const Split& split, Box4 bounds[2]) {
  if (split.kind == SplitKind::kSampled) return partition<SplitKind::kSampled>(src, dst, dst + n - 1, n, split, bounds);
  bounds[1] = split.leftBounds, bounds[0] = split.rightBounds;
  return partition<SplitKind::kBinned>(src, dst, dst + split.leftCount, n, split, bounds);
}

} // namespace
} // namespace bt::BT_SAH_ISA
