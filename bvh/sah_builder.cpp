#include "bvh/sah_builder.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <future>
#include <stdexcept>
#include <thread>

#include <immintrin.h>

namespace bt {
namespace {

// Subtrees smaller than this are built on the thread that reached them: below it, starting a
// thread costs more than the subtree.
constexpr uint32_t kParallelMinBoxes = 4096;
constexpr int kMaxBins = 256;
constexpr float kFloatMax = std::numeric_limits<float>::max();
// Below this depth, nodes are split at the median along the widest centroid axis instead of by
// SAH, which bounds the depth at kMedianSplitDepth + log2(n) <= kBvhMaxDepth for n <= 2^24
// boxes. SAH trees of real levels stay well above it; only pathological inputs (geometric
// series of box sizes) reach it.
constexpr uint32_t kMedianSplitDepth = kBvhMaxDepth - 24;
constexpr size_t kMaxBoxes = size_t{1} << 24;

// The builder's inner loops work on SSE registers (x86-64 baseline): a box is two __m128
// with x, y, z in lanes 0-2; lane 3 is masked to zero before any arithmetic.
const __m128 kXyzMask = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));

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

// One input box as the builder moves it around: bounds plus the input index, 32 bytes, so that
// partitioning swaps whole records instead of chasing an index.
struct BoxRef {
  glm::vec3 min;
  uint32_t index;
  glm::vec3 max;
  uint32_t pad;

  __m128 lo() const { return _mm_and_ps(_mm_loadu_ps(&min.x), kXyzMask); }
  __m128 hi() const { return _mm_and_ps(_mm_loadu_ps(&max.x), kXyzMask); }
  // Twice the centroid: binning only needs positions relative to each other.
  __m128 centroid2() const { return _mm_add_ps(lo(), hi()); }
  float centroid2(int axis) const { return min[axis] + max[axis]; } // == lane `axis` of the above
};

// Maps doubled centroids to bins, all three axes at once. The partition step calls the same
// arithmetic, so a box always lands on the side its bin was counted on.
struct BinMapping {
  __m128 origin;
  __m128 scale; // 0 on an axis whose centroids all coincide
  int binCount;

  void bins(__m128 centroid2, int32_t out[4]) const {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(_mm_mul_ps(_mm_sub_ps(centroid2, origin), scale)));
    for (int a = 0; a < 3; ++a) out[a] = std::clamp(out[a], 0, binCount - 1);
  }
};

// Nodes this small are split by an exact sweep over their sorted centroids instead of bins:
// sorting a handful of boxes costs less than clearing and sweeping 3 x binCount bins, and the
// deep levels, where bins are coarsest relative to the boxes, are where binning loses most.
constexpr uint32_t kExactSweepMax = 32;

struct Split {
  int axis = -1;      // -1: no split found (all centroids coincide)
  bool exact = false; // exact: left = doubled centroid <= position; else bin <= lastLeftBin
  float position = 0.0f;
  int lastLeftBin = 0;
  double childCost = 0.0; // area(left) * count(left) + area(right) * count(right), half-areas
  const BinMapping* mapping = nullptr;
};

class BinnedSahBuilder {
public:
  BinnedSahBuilder(std::span<const Aabb> boxes, const SahBuildSettings& settings)
      : settings_(settings), refs_(boxes.size()), slots_(boxes.empty() ? 0 : 2 * boxes.size() - 1) {
    settings_.binCount = std::clamp(settings_.binCount, 2, kMaxBins);
    settings_.leafSize = std::max(settings_.leafSize, 1);
    const int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
    spareThreads_ = std::max(threads, 1) - 1;
    for (size_t i = 0; i < boxes.size(); ++i) refs_[i] = {boxes[i].min, static_cast<uint32_t>(i), boxes[i].max, 0};
  }

