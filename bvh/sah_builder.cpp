#include "bvh/sah_builder.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <future>
#include <stdexcept>
#include <thread>

namespace bt {
namespace {

// Subtrees smaller than this are built on the thread that reached them: below it, starting a
// thread costs more than the subtree.
constexpr uint32_t kParallelMinBoxes = 4096;
constexpr int kMaxBins = 256;
// Below this depth, nodes are split at the median along the widest centroid axis instead of by
// SAH, which bounds the depth at kMedianSplitDepth + log2(n) <= kBvhMaxDepth for n <= 2^24
// boxes. SAH trees of real levels stay well above it; only pathological inputs (geometric
// series of box sizes) reach it.
constexpr uint32_t kMedianSplitDepth = kBvhMaxDepth - 24;
constexpr size_t kMaxBoxes = size_t{1} << 24;

// One input box as the builder moves it around: bounds plus the input index, 32 bytes, so that
// partitioning swaps whole records instead of chasing an index.
struct BoxRef {
  glm::vec3 min;
  uint32_t index;
  glm::vec3 max;
  uint32_t pad;

  // Twice the centroid: binning only needs positions relative to each other.
  glm::vec3 centroid2() const { return min + max; }
};

struct Bin {
  Aabb bounds;
  uint32_t count = 0;
};

// Maps a (doubled) centroid coordinate to its bin along one axis. The partition step calls the
// same function, so a box always lands on the side its bin was counted on.
struct BinMapping {
  float origin = 0.0f;
  float scale = 0.0f;
  int binCount = 0;

