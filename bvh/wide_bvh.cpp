#include "bvh/wide_bvh.h"

#include <limits>

namespace bt {

namespace {

// A lane to be: a box and what lies in it.
struct Lane {
  const float* lo;
  const float* hi;
  uint32_t child, count;
  uint32_t binary; // its binary node, to expand (kNoNode: a brush or a leaf lane as it is)
};
constexpr uint32_t kNoNode = ~0u;

struct Collapse {
  std::span<const GpuBvhNode> nodes;
  std::span<const GpuBrush> brushes;
  std::vector<WideBvhNode> wide;

  // A leaf of two to four brushes becomes a node of brush lanes; a larger one (a leafSize above
  // four) stays a leaf lane.
  static bool split(const GpuBvhNode& n) { return n.count >= 2 && n.count <= 4; }

  Lane lane(uint32_t binary) const {
    const GpuBvhNode& n = nodes[binary];
    const bool expand = n.count == 0 || split(n);
    return {n.boundsMin, n.boundsMax, n.leftFirst, expand ? 0u : n.count, expand ? binary : kNoNode};
  }

  // A node of `count` lanes; the unused ones NaN.
  static WideBvhNode node(const Lane* lanes, uint32_t count) {
    WideBvhNode out{};
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (uint32_t k = 0; k < 4; ++k)
      for (int a = 0; a < 3; ++a) out.lo[a][k] = out.hi[a][k] = nan;
    for (uint32_t k = 0; k < count; ++k) {
      for (int a = 0; a < 3; ++a) out.lo[a][k] = lanes[k].lo[a], out.hi[a][k] = lanes[k].hi[a];
      out.child[k] = lanes[k].child;
      out.count[k] = lanes[k].count;
    }
    return out;
  }

  // The lanes of wide node `at` from binary node `binary`: an inner node's children, an inner
  // child replaced by its own two (a leaf child to be split stays one lane); a leaf's brushes.
  void fill(uint32_t at, uint32_t binary) {
    Lane lanes[4];
    uint32_t count = 0;
    const GpuBvhNode& n = nodes[binary];
    if (n.count > 0) {
      for (uint32_t b = n.leftFirst; b < n.leftFirst + n.count; ++b)
        lanes[count++] = {brushes[b].boundsMin, brushes[b].boundsMax, b, 1, kNoNode};
    } else {
      for (uint32_t c = n.leftFirst; c < n.leftFirst + 2; ++c) {
        if (nodes[c].count > 0) {
          lanes[count++] = lane(c);
        } else {
          lanes[count++] = lane(nodes[c].leftFirst);
          lanes[count++] = lane(nodes[c].leftFirst + 1);
        }
      }
    }
    wide[at] = node(lanes, count);
    // Lanes to expand get their wide nodes after this one, depth first.
    for (uint32_t k = 0; k < count; ++k) {
      if (lanes[k].binary == kNoNode) continue;
      const uint32_t index = uint32_t(wide.size());
      wide.emplace_back();
      wide[at].child[k] = index;
      fill(index, lanes[k].binary);
    }
  }
};

} // namespace

std::vector<WideBvhNode> collapseToWide(std::span<const GpuBvhNode> nodes, std::span<const GpuBrush> brushes) {
  if (nodes.empty()) return {};
  Collapse c{nodes, brushes, {}};
  c.wide.reserve(nodes.size());
  c.wide.emplace_back();
  if (nodes[0].count > 0 && !Collapse::split(nodes[0])) {
    // A root leaf too large to split: its one lane.
    const Lane root = c.lane(0);
    c.wide[0] = Collapse::node(&root, 1);
  } else {
    c.fill(0, 0);
  }
  return std::move(c.wide);
}

} // namespace bt