  FlatBvh build() {
    FlatBvh result;
    if (refs_.empty()) return result;
    Box4 bounds, centroids;
    boundsOf(0, static_cast<uint32_t>(refs_.size()), bounds, centroids);
    // Slot layout while building: a node in slot s with n boxes owns the 2n - 2 slots from
    // `descendants` on for its subtree: its two children first, then the left child's
    // subtree (2 nL - 2 slots), then the right child's. That makes every slot known before
    // the subtrees are built, so threads never share a counter and the layout is the same
    // for any thread count. Leaves leave their reserved slots unused; compactDepthFirst()
    // squeezes the holes out.
    buildNode(0, 1, 0, static_cast<uint32_t>(refs_.size()), 0, bounds, centroids);
    result.nodes = compactDepthFirst(slots_);
    result.order.resize(refs_.size());
    for (size_t i = 0; i < refs_.size(); ++i) result.order[i] = refs_[i].index;
    return result;
  }

private:
  void makeLeaf(uint32_t slot, uint32_t begin, uint32_t count) {
    slots_[slot].leftFirst = begin;
    slots_[slot].count = count;
  }

  void buildNode(uint32_t slot, uint32_t descendants, uint32_t begin, uint32_t end, uint32_t depth,
                 const Box4& bounds, const Box4& centroids) {
    GpuBvhNode& node = slots_[slot];
    const Aabb box = bounds.aabb();
    for (int a = 0; a < 3; ++a) {
      node.boundsMin[a] = box.min[a];
      node.boundsMax[a] = box.max[a];
    }
    const uint32_t count = end - begin;
    if (count == 1) return makeLeaf(slot, begin, count);

    BinMapping mapping;
    const Split split = depth < kMedianSplitDepth ? findSplit(begin, end, centroids, mapping) : Split{};
    uint32_t middle = 0;
    Box4 leftBounds, rightBounds, leftCentroids, rightCentroids;
    if (split.axis >= 0) {
      if (!shouldSplit(count, settings_.leafSize, bounds.halfArea(), split.childCost))
        return makeLeaf(slot, begin, count);
      middle = partition(begin, end, split, leftBounds, rightBounds, leftCentroids, rightCentroids);
    } else {
      // Too deep for SAH (see kMedianSplitDepth), or every centroid in one point so that no
      // SAH split exists: split at the median when the node is too big for a leaf.
      if (count <= static_cast<uint32_t>(settings_.leafSize)) return makeLeaf(slot, begin, count);
      middle = medianSplit(begin, end, centroids);
      boundsOf(begin, middle, leftBounds, leftCentroids);
      boundsOf(middle, end, rightBounds, rightCentroids);
    }

    const uint32_t leftCount = middle - begin;
    const uint32_t leftSlot = descendants, rightSlot = descendants + 1;
    const uint32_t leftDescendants = descendants + 2;
    const uint32_t rightDescendants = leftDescendants + 2 * leftCount - 2;
    node.leftFirst = leftSlot;
    node.count = 0;

    auto buildLeft = [&] { buildNode(leftSlot, leftDescendants, begin, middle, depth + 1, leftBounds, leftCentroids); };
    auto buildRight = [&] { buildNode(rightSlot, rightDescendants, middle, end, depth + 1, rightBounds, rightCentroids); };
    if (count >= kParallelMinBoxes && claimThread()) {
      auto left = std::async(std::launch::async, [&] {
        buildLeft();
        spareThreads_.fetch_add(1);
      });
      buildRight();
      left.get();
    } else {
      buildLeft();
      buildRight();
    }
  }

  bool claimThread() {
    int spare = spareThreads_.load();
    while (spare > 0)
      if (spareThreads_.compare_exchange_weak(spare, spare - 1)) return true;
    return false;
  }

