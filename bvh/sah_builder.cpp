#include "bvh/sah_builder.h"

#include "bvh/binned_sah/isa_builds.h"

#include <cstddef>
#include <stdexcept>
#include <utility>

namespace bt {

namespace {

void checkBoxCount(std::span<const Aabb> boxes) {
  // The median split's depth bound (see kMedianSplitDepth in binned_sah/builder.h) holds up to 2^24 boxes.
  if (boxes.size() > size_t{1} << 24) throw std::invalid_argument("buildBinnedSah: more than 2^24 boxes");
}

float halfArea(const GpuBvhNode& n) {
  const float x = n.boundsMax[0] - n.boundsMin[0];
  const float y = n.boundsMax[1] - n.boundsMin[1];
  const float z = n.boundsMax[2] - n.boundsMin[2];
  return x * y + y * z + z * x;
}

} // namespace

void resizeSlots(std::vector<GpuBvhNode>& slots, size_t count) {
  slots.resize(count);
}

bool binnedSahAvx2Usable() {
#if defined(BT_SAH_BUILDER_AVX2)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings) {
  checkBoxCount(boxes); // the builder checks the boxes themselves as it reads them
#if defined(BT_SAH_BUILDER_AVX2)
  if (binnedSahAvx2Usable()) return avx2::buildBinnedSah(boxes, settings);
#endif
  return sse2::buildBinnedSah(boxes, settings);
}

FlatBvh buildBinnedSahBaseline(std::span<const Aabb> boxes, const SahBuildSettings& settings) {
  checkBoxCount(boxes);
  return sse2::buildBinnedSah(boxes, settings);
}

std::vector<GpuBvhNode> compactDepthFirst(std::span<const GpuBvhNode> nodes) {
  std::vector<GpuBvhNode> out;
  if (nodes.empty()) return out;
  // Sized for every node, then cut to those reachable: appending through push_back, a call per
  // node, cost as much as the copying.
  out.resize(nodes.size());
  GpuBvhNode* placed = out.data();
  size_t used = 1;
  placed[0] = nodes[0];
  // (index in `nodes`, index in `out`) of interior nodes whose children are still to be placed.
  std::vector<std::pair<uint32_t, uint32_t>> stack;
  stack.reserve(2 * kBvhMaxDepth);
  if (nodes[0].count == 0) stack.push_back({0, 0});
  while (!stack.empty()) {
    const auto [from, to] = stack.back();
    stack.pop_back();
    const uint32_t left = nodes[from].leftFirst;
    if (used + 2 > out.size()) throw std::logic_error("compactDepthFirst: nodes do not form a tree");
    const uint32_t first = static_cast<uint32_t>(used);
    placed[to].leftFirst = first;
    placed[first] = nodes[left];
    placed[first + 1] = nodes[left + 1];
    used += 2;
    // Right first on the stack so the left subtree is laid out next: depth-first order.
    if (nodes[left + 1].count == 0) stack.push_back({left + 1, first + 1});
    if (nodes[left].count == 0) stack.push_back({left, first});
  }
  out.resize(used);
  return out;
}

double sahCost(std::span<const GpuBvhNode> nodes) {
  if (nodes.empty()) return 0.0;
  const double rootArea = halfArea(nodes[0]);
  if (!(rootArea > 0.0)) return 0.0;
  double cost = 0.0;
  for (const GpuBvhNode& n : nodes) cost += n.count == 0 ? kSahTraversalCost * halfArea(n) : kSahBrushCost * n.count * halfArea(n);
  return cost / rootArea;
}

} // namespace bt
