#include "renderer/gl/gl_wide_bvh.h"

#include "renderer/gl/gl_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace bt::gl {

namespace {

constexpr int kWidth = 8;
constexpr uint32_t kLeafBits = kGlWideInnerBit; // the walk's hit mask: a node's leaf children hold at most this many primitives

struct Box {
  float lo[3] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  float hi[3] = {std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest()};
  void grow(const GpuBvhNode& n) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], n.boundsMin[a]), hi[a] = std::max(hi[a], n.boundsMax[a]);
  }
};

float halfArea(const GpuBvhNode& n) {
  const float dx = n.boundsMax[0] - n.boundsMin[0], dy = n.boundsMax[1] - n.boundsMin[1], dz = n.boundsMax[2] - n.boundsMin[2];
  return dx * dy + dy * dz + dz * dx;
}

// Up to 8 binary nodes.
struct Children {
  std::array<uint32_t, kWidth> node;
  size_t size = 0;
};

// The binary nodes a wide node built from interior node `b` holds: b's children, the interior
// one with the largest surface area opened until 8 are held or none is interior.
Children collapsedChildren(std::span<const GpuBvhNode> nodes, uint32_t b) {
  Children children{{nodes[b].leftFirst, nodes[b].leftFirst + 1}, 2};
  std::array<float, kWidth> area; // an interior child's, -1 for a leaf
  const auto areaOf = [&](uint32_t n) { return nodes[n].count == 0 ? halfArea(nodes[n]) : -1.0f; };
  area[0] = areaOf(children.node[0]), area[1] = areaOf(children.node[1]);
  while (children.size < kWidth) {
    const size_t open = size_t(std::max_element(area.begin(), area.begin() + children.size) - area.begin());
    if (area[open] < 0.0f) break;
    const uint32_t opened = children.node[open];
    children.node[open] = nodes[opened].leftFirst;
    area[open] = areaOf(children.node[open]);
    children.node[children.size] = nodes[opened].leftFirst + 1;
    area[children.size++] = areaOf(nodes[opened].leftFirst + 1);
  }
  return children;
}

// The paper's octant rule: slot s (bit a set: rays going negative along axis a) takes the child
// whose centre lies furthest back along s's diagonal, so that a ray of octant s meets it first;
// greedily, cheapest (child, slot) pair first. Returns the child of each slot, -1 for none. Up
// to 4 children take slots 0-3 (by the signs along x and y alone), so that the walk tests one
// word of slots instead of two (trace_wide.glsl intersectWideNode).
std::array<int, kWidth> slotsByOctant(std::span<const GpuBvhNode> nodes, const Children& children, const Box& box) {
  const int slots = children.size <= kWidth / 2 ? kWidth / 2 : kWidth;
  float cost[kWidth][kWidth];         // [child][slot]
  std::array<int, kWidth> bestSlot{}; // each unplaced child's cheapest free slot
  for (size_t c = 0; c < children.size; ++c) {
    const GpuBvhNode& n = nodes[children.node[c]];
    float offset[3];
    for (int a = 0; a < 3; ++a) offset[a] = (n.boundsMin[a] + n.boundsMax[a]) - (box.lo[a] + box.hi[a]);
    for (int s = 0; s < slots; ++s) {
      cost[c][s] = (s & 1 ? -offset[0] : offset[0]) + (s & 2 ? -offset[1] : offset[1]) + (s & 4 ? -offset[2] : offset[2]);
      if (cost[c][s] < cost[c][bestSlot[c]]) bestSlot[c] = s;
    }
  }
  std::array<int, kWidth> slotChild;
  slotChild.fill(-1);
  std::array<bool, kWidth> placed{};
  for (size_t round = 0; round < children.size; ++round) {
    int child = -1;
    for (size_t c = 0; c < children.size; ++c)
      if (!placed[c] && (child < 0 || cost[c][bestSlot[c]] < cost[child][bestSlot[child]])) child = int(c);
    const int slot = bestSlot[child];
    slotChild[slot] = child;
    placed[child] = true;
    for (size_t c = 0; c < children.size; ++c) { // those that wanted the slot take their next best
      if (placed[c] || bestSlot[c] != slot) continue;
      int best = -1;
      for (int s = 0; s < slots; ++s)
        if (slotChild[s] < 0 && (best < 0 || cost[c][s] < cost[c][best])) best = s;
      bestSlot[c] = best;
    }
  }
  return slotChild;
}

float scaleOf(uint8_t exponent) {
  return std::bit_cast<float>(uint32_t(exponent) << 23);
}