  int bin(float centroid2) const {
    const int b = static_cast<int>((centroid2 - origin) * scale);
    return std::clamp(b, 0, binCount - 1);
  }
};

// Nodes this small are split by an exact sweep over their sorted centroids instead of bins:
// sorting a handful of boxes costs no more than clearing 3 x binCount bins, and the deep
// levels, where bins are coarsest relative to the boxes, are where binning loses most.
constexpr uint32_t kExactSweepMax = 32;

struct Split {
  int axis = -1; // -1: no split found (all centroids coincide)
  bool exact = false;      // exact: left = doubled centroid <= position; else bins <= lastLeftBin
  float position = 0.0f;
  int lastLeftBin = 0;
  double childCost = 0.0; // area(left) * count(left) + area(right) * count(right), half-areas
  BinMapping mapping;
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
    Aabb bounds, centroids;
    for (const BoxRef& r : refs_) {
      bounds.grow(Aabb{r.min, r.max});
      centroids.grow(r.centroid2());
    }
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
                 const Aabb& bounds, const Aabb& centroids) {
    GpuBvhNode& node = slots_[slot];
    for (int a = 0; a < 3; ++a) {
      node.boundsMin[a] = bounds.min[a];
      node.boundsMax[a] = bounds.max[a];
    }
    const uint32_t count = end - begin;
    if (count == 1) return makeLeaf(slot, begin, count);

    const Split split = depth < kMedianSplitDepth ? findSplit(begin, end, centroids) : Split{};
    uint32_t middle = 0;
    Aabb leftBounds, rightBounds, leftCentroids, rightCentroids;
    if (depth >= kMedianSplitDepth) {
      if (count <= static_cast<uint32_t>(settings_.leafSize)) return makeLeaf(slot, begin, count);
      middle = medianSplit(begin, end, centroids);
      boundsOf(begin, middle, leftBounds, leftCentroids);
      boundsOf(middle, end, rightBounds, rightCentroids);
    } else if (split.axis >= 0) {
      if (!shouldSplit(count, settings_.leafSize, bounds.halfArea(), split.childCost))
        return makeLeaf(slot, begin, count);
      middle = partition(begin, end, split, leftBounds, rightBounds, leftCentroids, rightCentroids);
    } else {
      // Every centroid in one point: no SAH split exists. Split in half only when the node is
      // too big for a leaf; which half a box goes to does not matter.
      if (count <= static_cast<uint32_t>(settings_.leafSize)) return makeLeaf(slot, begin, count);
      middle = begin + count / 2;
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

  Split findSplit(uint32_t begin, uint32_t end, const Aabb& centroids) const {
    if (end - begin <= kExactSweepMax) return findExactSplit(begin, end);
    const int binCount = settings_.binCount;
    std::array<std::array<Bin, kMaxBins>, 3> bins;
    std::array<BinMapping, 3> mappings;
    for (int a = 0; a < 3; ++a) {
      const float extent = centroids.max[a] - centroids.min[a];
      mappings[a] = {centroids.min[a], extent > 0.0f ? binCount / extent : 0.0f, binCount};
      for (int b = 0; b < binCount; ++b) bins[a][b] = Bin{};
    }
    for (uint32_t i = begin; i < end; ++i) {
      const BoxRef& r = refs_[i];
      const glm::vec3 c = r.centroid2();
      for (int a = 0; a < 3; ++a) {
        Bin& bin = bins[a][mappings[a].bin(c[a])];
        bin.bounds.min = glm::min(bin.bounds.min, r.min);
        bin.bounds.max = glm::max(bin.bounds.max, r.max);
        ++bin.count;
      }
    }

    Split best;
    best.childCost = std::numeric_limits<double>::infinity();
    std::array<double, kMaxBins> leftCost; // cost of bins [0, b] on the left
    for (int a = 0; a < 3; ++a) {
      if (mappings[a].scale == 0.0f) continue;
      Aabb box;
      uint32_t n = 0;
      for (int b = 0; b < binCount - 1; ++b) {
        box.grow(bins[a][b].bounds);
        n += bins[a][b].count;
        leftCost[b] = static_cast<double>(box.halfArea()) * n;
      }
      box = Aabb{};
      n = 0;
      for (int b = binCount - 1; b > 0; --b) {
        box.grow(bins[a][b].bounds);
        n += bins[a][b].count;
        const int lastLeft = b - 1;
        const double cost = leftCost[lastLeft] + static_cast<double>(box.halfArea()) * n;
        // Both sides must be non-empty: the leftCost of an empty left side is 0, which the
        // count check rules out.
        const uint32_t rightCount = n;
        const uint32_t leftCount = (end - begin) - rightCount;
        if (leftCount > 0 && rightCount > 0 && cost < best.childCost) {
          best.axis = a;
          best.lastLeftBin = lastLeft;
          best.childCost = cost;
          best.mapping = mappings[a];
        }
      }
    }
    best.childCost *= kSahBrushCost;
    return best;
  }

  Split findExactSplit(uint32_t begin, uint32_t end) const {
    const uint32_t n = end - begin;
    std::array<uint32_t, kExactSweepMax> order;
    std::array<double, kExactSweepMax> rightCost; // cost of order[i .. n) on the right
    Split best;
    best.childCost = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      for (uint32_t i = 0; i < n; ++i) order[i] = begin + i;
      auto centroid = [&](uint32_t i) { return refs_[order[i]].centroid2()[a]; };
      std::sort(order.begin(), order.begin() + n,
                [&](uint32_t x, uint32_t y) { return refs_[x].centroid2()[a] < refs_[y].centroid2()[a]; });
      Aabb box;
      for (uint32_t i = n; i-- > 1;) {
        box.grow(Aabb{refs_[order[i]].min, refs_[order[i]].max});
        rightCost[i] = static_cast<double>(box.halfArea()) * (n - i);
      }
      box = Aabb{};
      for (uint32_t i = 1; i < n; ++i) { // left = order[0 .. i)
        box.grow(Aabb{refs_[order[i - 1]].min, refs_[order[i - 1]].max});
        if (centroid(i - 1) == centroid(i)) continue; // not separable by a plane
        const double cost = static_cast<double>(box.halfArea()) * i + rightCost[i];
        if (cost < best.childCost) {
          best.axis = a;
          best.exact = true;
          best.position = centroid(i - 1);
          best.childCost = cost;
        }
      }
    }
    best.childCost *= kSahBrushCost;
    return best;
  }

  uint32_t partition(uint32_t begin, uint32_t end, const Split& split, Aabb& leftBounds, Aabb& rightBounds,
                     Aabb& leftCentroids, Aabb& rightCentroids) {
    uint32_t i = begin, j = end;
    while (i < j) {
      const BoxRef& r = refs_[i];
      const glm::vec3 c = r.centroid2();
      const bool left = split.exact ? c[split.axis] <= split.position : split.mapping.bin(c[split.axis]) <= split.lastLeftBin;
      if (left) {
        leftBounds.grow(Aabb{r.min, r.max});
        leftCentroids.grow(c);
        ++i;
      } else {
        rightBounds.grow(Aabb{r.min, r.max});
        rightCentroids.grow(c);
        std::swap(refs_[i], refs_[--j]);
      }
    }
    return i;
  }

  uint32_t medianSplit(uint32_t begin, uint32_t end, const Aabb& centroids) {
    const glm::vec3 extent = centroids.max - centroids.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(refs_.begin() + begin, refs_.begin() + middle, refs_.begin() + end,
                     [axis](const BoxRef& a, const BoxRef& b) { return a.centroid2()[axis] < b.centroid2()[axis]; });
    return middle;
  }

  void boundsOf(uint32_t begin, uint32_t end, Aabb& bounds, Aabb& centroids) const {
    for (uint32_t i = begin; i < end; ++i) {
      bounds.grow(Aabb{refs_[i].min, refs_[i].max});
      centroids.grow(refs_[i].centroid2());
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