  Split findSplit(uint32_t begin, uint32_t end, const Box4& centroids, BinMapping& mapping) const {
    if (end - begin <= kExactSweepMax) return findExactSplit(begin, end);
    const int binCount = settings_.binCount;
    alignas(16) float extent[4];
    _mm_store_ps(extent, _mm_sub_ps(centroids.max, centroids.min));
    alignas(16) float scale[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.0f ? binCount / extent[a] : 0.0f;
    mapping = {centroids.min, _mm_load_ps(scale), binCount};

    // Raw storage: only the binCount bins in use are cleared (a Box4 array would construct all
    // kMaxBins of them on every call).
    struct Bins {
      __m128 min[kMaxBins], max[kMaxBins];
      uint32_t count[kMaxBins];
    };
    std::array<Bins, 3> bins;
    for (int a = 0; a < 3; ++a) {
      std::fill_n(bins[a].min, binCount, Box4{}.min);
      std::fill_n(bins[a].max, binCount, Box4{}.max);
      std::fill_n(bins[a].count, binCount, 0u);
    }
    alignas(16) int32_t bin[4];
    for (uint32_t i = begin; i < end; ++i) {
      const __m128 lo = refs_[i].lo(), hi = refs_[i].hi();
      mapping.bins(_mm_add_ps(lo, hi), bin);
      for (int a = 0; a < 3; ++a) {
        bins[a].min[bin[a]] = _mm_min_ps(bins[a].min[bin[a]], lo);
        bins[a].max[bin[a]] = _mm_max_ps(bins[a].max[bin[a]], hi);
        ++bins[a].count[bin[a]];
      }
    }

    Split best;
    best.childCost = std::numeric_limits<double>::infinity();
    const uint32_t n = end - begin;
    std::array<double, kMaxBins> leftCost; // cost of bins [0, b] on the left
    for (int a = 0; a < 3; ++a) {
      if (scale[a] == 0.0f) continue;
      Box4 box;
      uint32_t count = 0;
      for (int b = 0; b < binCount - 1; ++b) {
        box.grow(bins[a].min[b], bins[a].max[b]);
        count += bins[a].count[b];
        leftCost[b] = count > 0 ? static_cast<double>(box.halfArea()) * count : 0.0;
      }
      box = Box4{};
      count = 0;
      for (int b = binCount - 1; b > 0; --b) {
        box.grow(bins[a].min[b], bins[a].max[b]);
        count += bins[a].count[b];
        // Both sides must hold boxes.
        if (count == 0 || count == n) continue;
        const double cost = leftCost[b - 1] + static_cast<double>(box.halfArea()) * count;
        if (cost < best.childCost) {
          best.axis = a;
          best.lastLeftBin = b - 1;
          best.childCost = cost;
        }
      }
    }
    best.mapping = &mapping;
    best.childCost *= kSahBrushCost;
    return best;
  }

  Split findExactSplit(uint32_t begin, uint32_t end) const {
    const uint32_t n = end - begin;
    struct Key {
      float centroid2;
      uint32_t ref;
    };
    std::array<Key, kExactSweepMax> sorted;
    std::array<double, kExactSweepMax> rightCost; // cost of sorted[i .. n) on the right
    Split best;
    best.childCost = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      for (uint32_t i = 0; i < n; ++i) sorted[i] = {refs_[begin + i].centroid2(a), begin + i};
      std::sort(sorted.begin(), sorted.begin() + n, [](const Key& x, const Key& y) { return x.centroid2 < y.centroid2; });
      Box4 box;
      for (uint32_t i = n; i-- > 1;) {
        box.grow(refs_[sorted[i].ref].lo(), refs_[sorted[i].ref].hi());
        rightCost[i] = static_cast<double>(box.halfArea()) * (n - i);
      }
      box = Box4{};
      for (uint32_t i = 1; i < n; ++i) { // left = sorted[0 .. i)
        box.grow(refs_[sorted[i - 1].ref].lo(), refs_[sorted[i - 1].ref].hi());
        if (sorted[i - 1].centroid2 == sorted[i].centroid2) continue; // not separable by a plane
        const double cost = static_cast<double>(box.halfArea()) * i + rightCost[i];
        if (cost < best.childCost) {
          best.axis = a;
          best.exact = true;
          best.position = sorted[i - 1].centroid2;
          best.childCost = cost;
        }
      }
    }
    best.childCost *= kSahBrushCost;
    return best;
  }

