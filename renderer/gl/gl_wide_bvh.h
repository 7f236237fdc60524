// TraceScene's binary BVH collapsed into the compressed 8-wide nodes of the GPU walk's wide
// layout (gl_structs.h GlWideNode, shaders/trace_wide.glsl).
#pragma once

#include "bvh/trace_scene.h"
#include "renderer/gl/gl_structs.h"

#include <span>
#include <vector>

namespace bt::gl {

// One tree: nodes[0] is the root; interior children are numbered in rows of the node buffer,
// node k at firstRow + kGlWideNodeRows * k. order[i] is the binary tree's primitive (its leaves'
// index) at position i of the wide order, which leafBase and the metas index.
struct WideBvh {
  std::vector<GlWideNode> nodes;
  std::vector<uint32_t> order;
  uint32_t depth = 0; // levels of nodes, 1 for the root alone
};

// The collapse, in linear time: from the binary root down, each wide node takes its binary
// node's two children and opens the interior one with the largest surface area until it holds 8
// (or only leaves), as the greedy collapse of Ylitie et al. (their SAH collapse is the better
// tree, the greedy one builds in a fraction of the binary build). Children go to the slots by
// the paper's octant rule, boxes quantised outwards. A leaf child holds at most
// kGlWideLeafMaxCount primitives and a node's leaf children 24 (the walk's hit mask): a binary
// leaf that does not fit becomes a node of its own, of leaf children that all take its box.
// Throws GlError for a tree deeper than kGlWideMaxDepth.
WideBvh collapseBvh(std::span<const GpuBvhNode> nodes, uint32_t firstRow);

// Child slot `slot`'s box of `node` as the shader computes it (trace_wide.glsl).
void wideChildBox(const GlWideNode& node, int slot, float lo[3], float hi[3]);

// What the wide layout uploads: the node buffer's rows (GlWideHeader, then the brushes' tree,
// then the triangles') and the brush buffer's (`brushes`, the tracer's as uploaded, in their
// tree's wide order, then the triangles in theirs, 3 rows each).
struct WideScene {
  std::vector<uint32_t> nodeWords;
  std::vector<uint32_t> primitiveWords;
  uint32_t brushDepth = 0, triangleDepth = 0;
};
WideScene wideSceneForGl(const TraceScene& tracer, std::span<const GpuBrush> brushes);

} // namespace bt::gl
