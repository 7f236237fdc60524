// The brush BVH with four children a node, for the CPU's closest-hit walk (TraceScene::closestHit;
// the any-hit walks and the GL tracer keep the binary nodes): the binary SAH tree (GpuBvhNode)
// collapsed, each node taking its grandchildren in place of its inner children, so that one SSE
// pass tests four boxes. The boxes are the binary tree's own (and the brushes'), so the walk
// tests every brush against the same node boxes, the same floats, as the binary walk does
// (trace_scene.h's rules hold unchanged); camera and bounce rays: lq_e4m3's physical render
// spends a quarter of its time in this walk.
#pragma once

#include "scene/gpu_structs.h"

#include <cstdint>
#include <span>
#include <vector>

namespace bt {

// Four child boxes side by side, one lane per child, 128 bytes. A lane with count > 0 is a leaf,
// brushes[child .. child + count) of TraceScene::brushes(); count == 0 an inner node,
// wide nodes[child]. An unused lane's box is NaN, which every comparison of the node test
// rejects.
struct alignas(16) WideBvhNode {
  float lo[3][4]; // [axis][lane]: the box's minimum
  float hi[3][4];
  uint32_t child[4];
  uint32_t count[4];
};
static_assert(sizeof(WideBvhNode) == 128);

// The wide tree of a binary one (nodes[0] its root; empty gives empty) over `brushes` (the
// leaves' slots). A binary leaf of two or more brushes becomes a node of its own whose lanes are
// its brushes, one each, their own boxes: the walk rejects most brushes of a leaf it reaches on
// their boxes, four at once, before it reads them. A binary root that is a leaf becomes one node
// with that leaf's lanes. Lanes keep the binary order (left before right).
std::vector<WideBvhNode> collapseToWide(std::span<const GpuBvhNode> nodes, std::span<const GpuBrush> brushes);

// A wide walk's stack holds up to three entries pushed per level, a wide level being at least one
// binary level below the one before.
inline constexpr uint32_t kWideBvhStackSize = 3 * kBvhMaxDepth + 1;

} // namespace bt
