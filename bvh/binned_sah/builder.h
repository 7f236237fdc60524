// The binned SAH builder proper, included by sah_builder.cpp once per instruction set it is
// compiled for (inside namespace bt::sse2 and bt::avx2); see there. Not a header of its own.

namespace {

constexpr int kMaxBins = 256;
constexpr float kFloatMax = std::numeric_limits<float>::max();
constexpr float kFloatInf = std::numeric_limits<float>::infinity();
// Below this depth, nodes are split at the median along the widest centroid axis instead of by
// SAH, which bounds the depth at kMedianSplitDepth + log2(n) <= kBvhMaxDepth for n <= 2^24
// boxes. SAH trees of real levels stay well above it; only pathological inputs (geometric
// series of box sizes) reach it.
constexpr uint32_t kMedianSplitDepth = kBvhMaxDepth - 24;
// Subtrees of at least this many boxes go to the build's task queue, where an idle thread can
// take them; smaller ones are built by the thread that reached them. A task costs a lock, but
// the last subtrees, built while other threads have nothing left to take, are at most a few
// times this size: with 1024, two threads at 50k boxes waited for each other's last subtree.
constexpr uint32_t kTaskMinBoxes = 256;
// A build too small to hand out a few tasks of a few thousand boxes is not worth starting a
// thread for.
constexpr uint32_t kThreadsMinBoxes = 4096;
// Subtrees this small are built by exact sweeps over their sorted centroids instead of bins (see
// SmallBoxes): sorting a handful of boxes costs less than clearing and sweeping 3 x binCount
// bins, and the deep levels, where bins are coarsest relative to the boxes, are where binning
// loses most.
constexpr uint32_t kSmallSubtreeMax = 8;
constexpr uint32_t kMinBins = 8;                                 // see binCountFor()
constexpr uint32_t kTwoBinSetsMin = 64;                          // see binBoxes()
constexpr uint32_t kSampledBinningMin = 2048, kBinSamples = 512; // see sampleStrideFor()

// The builder's inner loops work on SSE registers (x86-64 baseline): a box is two __m128
// with x, y, z in lanes 0-2; lane 3 is masked to zero before any arithmetic.
// A function, not a constant: a namespace-scope __m128 may be initialised at start-up, which in
// the AVX2 compilation (see sah_builder.cpp) would run AVX2 code on any CPU.
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

// A node to build with its subtree: where it goes (see the slot layout in build()), which of the
// two BoxRef buffers holds its boxes, and their bounds.
struct NodeTask {
  uint32_t slot, descendants;
  uint32_t begin, end;
  uint32_t depth;
  int buffer;
  int owner; // the thread whose task queue its child tasks go to
  Box4 bounds;
};

// One thread's task queue. The thread takes its newest task, the deepest, whose boxes it has
// just partitioned and still has in cache; an idle thread steals the oldest, the biggest, so
// that steals are few and each thread mostly builds subtrees of its own.
// A ring buffer: queued tasks are subtrees that no thread has started, so they hold disjoint
// boxes, and at most n / kTaskMinBoxes are queued at once.
class TaskQueue {
public:
  explicit TaskQueue(size_t capacity) : tasks_(capacity) {}
  bool empty() const { return size_ == 0; }
  void push(const NodeTask& task) { tasks_[(oldest_ + size_++) % tasks_.size()] = task; }
  NodeTask take(bool newest) {
    --size_;
    if (newest) return tasks_[(oldest_ + size_) % tasks_.size()];
    const NodeTask& task = tasks_[oldest_];
    oldest_ = (oldest_ + 1) % tasks_.size();
    return task;
  }

private:
  std::vector<NodeTask> tasks_;
  size_t oldest_ = 0, size_ = 0;
};

// Top-down binned SAH build. Each node: find the split (binned over the three axes at once,
// from a sample of the boxes in big nodes, an exact sweep for a few boxes), decide by shouldSplit(), move the boxes to the other BoxRef
// buffer partitioned, recurse. Subtrees of kTaskMinBoxes or more go to the task queue of the
// thread that reached them, which the other threads steal from when theirs is empty (see
// TaskQueue); every choice depends on the boxes alone, never on which thread
// builds what, so the tree is the same for any thread count.
//
// Before the build, the same threads read the input boxes, chunk by chunk: done by one thread,
// that pass held the others idle. After it, the thread that finishes the last task squeezes the
// holes that tasks leave out of the slots, in place (see layOut()).
class BinnedSahBuilder {
public:
  BinnedSahBuilder(std::span<const Aabb> boxes, const SahBuildSettings& settings)
      : settings_(settings), input_(boxes), count_(static_cast<uint32_t>(boxes.size())) {
    settings_.binCount = std::clamp(settings_.binCount, 2, kMaxBins);
    settings_.leafSize = std::max(settings_.leafSize, 1);
    const int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
    threads_ = count_ < kThreadsMinBoxes ? 1 : std::max(threads, 1);
    // Uninitialised on purpose: every slot and entry is written before it is read.
    refs_[0].reset(new BoxRef[count_]);
    refs_[1].reset(new BoxRef[count_]);
    const size_t slotCount = count_ == 0 ? 0 : 2 * size_t{count_} - 1;
    order_.resize(count_);
    // The slots are the result, cut to the tree's size at the end (see build()). With threads,
    // the first thread sizes it while the others start (see sizeSlots()); everything the
    // threads use is allocated here, before they start: nothing they do can throw and leave the
    // others waiting at a barrier.
    if (threads_ == 1) {
      nodes_.resize(slotCount);
    } else {
      nodes_.reserve(slotCount);
    }
    slots_ = nodes_.data();
    // A hole per task at most (see build()). SAH trees of levels have about 2 n / kTaskMinBoxes
    // tasks (a node splits its boxes roughly in two); only pathological ones, splitting a few
    // boxes off at a time, have more, and these grow.
    const size_t maxTasks = 2 * size_t{count_} / kTaskMinBoxes + 1;
    holes_.reserve(maxTasks);
    holeEnds_.reserve(maxTasks);
    holeShifts_.reserve(maxTasks);
  }

