#include "tests/bvh/full_sweep_sah.h"

#include <algorithm>
#include <array>
#include <numeric>

namespace bt::test {
namespace {

class FullSweepBuilder {
public:
  FullSweepBuilder(std::span<const Aabb> boxes, int leafSize) : boxes_(boxes), leafSize_(leafSize) {}

  FlatBvh build() {
    FlatBvh result;
    if (boxes_.empty()) return result;
    std::vector<uint32_t> items(boxes_.size());
    std::iota(items.begin(), items.end(), 0u);
    nodes_.push_back({});
    buildNode(0, items);
    result.nodes = compactDepthFirst(nodes_);
    result.order = std::move(order_);
    return result;
  }

private:
  float centroid(uint32_t i, int axis) const { return boxes_[i].min[axis] + boxes_[i].max[axis]; }

  void buildNode(uint32_t slot, std::vector<uint32_t>& items) {
    Aabb bounds;
    for (uint32_t i : items) bounds.grow(boxes_[i]);
    for (int a = 0; a < 3; ++a) nodes_[slot].boundsMin[a] = bounds.min[a], nodes_[slot].boundsMax[a] = bounds.max[a];
    const size_t n = items.size();

    // Sweep every axis: sort by centroid, suffix areas from the right, then prefix from the left.
    double bestCost = std::numeric_limits<double>::infinity();
    int bestAxis = -1;
    size_t bestLeftCount = 0;
    std::array<std::vector<uint32_t>, 3> sorted;
    std::vector<double> rightCost(n);
    for (int a = 0; a < 3; ++a) {
      sorted[a] = items;
      std::sort(sorted[a].begin(), sorted[a].end(), [&](uint32_t x, uint32_t y) {
        const float cx = centroid(x, a), cy = centroid(y, a);
        return cx < cy || (cx == cy && x < y);
      });
      Aabb box;
      for (size_t i = n; i-- > 1;) { // right side = sorted[i .. n)
        box.grow(boxes_[sorted[a][i]]);
        rightCost[i] = static_cast<double>(box.halfArea()) * (n - i);
      }
      box = Aabb{};
      for (size_t i = 1; i < n; ++i) { // left side = sorted[0 .. i)
        box.grow(boxes_[sorted[a][i - 1]]);
        // Splitting between equal centroids is not a plane split; the binned builder cannot
        // make it either.
        if (centroid(sorted[a][i - 1], a) == centroid(sorted[a][i], a)) continue;
        const double cost = static_cast<double>(box.halfArea()) * i + rightCost[i];
        if (cost < bestCost) bestCost = cost, bestAxis = a, bestLeftCount = i;
      }
    }

    const bool split = bestAxis >= 0 ? shouldSplit(static_cast<uint32_t>(n), leafSize_, bounds.halfArea(), kSahBrushCost * bestCost)
                                     : n > static_cast<size_t>(leafSize_);
    if (!split) {
      nodes_[slot].leftFirst = static_cast<uint32_t>(order_.size());
      nodes_[slot].count = static_cast<uint32_t>(n);
      order_.insert(order_.end(), items.begin(), items.end());
      return;
    }
    if (bestAxis < 0) bestAxis = 0, bestLeftCount = n / 2; // all centroids coincide
    std::vector<uint32_t> left(sorted[bestAxis].begin(), sorted[bestAxis].begin() + bestLeftCount);
    std::vector<uint32_t> right(sorted[bestAxis].begin() + bestLeftCount, sorted[bestAxis].end());
    items.clear();
    items.shrink_to_fit();
    const uint32_t children = static_cast<uint32_t>(nodes_.size());
    nodes_[slot].leftFirst = children;
    nodes_[slot].count = 0;
    nodes_.push_back({});
    nodes_.push_back({});
    buildNode(children, left);
    buildNode(children + 1, right);
  }

  std::span<const Aabb> boxes_;
  int leafSize_;
  std::vector<GpuBvhNode> nodes_;
  std::vector<uint32_t> order_;
};

} // namespace

FlatBvh buildFullSweepSah(std::span<const Aabb> boxes, int leafSize) {
  return FullSweepBuilder(boxes, leafSize).build();
}

} // namespace bt::test
