// The small-subtree sweep of the binned SAH builder (see builder.h): subtrees of a few boxes
// built by exact sweeps over their sorted centroids instead of bins.
#pragma once

#include "bvh/binned_sah/simd_box.h"

#ifndef BT_SAH_ISA
#error "include from a binned_sah_<isa>.cpp, which names the instruction set's namespace"
#endif

namespace bt::BT_SAH_ISA {
namespace {

// Subtrees this small are built by exact sweeps over their sorted centroids instead of bins (see
// SmallBoxes): sorting a handful of boxes costs less than clearing and sweeping 3 x binCount
// bins, and the deep levels, where bins are coarsest relative to the boxes, are where binning
// loses most.
constexpr uint32_t kSmallSubtreeMax = 8;

// Subtrees of kSmallSubtreeMax boxes or fewer, most of the tree's nodes, are built from their
// boxes loaded once into registers and sorted once along each axis: each node's split is an
// exact sweep over its sorted boxes, and its children's sorted lists are its own, filtered. The
// boxes are never partitioned through the BoxRef buffers again. This makes the tree that sorting
// and partitioning each node anew would make: boxes with equal centroids keep their order in
// the node, which a stable partition keeps, and every cost is computed in the same order.

// The boxes of a small subtree, slot s holding its root's s-th box.
struct SmallBoxes {
  __m128 lo[kSmallSubtreeMax], hi[kSmallSubtreeMax];
  alignas(16) float centroid2[kSmallSubtreeMax][4]; // lane 3 zero
  uint32_t index[kSmallSubtreeMax];
};

// A node of a small subtree: its boxes' slots in node order (the order that partitioning them
// would have left them in, which its leaf keeps), and sorted along each axis by doubled
// centroid, then node order.
struct SmallNode {
  uint32_t count;
  uint8_t slots[kSmallSubtreeMax];
  uint8_t sorted[3][kSmallSubtreeMax];
};

// The exact SAH split of a small node of three or more boxes: the plane after sorted[axis][0,
// leftCount).
struct SmallSplit {
  int axis = -1; // -1: no split (all centroids coincide)
  uint32_t leftCount = 0;
  double childCost = 0.0; // as Split::childCost
};

// Loads a small subtree's N boxes, in the order they lie in `refs`, and sorts them by rank,
// all three axes at once: slot i goes to the number of slots before it in (centroid, slot)
// order. N^2 compares cost less than the mispredicted branches of an insertion sort.
template <uint32_t N> SmallNode loadSmallSubtree(const BoxRef* refs, SmallBoxes& boxes) {
  SmallNode node;
  node.count = N;
  __m128 centroid[N];
#pragma GCC unroll 8
  for (uint32_t i = 0; i < N; ++i) {
    boxes.lo[i] = refs[i].lo(), boxes.hi[i] = refs[i].hi();
    centroid[i] = _mm_add_ps(boxes.lo[i], boxes.hi[i]);
    _mm_store_ps(boxes.centroid2[i], centroid[i]);
    boxes.index[i] = refs[i].index;
    node.slots[i] = static_cast<uint8_t>(i);
  }
#pragma GCC unroll 8
  for (uint32_t i = 0; i < N; ++i) {
    __m128i rank = _mm_setzero_si128(); // minus the count, as a true compare is -1
#pragma GCC unroll 8
    for (uint32_t j = 0; j < i; ++j) rank = _mm_add_epi32(rank, _mm_castps_si128(_mm_cmple_ps(centroid[j], centroid[i])));
#pragma GCC unroll 8
    for (uint32_t j = i + 1; j < N; ++j) rank = _mm_add_epi32(rank, _mm_castps_si128(_mm_cmplt_ps(centroid[j], centroid[i])));
    alignas(16) int32_t r[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(r), rank);
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) node.sorted[a][-r[a]] = static_cast<uint8_t>(i);
  }
  return node;
}

// The exact SAH split of a small node of M boxes: every plane between consecutive distinct
// centroids, the three axes side by side in the lanes of one register (as bestBinnedSplit()).
// M is a template parameter so that every loop is unrolled: in nodes this small, the
// mispredicted exits of loops that run a node's count of times cost more than the sweep.
template <uint32_t M> SmallSplit findSmallSplit(const SmallBoxes& boxes, const SmallNode& node) {
  const auto& sorted = node.sorted;
  // rightCost[i]: sorted[a][i, M) on the right.
  __m128 rightCost[M];
  Box4 box[3];
#pragma GCC unroll 8
  for (uint32_t i = M - 1; i >= 1; --i) {
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) box[a].grow(boxes.lo[sorted[a][i]], boxes.hi[sorted[a][i]]);
    rightCost[i] = _mm_mul_ps(halfAreas(box[0], box[1], box[2]), _mm_set1_ps(static_cast<float>(M - i)));
  }
  __m128 bestCost = _mm_set1_ps(kFloatInf);
  __m128i bestIndex = _mm_setzero_si128(), found = _mm_setzero_si128();
  box[0] = box[1] = box[2] = Box4{};
#pragma GCC unroll 8
  for (uint32_t i = 1; i < M; ++i) { // left = sorted[a][0, i)
#pragma GCC unroll 3
    for (int a = 0; a < 3; ++a) box[a].grow(boxes.lo[sorted[a][i - 1]], boxes.hi[sorted[a][i - 1]]);
    const __m128 cost = _mm_add_ps(_mm_mul_ps(halfAreas(box[0], box[1], box[2]), _mm_set1_ps(static_cast<float>(i))), rightCost[i]);
    // Equal centroids cannot be separated by a plane; lane 3 compares 0 with 0.
    const __m128 previous =
        _mm_setr_ps(boxes.centroid2[sorted[0][i - 1]][0], boxes.centroid2[sorted[1][i - 1]][1], boxes.centroid2[sorted[2][i - 1]][2], 0.0f);
    const __m128 next =
        _mm_setr_ps(boxes.centroid2[sorted[0][i]][0], boxes.centroid2[sorted[1][i]][1], boxes.centroid2[sorted[2][i]][2], 0.0f);
    const __m128i better = _mm_castps_si128(_mm_and_ps(_mm_cmpneq_ps(previous, next), _mm_cmplt_ps(cost, bestCost)));
    bestCost = _mm_or_ps(_mm_and_ps(_mm_castsi128_ps(better), cost), _mm_andnot_ps(_mm_castsi128_ps(better), bestCost));
    bestIndex = _mm_or_si128(_mm_and_si128(better, _mm_set1_epi32(static_cast<int32_t>(i))), _mm_andnot_si128(better, bestIndex));
    found = _mm_or_si128(found, better);
  }
  SmallSplit best;
  best.axis = cheapestAxis(bestCost, found);
  if (best.axis < 0) return best;
  best.leftCount = static_cast<uint32_t>(laneOf(bestIndex, best.axis));
  best.childCost = kSahBrushCost * laneOf(bestCost, best.axis);
  return best;
}