  FlatBvh build() {
    if (count_ == 0) return {};
    // Slot layout while building: a node in slot s with n boxes owns the 2n - 2 slots from
    // `descendants` on for its subtree: its two children first, then the left child's
    // descendants, then the right child's. A subtree built by the thread that reached it is
    // built left before right, so the right child's descendants go right after the left
    // child's, wherever they end: that is the depth-first layout, without holes, and all of
    // it with one thread. A left child handed to the task queue gets all its 2 nL - 2 slots,
    // as its size is not known yet, and the right child's descendants go after them; a task
    // that uses fewer leaves a hole at the end of its slots. So every slot is known before
    // the subtrees are built, threads never share a counter, and the tree is the same for any
    // thread count. The final layout squeezes the holes out (see layOut()).
    if (threads_ == 1) {
      NodeTask root{0, 1, 0, count_, 0, 0, 0, {}};
      Box4 centroids; // left to the root, which bins (see partition())
      const uint32_t invalid = readBoxes(0, count_, root.bounds, centroids);
      if (invalid != kNoBox) throwInvalidBox(invalid);
      nodes_.resize(1 + buildNode(root)); // shrinks: no allocation
    } else {
      const uint32_t invalid = buildWithThreads();
      if (invalid != kNoBox) throwInvalidBox(invalid);
    }
    FlatBvh result;
    result.nodes = std::move(nodes_);
    result.order = std::move(order_);
    return result;
  }

private:
  static constexpr uint32_t kNoBox = std::numeric_limits<uint32_t>::max();
  // The threads split the root chunk by chunk (see buildWithThreads()): chunks of at least this
  // many boxes, and enough of them per thread that one thread can take over from a late one.
  static constexpr uint32_t kRootChunkMinBoxes = 2048;
  static constexpr uint32_t kRootChunksPerThread = 8;

  // Copies input boxes [begin, end) into refs_[0] and grows their bounds and centroid bounds.
  // Stops at the first box that is empty or has a non-finite bound and returns its index
  // (kNoBox when all are valid).
  uint32_t readBoxes(uint32_t begin, uint32_t end, Box4& bounds, Box4& centroids) {
    static_assert(sizeof(Aabb) == 24);
    const __m128 zero = _mm_setzero_ps();
    BoxRef* refs = refs_[0].get();
    for (uint32_t i = begin; i < end; ++i) {
      // An Aabb is six packed floats: min.xyz at 0, max.xyz at 12. Loading max from 8 on, as
      // (min.z, max.x, max.y, max.z), stays inside the box, also for the last one.
      const float* box = &input_[i].min.x;
      const __m128 lo = _mm_and_ps(_mm_loadu_ps(box), xyzMask());
      const __m128 hi = _mm_and_ps(_mm_shuffle_ps(_mm_loadu_ps(box + 2), _mm_loadu_ps(box + 2), _MM_SHUFFLE(3, 3, 2, 1)), xyzMask());
      // x - x is 0 for a finite x, NaN for an infinite or NaN one. Lane 3 is 0 in both.
      const __m128 finite = _mm_and_ps(_mm_cmpeq_ps(_mm_sub_ps(lo, lo), zero), _mm_cmpeq_ps(_mm_sub_ps(hi, hi), zero));
      if (_mm_movemask_ps(_mm_and_ps(finite, _mm_cmple_ps(lo, hi))) != 0xf) return i;
      _mm_storeu_ps(&refs[i].min.x, lo);
      _mm_storeu_ps(&refs[i].max.x, hi); // pad = lane 3 = 0
      refs[i].index = i;
      bounds.grow(lo, hi);
      const __m128 c = _mm_add_ps(lo, hi);
      centroids.grow(c, c);
    }
    return kNoBox;
  }