// Axis a's exponent and the slots' 8-bit bounds: floor and ceil, then stepped outwards until the
// shader's float arithmetic (origin + q * scale: the product is exact) holds the exact bound.
void quantise(GlWideNode& node, int a, const std::array<const GpuBvhNode*, kWidth>& slots) {
  const float origin = node.origin[a];
  float extent = 0.0f;
  for (const GpuBvhNode* n : slots)
    if (n) extent = std::max(extent, n->boundsMax[a] - origin);
  // The smallest power of two with 255 steps over the extent (255 * 2^(ilogb - 8) is below it),
  // at least 2^-100 (so that no q * scale is subnormal, which GPUs flush to zero).
  int e = -100;
  if (extent > 0.0f) {
    e = std::max(e, std::ilogb(extent) - 8);
    while (std::ldexp(255.0f, e) < extent) ++e;
  }
  for (;; ++e) {
    if (e + 127 > 254) throw GlError("a BVH node's box is too large for the wide layout");
    const uint8_t exponent = uint8_t(e + 127);
    const float scale = scaleOf(exponent), inverse = 1.0f / scale; // exact: powers of two
    bool fits = true;
    for (int s = 0; s < kWidth && fits; ++s) {
      const GpuBvhNode* n = slots[s];
      if (!n) continue;
      // A first guess (truncation is floor for these non-negative values), then the exact rule.
      const float lo = std::max((n->boundsMin[a] - origin) * inverse, 0.0f), hi = std::max((n->boundsMax[a] - origin) * inverse, 0.0f);
      int qlo = int(std::min(lo, 255.0f)), qhi = int(std::min(hi, 255.0f));
      qhi += qhi < 255 && float(qhi) < hi;
      while (qlo > 0 && origin + float(qlo) * scale > n->boundsMin[a]) --qlo;
      while (qhi < 255 && origin + float(qhi) * scale < n->boundsMax[a]) ++qhi;
      fits = origin + float(qlo) * scale <= n->boundsMin[a] && origin + float(qhi) * scale >= n->boundsMax[a];
      node.qlo[a][s] = uint8_t(qlo);
      node.qhi[a][s] = uint8_t(qhi);
    }
    if (fits) {
      node.exponent[a] = exponent;
      return;
    }
  }
}

// A wide node to make: from binary interior node `binary` (or the root leaf of a one-leaf tree),
// or, with count > 0, for primitives first .. + count of binary leaf `binary`, too many for one
// leaf child: a node of leaf children (or of such nodes) that all take the leaf's box.
struct Pending {
  uint32_t binary;
  uint32_t wide;
  uint32_t depth;
  uint32_t first = 0, count = 0;
};

// Makes the wide nodes, numbering interior children as they are placed.
class Collapse {
public:
  Collapse(std::span<const GpuBvhNode> nodes, uint32_t firstRow, WideBvh& out) : nodes_(nodes), firstRow_(firstRow), out_(out) {}

  void make(const Pending& p) {
    GlWideNode node{};
    node.childBase = firstRow_ + kGlWideNodeRows * uint32_t(out_.nodes.size());
    node.leafBase = uint32_t(out_.order.size());
    std::array<const GpuBvhNode*, kWidth> boxes{};
    inner_.clear();
    if (p.count > 0) {
      makeRange(node, boxes, p);
    } else {
      const Children children = nodes_[p.binary].count > 0 ? Children{{p.binary}, 1} : collapsedChildren(nodes_, p.binary);
      Box box;
      for (size_t c = 0; c < children.size; ++c) box.grow(nodes_[children.node[c]]);
      std::copy(std::begin(box.lo), std::end(box.lo), node.origin);
      const std::array<int, kWidth> slotChild = slotsByOctant(nodes_, children, box);
      for (int s = 0; s < kWidth; ++s) {
        if (slotChild[s] < 0) continue;
        const uint32_t b = children.node[slotChild[s]];
        boxes[s] = &nodes_[b];
        if (nodes_[b].count > 0)
          placeLeaf(node, s, b, nodes_[b].leftFirst, nodes_[b].count, p.depth);
        else
          placeInner(node, s, {b, 0, p.depth + 1});
      }
    }
    for (int a = 0; a < 3; ++a) quantise(node, a, boxes);
    out_.nodes[p.wide] = node;
    out_.nodes.resize(out_.nodes.size() + inner_.size());
  }
  const std::vector<Pending>& inner() const { return inner_; } // the last node's interior children, in slot order

private:
  std::span<const GpuBvhNode> nodes_;
  uint32_t firstRow_;
  WideBvh& out_;
  std::vector<Pending> inner_;

  void placeInner(GlWideNode& node, int slot, Pending child) {
    node.imask |= uint8_t(1u << slot);
    node.meta[slot] = wideInnerMeta(slot);
    child.wide = uint32_t(out_.nodes.size() + inner_.size());
    inner_.push_back(child);
  }

