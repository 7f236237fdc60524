// Binned SAH BVH builder over axis-aligned boxes (Wald, "On fast Construction of SAH-based
// Bounding Volume Hierarchies", 2007), the part of TraceScene that knows nothing about brushes.
#pragma once

#include "scene/gpu_structs.h"

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace bt {

// A float box; empty when min > max (the default).
struct Aabb {
  glm::vec3 min{std::numeric_limits<float>::infinity()};
  glm::vec3 max{-std::numeric_limits<float>::infinity()};

  void grow(const Aabb& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
  }
  void grow(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
  }
  bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
  // Half the surface area: SAH only ever uses ratios of areas. Zero for an empty box.
  float halfArea() const {
    if (empty()) return 0.0f;
    const glm::vec3 e = max - min;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  }
};

// SAH cost model: cost = sum over interior nodes of area(node) / area(root) * kSahTraversalCost
//                      + sum over leaves of area(leaf) / area(root) * count * kSahBrushCost.
// A brush test costs a slab test plus a few planes, a node a slab test; but a miss on a
// brush's box, the common case, costs the same as a node, hence 1 : 1 (as tinybvh uses).
inline constexpr double kSahTraversalCost = 1.0;
inline constexpr double kSahBrushCost = 1.0;

struct SahBuildSettings {
  int leafSize = 4; // see BvhBuildOptions
  int binCount = 32;
  int threads = 0; // 0 = all cores
};

struct FlatBvh {
  std::vector<GpuBvhNode> nodes; // layout of GpuBvhNode; leaves index `order`
  std::vector<uint32_t> order;   // order[i]: the input box that leaf slot i holds
};

// Builds the BVH of `boxes` (none may be empty or have a non-finite bound; std::invalid_argument
// otherwise). The result does not depend on `threads`.
FlatBvh buildBinnedSah(std::span<const Aabb> boxes, const SahBuildSettings& settings);
// The same build compiled for the x86-64 baseline only; buildBinnedSah() runs an AVX2
// compilation of it where binnedSahAvx2Usable(). Both give the same tree; the tests compare them.
FlatBvh buildBinnedSahBaseline(std::span<const Aabb> boxes, const SahBuildSettings& settings);
// Whether the library holds an AVX2 compilation of the builder (GCC or Clang on x86-64) and the
// CPU runs it: where not, buildBinnedSah() is buildBinnedSahBaseline().
bool binnedSahAvx2Usable();

// The SAH decision that every builder here shares (the test suite's full-sweep reference
// included), in units of half-areas: a node is split when it holds more than leafSize
// boxes, or when its best split is cheaper than intersecting all of its boxes.
// bestSplitChildCost = kSahBrushCost * (area(left) * count(left) + area(right) * count(right)).
inline bool shouldSplit(uint32_t count, int leafSize, double nodeArea, double bestSplitChildCost) {
  if (count <= 1) return false;
  if (count > static_cast<uint32_t>(leafSize)) return true;
  const double leafCost = kSahBrushCost * count * nodeArea;
  const double splitCost = kSahTraversalCost * nodeArea + bestSplitChildCost;
  return splitCost < leafCost;
}

// The SAH cost of a flattened BVH by the cost model above (0 for an empty or flat-zero-area one).
double sahCost(std::span<const GpuBvhNode> nodes);

// Flattens a tree whose children sit anywhere in `nodes` (children pairs adjacent) into
// depth-first order with the root at 0 and each pair of children next to each other.
std::vector<GpuBvhNode> compactDepthFirst(std::span<const GpuBvhNode> nodes);

} // namespace bt