  [[noreturn]] void throwInvalidBox(uint32_t i) const {
    // Finite bounds keep every doubled centroid ordered (at worst +-inf, never NaN), which the
    // exact sweep's ranking and the partitions rely on.
    throw std::invalid_argument(input_[i].empty() ? "buildBinnedSah: empty box" : "buildBinnedSah: box with an infinite or NaN bound");
  }

  // The root split by all threads together, then its subtrees through the task queue. Alone, the
  // root's split (binning and partitioning every box) keeps the other threads idle for a sixth
  // of a two-thread build. Here the boxes are cut into chunks that the threads take one at a
  // time, in three stages: read (and check) them, bin them, partition them. The thread that
  // finishes a stage's last chunk does what joins the chunks (the root's bounds, the split from
  // the merged bins, the root's child tasks) and opens the next stage. No thread waits for
  // another to arrive: a helper that starts late (starting a thread takes a tenth of a
  // millisecond, more on a busy machine) finds chunks left or none, and one that is descheduled
  // holds up no more than its chunk. The merged bins are exactly those of one pass over all
  // boxes and each chunk's boxes keep their order, so the tree is the same as a one-thread
  // build's. Returns the first invalid box, kNoBox if none.
  uint32_t buildWithThreads() {
    // Queued tasks hold disjoint boxes, kTaskMinBoxes or more (the root's children may have
    // fewer), so a queue of n / kTaskMinBoxes + 2 never overflows.
    queues_.assign(threads_, TaskQueue(count_ / kTaskMinBoxes + 2));
    const uint32_t chunks = std::clamp<uint32_t>(count_ / kRootChunkMinBoxes, 1, kRootChunksPerThread * threads_);
    const auto chunkBegin = [&](uint32_t c) { return static_cast<uint32_t>(uint64_t{count_} * c / chunks); };
    const int binCount = binCountFor(count_);
    // Each thread's bins, cleared here as a thread may start too late to bin any chunk; and
    // each chunk's bin counts (binCount per chunk), which place its boxes in the partition.
    std::vector<Bins> bins(threads_);
    for (Bins& b : bins) b.clear(binCount);
    std::vector<std::array<int32_t, 4>> chunkCounts(size_t{chunks} * binCount);
    std::vector<std::array<Box4, 2>> chunkBounds(chunks);        // [bounds, centroids]
    std::vector<uint32_t> invalid(chunks);                       // first invalid box
    std::vector<uint32_t> leftBegin(chunks), rightBegin(chunks); // where the boxes go
    NodeTask root{0, 1, 0, count_, 0, 0, 0, {}};
    Box4 rootCentroids;
    uint32_t firstInvalid = kNoBox;
    BinMapping mapping{};
    Split split;
    bool together = false; // whether the threads split the root, or leave it to the task queue
    // The root's split counts as an unfinished task, so that work() waits for its children.
    unfinished_ = 1;

    enum Stage : int { kRead, kBin, kPartition, kBuilt };
    std::atomic<int> stage{kRead};
    std::array<std::atomic<uint32_t>, kBuilt> nextJob{}, jobsDone{};
    // Runs `job` on the jobs of stage s until none is left. The thread that finishes the last
    // one runs `join` and opens the next stage; the others wait for that (when `wait`).
    const auto runStage = [&](int thread, Stage s, uint32_t jobs, auto&& job, auto&& join, bool wait) {
      for (uint32_t j; (j = nextJob[s].fetch_add(1)) < jobs;) {
        job(thread, j);
        if (jobsDone[s].fetch_add(1) + 1 == jobs) {
          join();
          stage.store(s + 1);
          stage.notify_all();
        }
      }
      if (!wait) return;
      for (int now; (now = stage.load()) <= s;) stage.wait(now);
    };
    const auto readChunk = [&](int, uint32_t c) {
      invalid[c] = readBoxes(chunkBegin(c), chunkBegin(c + 1), chunkBounds[c][0], chunkBounds[c][1]);
    };
    const auto joinRead = [&] {
      for (uint32_t c = 0; c < chunks; ++c) {
        firstInvalid = std::min(firstInvalid, invalid[c]);
        root.bounds.grow(chunkBounds[c][0]);
        rootCentroids.grow(chunkBounds[c][1]);
      }
      mapping = binMappingFor(rootCentroids, binCount);
    };
    const BoxRef* src = refs_[root.buffer].get();
    BoxRef* dst = refs_[1 - root.buffer].get();
    const auto binChunk = [&](int thread, uint32_t c) {
      const uint32_t begin = chunkBegin(c), end = chunkBegin(c + 1);
      Bins chunkBins;
      binBoxes(src + begin, end - begin, 1, mapping, binCount, chunkBins);
      bins[thread].merge(chunkBins, binCount);
      std::memcpy(&chunkCounts[size_t{c} * binCount], chunkBins.count, sizeof(chunkCounts[0]) * binCount);
    };
    const auto joinSplit = [&] {
      Bins all = bins[0];
      for (int t = 1; t < threads_; ++t) all.merge(bins[t], binCount);
      split = bestBinnedSplit(all, count_, mapping, binCount);
      together = split.axis >= 0 && shouldSplit(count_, settings_.leafSize, root.bounds.halfArea(), split.childCost);
      if (!together) {
        // The root goes to the queue as an ordinary task, which takes over the unfinished count.
        std::lock_guard lock(mutex_);
        queues_[0].push(root);
        ++queuedTasks_;
        wake_.notify_one();
        return;
      }
      // Each chunk's boxes go after those of the chunks before it, on either side.
      uint32_t left = 0, right = split.leftCount;
      for (uint32_t c = 0; c < chunks; ++c) {
        leftBegin[c] = left, rightBegin[c] = right;
        uint32_t leftInChunk = 0;
        for (int b = 0; b <= split.lastLeftBin; ++b)
          leftInChunk += static_cast<uint32_t>(chunkCounts[size_t{c} * binCount + b][split.axis]);
        left += leftInChunk;
        right += chunkBegin(c + 1) - chunkBegin(c) - leftInChunk;
      }
    };
    const auto partitionChunk = [&](int, uint32_t c) {
      const uint32_t begin = chunkBegin(c), end = chunkBegin(c + 1);
      Box4 unused[2];
      partition<SplitKind::kBinned>(src + begin, dst + leftBegin[c], dst + rightBegin[c], end - begin, split, unused);
    };
    const auto joinPartition = [&] {
      waitForSlots();
      writeBounds(slots_[root.slot], root);
      NodeTask left{}, right{};
      setChildren(root, split.leftCount, left, right);
      right.descendants = left.descendants + 2 * split.leftCount - 2; // the left child is a task
      left.buffer = right.buffer = 1 - root.buffer;
      left.bounds = split.leftBounds, right.bounds = split.rightBounds;
      {
        std::lock_guard lock(mutex_);
        queues_[0].push(right);
        queues_[0].push(left);
        queuedTasks_ += 2;
        ++unfinished_; // two tasks in, the root's split out
      }
      wake_.notify_all();
    };
    const auto run = [&](int thread) {
      if (thread == 0) sizeSlots();
      runStage(thread, kRead, chunks, readChunk, joinRead, true);
      if (firstInvalid != kNoBox) return;
      runStage(thread, kBin, chunks, binChunk, joinSplit, true);
      if (together) runStage(thread, kPartition, chunks, partitionChunk, joinPartition, false);
      work(thread); // returns once the last task is done and the tree laid out
    };
    {
      std::vector<std::jthread> helpers;
      for (int t = 1; t < threads_; ++t) helpers.emplace_back(run, t);
      run(0);
    }
    return firstInvalid;
  }