  uint32_t partition(uint32_t begin, uint32_t end, const Split& split, Box4& leftBounds, Box4& rightBounds,
                     Box4& leftCentroids, Box4& rightCentroids) {
    uint32_t i = begin, j = end;
    alignas(16) int32_t bin[4];
    while (i < j) {
      const __m128 lo = refs_[i].lo(), hi = refs_[i].hi(), c = _mm_add_ps(lo, hi);
      bool left;
      if (split.exact) {
        left = refs_[i].centroid2(split.axis) <= split.position;
      } else {
        split.mapping->bins(c, bin);
        left = bin[split.axis] <= split.lastLeftBin;
      }
      if (left) {
        leftBounds.grow(lo, hi);
        leftCentroids.grow(c, c);
        ++i;
      } else {
        rightBounds.grow(lo, hi);
        rightCentroids.grow(c, c);
        std::swap(refs_[i], refs_[--j]);
      }
    }
    return i;
  }

  uint32_t medianSplit(uint32_t begin, uint32_t end, const Box4& centroids) {
    const glm::vec3 extent = centroids.aabb().max - centroids.aabb().min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(refs_.begin() + begin, refs_.begin() + middle, refs_.begin() + end,
                     [axis](const BoxRef& a, const BoxRef& b) { return a.centroid2(axis) < b.centroid2(axis); });
    return middle;
  }

  void boundsOf(uint32_t begin, uint32_t end, Box4& bounds, Box4& centroids) const {
    for (uint32_t i = begin; i < end; ++i) {
      const __m128 lo = refs_[i].lo(), hi = refs_[i].hi(), c = _mm_add_ps(lo, hi);
      bounds.grow(lo, hi);
      centroids.grow(c, c);
    }
  }

  SahBuildSettings settings_;
  std::vector<BoxRef> refs_;
  std::vector<GpuBvhNode> slots_;
  std::atomic<int> spareThreads_{0};
};

float halfArea(const GpuBvhNode& n) {
  const float x = n.boundsMax[0] - n.boundsMin[0];
  const float y = n.boundsMax[1] - n.boundsMin[1];
  const float z = n.boundsMax[2] - n.boundsMin[2];
  return x * y + y * z + z * x;
}

} // namespace

FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings) {
  if (boxes.size() > kMaxBoxes) throw std::invalid_argument("buildBinnedSah: more than 2^24 boxes");
  for (const Aabb& b : boxes)
    if (b.empty()) throw std::invalid_argument("buildBinnedSah: empty box");
  return BinnedSahBuilder(boxes, settings).build();
}

std::vector<GpuBvhNode> compactDepthFirst(std::span<const GpuBvhNode> nodes) {
  std::vector<GpuBvhNode> out;
  if (nodes.empty()) return out;
  out.reserve(nodes.size());
  out.push_back(nodes[0]);
  // (index in `nodes`, index in `out`) of interior nodes whose children are still to be placed.
  std::vector<std::pair<uint32_t, uint32_t>> stack;
  if (nodes[0].count == 0) stack.push_back({0, 0});
  while (!stack.empty()) {
    const auto [from, to] = stack.back();
    stack.pop_back();
    const uint32_t left = nodes[from].leftFirst;
    const uint32_t placed = static_cast<uint32_t>(out.size());
    out[to].leftFirst = placed;
    out.push_back(nodes[left]);
    out.push_back(nodes[left + 1]);
    // Right first on the stack so the left subtree is laid out next: depth-first order.
    if (nodes[left + 1].count == 0) stack.push_back({left + 1, placed + 1});
    if (nodes[left].count == 0) stack.push_back({left, placed});
  }
  return out;
}

double sahCost(std::span<const GpuBvhNode> nodes) {
  if (nodes.empty()) return 0.0;
  const double rootArea = halfArea(nodes[0]);
  if (!(rootArea > 0.0)) return 0.0;
  double cost = 0.0;
  for (const GpuBvhNode& n : nodes)
    cost += n.count == 0 ? kSahTraversalCost * halfArea(n) : kSahBrushCost * n.count * halfArea(n);
  return cost / rootArea;
}

} // namespace bt