  // A leaf child where it fits the meta byte and the node's 32 leaf bits, else a node of its own.
  void placeLeaf(GlWideNode& node, int slot, uint32_t binary, uint32_t first, uint32_t count, uint32_t depth) {
    const uint32_t offset = uint32_t(out_.order.size()) - node.leafBase;
    if (count > kGlWideLeafMaxCount || offset + count > kLeafBits) return placeInner(node, slot, {binary, 0, depth + 1, first, count});
    node.meta[slot] = wideLeafMeta(count, offset);
    for (uint32_t i = first; i < first + count; ++i) out_.order.push_back(i);
  }

  // Part of a binary leaf: up to 24 primitives as leaf children of kGlWideLeafMaxCount at most,
  // more as up to 8 parts, each again such a node or a leaf child.
  void makeRange(GlWideNode& node, std::array<const GpuBvhNode*, kWidth>& boxes, const Pending& p) {
    const GpuBvhNode& leaf = nodes_[p.binary];
    std::copy(std::begin(leaf.boundsMin), std::end(leaf.boundsMin), node.origin);
    const uint32_t part = p.count <= kLeafBits ? kGlWideLeafMaxCount : (p.count + kWidth - 1) / kWidth;
    for (uint32_t s = 0, first = p.first; first < p.first + p.count; ++s, first += part) {
      boxes[s] = &leaf;
      placeLeaf(node, int(s), p.binary, first, std::min(part, p.first + p.count - first), p.depth);
    }
  }
};

} // namespace

void wideChildBox(const GlWideNode& node, int slot, float lo[3], float hi[3]) {
  for (int a = 0; a < 3; ++a) {
    const float scale = scaleOf(node.exponent[a]);
    lo[a] = node.origin[a] + float(node.qlo[a][slot]) * scale;
    hi[a] = node.origin[a] + float(node.qhi[a][slot]) * scale;
  }
}

// Depth first, each node's interior children given consecutive numbers as the node is made, so
// that siblings are neighbours and a subtree lies together.
WideBvh collapseBvh(std::span<const GpuBvhNode> nodes, uint32_t firstRow) {
  WideBvh out;
  out.nodes.push_back(GlWideNode{});
  out.depth = 1;
  if (nodes.empty()) return out; // a root without children
  Collapse collapse(nodes, firstRow, out);
  std::vector<Pending> todo{{0, 0, 1}};
  while (!todo.empty()) {
    const Pending p = todo.back();
    todo.pop_back();
    out.depth = std::max(out.depth, p.depth);
    if (p.depth > kGlWideMaxDepth)
      throw GlError(fmt::format("the wide BVH is deeper than {} levels (BT_GL_BVH=binary traces it)", kGlWideMaxDepth));
    collapse.make(p);
    todo.insert(todo.end(), collapse.inner().rbegin(), collapse.inner().rend());
  }
  return out;
}

namespace {

// `records` (of `bytes` bytes each) in the order `order`, appended to `words`.
template <class T> void appendInOrder(std::vector<uint32_t>& words, std::span<const T> records, const std::vector<uint32_t>& order) {
  static_assert(sizeof(T) % 4 == 0);
  const size_t start = words.size();
  words.resize(start + order.size() * sizeof(T) / 4);
  for (size_t i = 0; i < order.size(); ++i) std::memcpy(words.data() + start + i * sizeof(T) / 4, &records[order[i]], sizeof(T));
}

void appendNodes(std::vector<uint32_t>& words, const std::vector<GlWideNode>& nodes) {
  const size_t start = words.size();
  words.resize(start + nodes.size() * sizeof(GlWideNode) / 4);
  std::memcpy(words.data() + start, nodes.data(), nodes.size() * sizeof(GlWideNode));
}

} // namespace

WideScene wideSceneForGl(const TraceScene& tracer, std::span<const GpuBrush> brushRecords) {
  const WideBvh brushes = collapseBvh(tracer.nodes(), 1);
  GlWideHeader header{1, kGlNoChild, uint32_t(tracer.brushes().size_bytes() / 16), 0};
  WideBvh triangles;
  if (!tracer.triangleNodes().empty()) {
    header.triangleRoot = 1 + kGlWideNodeRows * uint32_t(brushes.nodes.size());
    triangles = collapseBvh(tracer.triangleNodes(), header.triangleRoot);
  }
  WideScene out;
  out.brushDepth = brushes.depth;
  out.triangleDepth = triangles.depth;
  out.nodeWords.resize(sizeof header / 4);
  std::memcpy(out.nodeWords.data(), &header, sizeof header);
  appendNodes(out.nodeWords, brushes.nodes);
  appendNodes(out.nodeWords, triangles.nodes);
  appendInOrder(out.primitiveWords, brushRecords, brushes.order);
  appendInOrder(out.primitiveWords, tracer.triangles(), triangles.order);
  return out;
}

} // namespace bt::gl