  // With threads, the slots (the result's array) are sized by the first thread while the others
  // start on the root's split, which writes no slot until it joins. Zero-filling them, which
  // std::vector's resize() cannot be kept from, takes as long as a sixth of a 50k build (the
  // pages are fresh); done in the read stage, it held the other thread idle at its end. Within
  // the capacity reserved in the constructor, so it does not allocate.
  void sizeSlots() {
    nodes_.resize(2 * size_t{count_} - 1);
    slotsSized_.store(true);
    slotsSized_.notify_all();
  }
  // Called before a thread writes a slot.
  void waitForSlots() const { slotsSized_.wait(false); }

  // Takes tasks until every task, including those that running tasks will still add, is done.
  // The thread that finishes the last one lays the tree out (see layOut()) before letting the
  // others go.
  void work(int thread) {
    waitForSlots();
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return queuedTasks_ > 0 || unfinished_ == 0; });
      if (queuedTasks_ == 0) return;
      NodeTask task = takeTask(thread);
      task.owner = thread;
      lock.unlock();
      const uint32_t used = buildNode(task);
      lock.lock();
      if (const uint32_t reserved = 2 * (task.end - task.begin) - 2; used < reserved)
        holes_.push_back({task.descendants + used, reserved - used});
      if (unfinished_ == 1) {
        layOut();
        unfinished_ = 0;
        wake_.notify_all();
      } else {
        --unfinished_;
      }
    }
  }

  // The thread's own newest task, or else the oldest of the first other thread that has one.
  // Called with mutex_ held and a task queued.
  NodeTask takeTask(int thread) {
    --queuedTasks_;
    for (int i = 0;; ++i) {
      TaskQueue& queue = queues_[(thread + i) % threads_];
      if (!queue.empty()) return queue.take(i == 0);
    }
  }

  void addTask(const NodeTask& task) {
    {
      std::lock_guard lock(mutex_);
      queues_[task.owner].push(task);
      ++queuedTasks_;
      ++unfinished_;
    }
    wake_.notify_one();
  }

  // Returns the slots that the leaf's descendants use: none.
  uint32_t makeLeaf(GpuBvhNode& node, const NodeTask& t) {
    node.leftFirst = t.begin;
    node.count = t.end - t.begin;
    const BoxRef* boxes = refs_[t.buffer].get();
    for (uint32_t i = t.begin; i < t.end; ++i) order_[i] = boxes[i].index;
    return 0;
  }

  // Writes the node's bounds with two stores, whose lane 3 lands in leftFirst and count: every
  // caller writes those afterwards.
  static void writeBounds(GpuBvhNode& node, const NodeTask& t) {
    static_assert(offsetof(GpuBvhNode, leftFirst) == 12 && offsetof(GpuBvhNode, count) == 28);
    _mm_storeu_ps(node.boundsMin, t.bounds.min);
    _mm_storeu_ps(node.boundsMax, t.bounds.max);
  }

  // Makes t's node the parent of `left` (t's first leftCount boxes) and `right` (the others):
  // their slots and boxes; their bounds and buffer are the caller's, and so is where the right
  // child's descendants go (see build()).
  void setChildren(const NodeTask& t, uint32_t leftCount, NodeTask& left, NodeTask& right) {
    GpuBvhNode& node = slots_[t.slot];
    node.leftFirst = t.descendants;
    node.count = 0;
    left.slot = t.descendants, right.slot = t.descendants + 1;
    left.descendants = t.descendants + 2;
    left.begin = t.begin, left.end = right.begin = t.begin + leftCount, right.end = t.end;
    left.depth = right.depth = t.depth + 1;
    left.owner = right.owner = t.owner;
  }

  // Builds t's subtree and returns how many slots from t.descendants on it uses: its node count
  // less one, plus the holes that its tasks may leave (see build()).
  uint32_t buildNode(const NodeTask& t) {
    const uint32_t count = t.end - t.begin;
    if (count <= kSmallSubtreeMax) return buildSmallSubtree(t);
    GpuBvhNode& node = slots_[t.slot];
    writeBounds(node, t);
    if (t.depth >= kMedianSplitDepth) return buildAtMedian(t);
    BoxRef* boxes = refs_[t.buffer].get() + t.begin;
    // Initialised from the call, not assigned: a Split is over a hundred bytes.
    const Split split = findBinnedSplit(boxes, count, sampleStrideFor(t), centroidBoundsOf(boxes, count), binCountFor(count));
    if (split.axis < 0) return buildAtMedian(t);
    if (!shouldSplit(count, settings_.leafSize, t.bounds.halfArea(), split.childCost)) return makeLeaf(node, t);
    NodeTask left{}, right{};
    Box4 bounds[2];
    const uint32_t leftCount = partition(boxes, refs_[1 - t.buffer].get() + t.begin, count, split, bounds);
    left.buffer = right.buffer = 1 - t.buffer;
    left.bounds = bounds[1], right.bounds = bounds[0];
    return buildChildren(t, leftCount, left, right);
  }

  // Makes `left` and `right`, whose bounds and buffer are set, t's children and builds them (or
  // hands the left one to the task queue); returns the slots that t's subtree uses.
  uint32_t buildChildren(const NodeTask& t, uint32_t leftCount, NodeTask& left, NodeTask& right) {
    setChildren(t, leftCount, left, right);
    uint32_t leftUsed = 2 * leftCount - 2; // all of its slots, for a task
    if (threads_ > 1 && leftCount >= kTaskMinBoxes) {
      addTask(left);
    } else {
      leftUsed = buildNode(left);
    }
    right.descendants = left.descendants + leftUsed;
    return 2 + leftUsed + buildNode(right);
  }

  // A node too deep for SAH (see kMedianSplitDepth), or with every centroid in one point so
  // that no SAH split exists: a leaf, or split at the median when too big for one. Its bounds
  // are written.
  uint32_t buildAtMedian(const NodeTask& t) {
    const uint32_t count = t.end - t.begin;
    if (count <= static_cast<uint32_t>(settings_.leafSize)) return makeLeaf(slots_[t.slot], t);
    BoxRef* boxes = refs_[t.buffer].get() + t.begin;
    NodeTask left{}, right{};
    const uint32_t leftCount = medianSplit(boxes, count, centroidBoundsOf(boxes, count));
    left.buffer = right.buffer = t.buffer;
    left.bounds = boundsOf(boxes, leftCount);
    right.bounds = boundsOf(boxes + leftCount, count - leftCount);
    return buildChildren(t, leftCount, left, right);
  }

  // The subtree of t, of kSmallSubtreeMax boxes or fewer (see SmallBoxes).
  uint32_t buildSmallSubtree(const NodeTask& t) {
    static_assert(kSmallSubtreeMax == 8);
    const BoxRef* refs = refs_[t.buffer].get() + t.begin;
    SmallBoxes boxes;
    switch (t.end - t.begin) {
    case 1: return buildSmallNode(boxes, loadSmallSubtree<1>(refs, boxes), t);
    case 2: return buildSmallNode(boxes, loadSmallSubtree<2>(refs, boxes), t);
    case 3: return buildSmallNode(boxes, loadSmallSubtree<3>(refs, boxes), t);
    case 4: return buildSmallNode(boxes, loadSmallSubtree<4>(refs, boxes), t);
    case 5: return buildSmallNode(boxes, loadSmallSubtree<5>(refs, boxes), t);
    case 6: return buildSmallNode(boxes, loadSmallSubtree<6>(refs, boxes), t);
    case 7: return buildSmallNode(boxes, loadSmallSubtree<7>(refs, boxes), t);
    default: return buildSmallNode(boxes, loadSmallSubtree<8>(refs, boxes), t);
    }
  }

  // Builds a node of a small subtree and its own subtree, as buildNode() does.
  uint32_t buildSmallNode(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    writeBounds(slots_[t.slot], t);
    if (n.count == 1) return makeSmallLeaf(boxes, n, t);
    if (t.depth >= kMedianSplitDepth) return buildSmallAtMedian(boxes, n, t);
    switch (n.count) {
    case 2: return buildSmallPair(boxes, n, t);
    case 3: return buildSmallInterior<3>(boxes, n, t);
    case 4: return buildSmallInterior<4>(boxes, n, t);
    case 5: return buildSmallInterior<5>(boxes, n, t);
    case 6: return buildSmallInterior<6>(boxes, n, t);
    case 7: return buildSmallInterior<7>(boxes, n, t);
    default: return buildSmallInterior<8>(boxes, n, t);
    }
  }

  template <uint32_t M> uint32_t buildSmallInterior(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    const SmallSplit split = findSmallSplit<M>(boxes, n);
    if (split.axis < 0) return buildSmallAtMedian(boxes, n, t);
    if (!shouldSplit(M, settings_.leafSize, t.bounds.halfArea(), split.childCost)) return makeSmallLeaf(boxes, n, t);
    SmallNode children[2];
    Box4 bounds[2];
    splitSmallNode<M>(boxes, n, split, children, bounds);
    NodeTask left{}, right{};
    setChildren(t, split.leftCount, left, right);
    left.buffer = right.buffer = t.buffer;
    left.bounds = bounds[1], right.bounds = bounds[0];
    const uint32_t leftUsed = buildSmallNode(boxes, children[1], left);
    right.descendants = left.descendants + leftUsed;
    return 2 + leftUsed + buildSmallNode(boxes, children[0], right);
  }

  // A node of two boxes, the most common interior node (SAH splits to about one box per leaf): a
  // leaf, or two one-box leaves with the lower centroid first. The one split puts one box on
  // each side and costs the same on every axis, so the first axis on which the centroids differ
  // takes it, as a sweep would choose.
  uint32_t buildSmallPair(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    const uint32_t a = n.slots[0], b = n.slots[1];
    const int differ = _mm_movemask_ps(_mm_cmpneq_ps(_mm_load_ps(boxes.centroid2[a]), _mm_load_ps(boxes.centroid2[b]))) & 7;
    if (differ == 0) return buildSmallAtMedian(boxes, n, t);
    const int axis = std::countr_zero(static_cast<unsigned>(differ));
    Box4 boxA, boxB;
    boxA.grow(boxes.lo[a], boxes.hi[a]);
    boxB.grow(boxes.lo[b], boxes.hi[b]);
    const double childCost = kSahBrushCost * (static_cast<double>(boxA.halfArea()) + boxB.halfArea());
    if (!shouldSplit(2, settings_.leafSize, t.bounds.halfArea(), childCost)) return makeSmallLeaf(boxes, n, t);
    const bool aFirst = boxes.centroid2[a][axis] <= boxes.centroid2[b][axis];
    GpuBvhNode& node = slots_[t.slot];
    node.leftFirst = t.descendants;
    node.count = 0;
    for (uint32_t child = 0; child < 2; ++child) {
      const uint32_t slot = (child == 0) == aFirst ? a : b;
      GpuBvhNode& leaf = slots_[t.descendants + child];
      _mm_storeu_ps(leaf.boundsMin, boxes.lo[slot]);
      _mm_storeu_ps(leaf.boundsMax, boxes.hi[slot]);
      leaf.leftFirst = t.begin + child;
      leaf.count = 1;
      order_[t.begin + child] = boxes.index[slot];
    }
    return 2;
  }

  // As makeLeaf(), the boxes in node order.
  uint32_t makeSmallLeaf(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    GpuBvhNode& node = slots_[t.slot];
    node.leftFirst = t.begin;
    node.count = n.count;
    for (uint32_t i = 0; i < n.count; ++i) order_[t.begin + i] = boxes.index[n.slots[i]];
    return 0;
  }

  // buildAtMedian() for a node of a small subtree, whose boxes it first writes to its place in
  // t's buffer, in node order (the small subtree read them from there and no longer needs them).
  uint32_t buildSmallAtMedian(const SmallBoxes& boxes, const SmallNode& n, const NodeTask& t) {
    if (n.count <= static_cast<uint32_t>(settings_.leafSize)) return makeSmallLeaf(boxes, n, t);
    BoxRef* refs = refs_[t.buffer].get() + t.begin;
    for (uint32_t i = 0; i < n.count; ++i) {
      const uint32_t slot = n.slots[i];
      _mm_storeu_ps(&refs[i].min.x, boxes.lo[slot]);
      _mm_storeu_ps(&refs[i].max.x, boxes.hi[slot]); // pad = lane 3 = 0
      refs[i].index = boxes.index[slot];
    }
    return buildAtMedian(t);
  }

  // Nodes of kSampledBinningMin boxes or more choose their split from every stride-th box, 512
  // to 1023 of them: that places the SAH's planes about as well as all of their boxes, for the
  // cost of binning a few. Smaller nodes bin every box: with 256 samples in nodes of 512 and
  // more, chasm's SAH went from 0.99 to 1.065 of the full sweep. Never the root, which the
  // build's threads bin together (see buildWithThreads()).
  static uint32_t sampleStrideFor(const NodeTask& t) {
    const uint32_t count = t.end - t.begin;
    return t.depth == 0 || count < kSampledBinningMin ? 1 : count / kBinSamples;
  }

  // A node with few boxes gets fewer bins, as sweeping bins costs more than binning its boxes
  // there: 5/8 bin per box, at most 24 below 256 boxes. Against 3/4 bin per box and 32 bins
  // from 43 boxes on, that saves 4 % of the build's instructions and keeps or lowers the SAH
  // on the shared maps (dm3 1.019 -> 1.017 of the full sweep, e1m1 1.017 -> 1.012, chasm
  // 0.991 -> 0.990, lq_e4m3 0.993 -> 0.996) and the generated levels (50k 0.982 -> 0.979).
  // The SAH moves by a percent or two either way with the bin count on these levels (their
  // brushes sit on grids that bins of some widths fit better), so changes here need measuring.
  int binCountFor(uint32_t count) const {
    const int perBoxes = static_cast<int>(std::max(count * 5 / 8, kMinBins));
    const int cap = count < 256 ? std::min(settings_.binCount, 24) : settings_.binCount;
    return std::min(cap, perBoxes);
  }

  static uint32_t medianSplit(BoxRef* boxes, uint32_t count, const Box4& centroids) {
    const glm::vec3 extent = centroids.aabb().max - centroids.aabb().min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t middle = count / 2;
    std::nth_element(boxes, boxes + middle, boxes + count,
                     [axis](const BoxRef& a, const BoxRef& b) { return a.centroid2(axis) < b.centroid2(axis); });
    return middle;
  }

  // Slots that a task reserved but did not use (see build()).
  struct Hole {
    uint32_t begin, size;
  };
  // The final layout is the slots in their order with the holes squeezed out, which is the
  // depth-first layout (see build()). Each stretch between two holes moves down by the size of
  // the holes before it, in place, in slot order: a slot moves to one before it, so none is
  // overwritten before it has moved. Done by one thread: in place, the threads could not
  // move stretches side by side without one overwriting another's before it moved, and a
  // second array of slots to lay out from cost more (its pages, fresh each build) than the
  // threads saved.
  void layOut() {
    std::sort(holes_.begin(), holes_.end(), [](const Hole& a, const Hole& b) { return a.begin < b.begin; });
    const uint32_t slotCount = 2 * count_ - 1;
    uint32_t shift = 0;
    for (const Hole& hole : holes_) {
      shift += hole.size;
      holeEnds_.push_back(hole.begin + hole.size);
      holeShifts_.push_back(shift);
    }
    const uint32_t total = slotCount - shift;
    uint32_t from = 0;
    shift = 0;
    for (size_t h = 0; h <= holes_.size(); ++h) {
      const uint32_t end = h < holes_.size() ? holes_[h].begin : slotCount;
      moveStretch(from, end, shift);
      if (h < holes_.size()) from = holeEnds_[h], shift = holeShifts_[h];
    }
    nodes_.resize(total); // shrinks: no allocation
  }

  // How far slot i moves down: the size of the holes before it.
  uint32_t shiftOf(uint32_t i) const {
    const size_t before = std::upper_bound(holeEnds_.begin(), holeEnds_.end(), i) - holeEnds_.begin();
    return before == 0 ? 0 : holeShifts_[before - 1];
  }

  // Moves slots [from, end), a stretch between two holes, down by `shift`, and their child
  // indices with them. A node's children lie after it, mostly in the same stretch; a child
  // past the stretch's end (the right child of a node whose left child was a task) looks its
  // shift up.
  void moveStretch(uint32_t from, uint32_t end, uint32_t shift) {
    for (uint32_t i = from; i < end; ++i) {
      GpuBvhNode node = slots_[i];
      if (node.count == 0) node.leftFirst -= node.leftFirst < end ? shift : shiftOf(node.leftFirst);
      slots_[i - shift] = node;
    }
  }

  SahBuildSettings settings_;
  std::span<const Aabb> input_;
  int threads_ = 1;
  uint32_t count_ = 0;
  std::unique_ptr<BoxRef[]> refs_[2]; // a node's boxes are in one; partitioning moves them to the other
  GpuBvhNode* slots_ = nullptr;       // nodes_'s storage, before the layout
  std::vector<uint32_t> order_;
  std::vector<GpuBvhNode> nodes_; // the result: slots_ laid out depth first
  // With threads: the holes between the tasks' slots, sorted by layOut(), which adds the end
  // of each and the size of all up to it.
  std::vector<Hole> holes_;
  std::vector<uint32_t> holeEnds_, holeShifts_;

  std::atomic<bool> slotsSized_{false}; // see sizeSlots()
  std::mutex mutex_;                    // guards queues_, queuedTasks_, unfinished_ and holes_
  std::condition_variable wake_;
  std::vector<TaskQueue> queues_; // one per thread
  uint32_t queuedTasks_ = 0;
  uint32_t unfinished_ = 0; // tasks queued or running
};

} // namespace