// Splits a small node of M boxes into children[1] (left) and children[0] (right), each keeping
// its boxes' node order and sorted order, and grows their bounds, bounds[1] and bounds[0], as
// partition() does.
template <uint32_t M>
void splitSmallNode(const SmallBoxes& boxes, const SmallNode& node, const SmallSplit& split, SmallNode children[2], Box4 bounds[2]) {
  const __m128 ignoreUnless[2] = {_mm_set1_ps(kFloatInf), _mm_setzero_ps()}; // [isLeft]: + for left
  uint8_t isLeft[kSmallSubtreeMax];                                          // by slot
  Box4 leftBox, rightBox;
#pragma GCC unroll 8
  for (uint32_t i = 0; i < M; ++i) {
    const uint32_t slot = node.sorted[split.axis][i], left = i < split.leftCount ? 1 : 0;
    isLeft[slot] = static_cast<uint8_t>(left);
    const __m128 toLeft = ignoreUnless[left], toRight = ignoreUnless[1 - left];
    leftBox.grow(_mm_add_ps(boxes.lo[slot], toLeft), _mm_sub_ps(boxes.hi[slot], toLeft));
    rightBox.grow(_mm_add_ps(boxes.lo[slot], toRight), _mm_sub_ps(boxes.hi[slot], toRight));
  }
  bounds[1] = leftBox, bounds[0] = rightBox;
  children[1].count = split.leftCount;
  children[0].count = M - split.leftCount;
  // Filters a list of the node's slots into the children's lists, in its order.
  const auto filter = [&](const uint8_t* from, uint8_t* toLeft, uint8_t* toRight) {
    uint32_t left = 0, right = 0;
#pragma GCC unroll 8
    for (uint32_t i = 0; i < M; ++i) {
      const uint32_t slot = from[i], goesLeft = isLeft[slot];
      (goesLeft ? toLeft[left] : toRight[right]) = static_cast<uint8_t>(slot);
      left += goesLeft;
      right += 1 - goesLeft;
    }
  };
  filter(node.slots, children[1].slots, children[0].slots);
  // Children of one or two boxes sweep nothing (see buildSmallNode()): those of a node of three
  // boxes never need sorted lists, nor those of a node of four split two and two.
  if (M > 4 || (M == 4 && split.leftCount != 2))
    for (int a = 0; a < 3; ++a) filter(node.sorted[a], children[1].sorted[a], children[0].sorted[a]);
}

} // namespace
} // namespace bt::BT_SAH_ISA
