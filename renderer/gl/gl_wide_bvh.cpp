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
constexpr uint32_t kLeafBits = 32; // the walk's leaf mask: a node's leaf children hold at most this many primitives

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

// The binary nodes a wide node built from interior node `b` holds: b's children, the interior
// one with the largest surface area opened until 8 are held or none is interior.
std::vector<uint32_t> collapsedChildren(std::span<const GpuBvhNode> nodes, uint32_t b) {
  std::vector<uint32_t> children{nodes[b].leftFirst, nodes[b].leftFirst + 1};
  while (children.size() < kWidth) {
    int open = -1;
    float openArea = -1.0f;
    for (size_t i = 0; i < children.size(); ++i)
      if (nodes[children[i]].count == 0 && halfArea(nodes[children[i]]) > openArea) open = int(i), openArea = halfArea(nodes[children[i]]);
    if (open < 0) break;
    const uint32_t opened = children[open];
    children[open] = nodes[opened].leftFirst;
    children.push_back(nodes[opened].leftFirst + 1);
  }
  return children;
}

// The paper's octant rule: slot s (bit a set: rays going negative along axis a) takes the child
// whose centre lies furthest back along s's diagonal, so that a ray of octant s meets it first;
// greedily, cheapest (child, slot) pair first. Returns the child of each slot, -1 for none.
std::array<int, kWidth> slotsByOctant(std::span<const GpuBvhNode> nodes, const std::vector<uint32_t>& children, const Box& box) {
  std::array<int, kWidth> slotChild;
  slotChild.fill(-1);
  std::array<bool, kWidth> placed{};
  for (size_t round = 0; round < children.size(); ++round) {
    float best = std::numeric_limits<float>::max();
    int bestChild = -1, bestSlot = -1;
    for (size_t c = 0; c < children.size(); ++c) {
      if (placed[c]) continue;
      const GpuBvhNode& n = nodes[children[c]];
      for (int s = 0; s < kWidth; ++s) {
        if (slotChild[s] >= 0) continue;
        float cost = 0.0f;
        for (int a = 0; a < 3; ++a) {
          const float offset = (n.boundsMin[a] + n.boundsMax[a]) - (box.lo[a] + box.hi[a]);
          cost += (s >> a & 1) ? -offset : offset;
        }
        if (cost < best) best = cost, bestChild = int(c), bestSlot = s;
      }
    }
    slotChild[bestSlot] = bestChild;
    placed[bestChild] = true;
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
  // The smallest power of two with 255 steps over the extent, at least 2^-100 (so that no q *
  // scale is subnormal, which GPUs flush to zero).
  int e = -100;
  if (extent > 0.0f) e = std::max(e, int(std::ceil(std::log2(double(extent) / 255.0))));
  for (;; ++e) {
    if (e + 127 > 254) throw GlError("a BVH node's box is too large for the wide layout");
    const uint8_t exponent = uint8_t(e + 127);
    const float scale = scaleOf(exponent);
    bool fits = true;
    for (int s = 0; s < kWidth && fits; ++s) {
      const GpuBvhNode* n = slots[s];
      if (!n) continue;
      double qlo = std::clamp(std::floor(double(n->boundsMin[a] - origin) / scale), 0.0, 255.0);
      double qhi = std::clamp(std::ceil(double(n->boundsMax[a] - origin) / scale), 0.0, 255.0);
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

struct Pending {
  uint32_t binary; // the binary node (interior, or the root leaf of a one-leaf tree)
  uint32_t wide;
  uint32_t depth;
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
  std::vector<Pending> todo{{0, 0, 1}};
  while (!todo.empty()) {
    const Pending p = todo.back();
    todo.pop_back();
    out.depth = std::max(out.depth, p.depth);
    if (p.depth > kGlWideMaxDepth)
      throw GlError(fmt::format("the wide BVH is deeper than {} levels (BT_GL_BVH=binary traces it)", kGlWideMaxDepth));
    const std::vector<uint32_t> children = nodes[p.binary].count > 0 ? std::vector<uint32_t>{p.binary} : collapsedChildren(nodes, p.binary);
    Box box;
    for (uint32_t c : children) box.grow(nodes[c]);
    const std::array<int, kWidth> slotChild = slotsByOctant(nodes, children, box);
    GlWideNode node{};
    std::copy(std::begin(box.lo), std::end(box.lo), node.origin);
    node.childBase = firstRow + kGlWideNodeRows * uint32_t(out.nodes.size());
    node.leafBase = uint32_t(out.order.size());
    std::array<const GpuBvhNode*, kWidth> slots{};
    std::vector<Pending> inner;
    for (int s = 0; s < kWidth; ++s) {
      if (slotChild[s] < 0) continue;
      const uint32_t b = children[slotChild[s]];
      const GpuBvhNode& n = nodes[b];
      slots[s] = &n;
      if (n.count == 0) {
        node.imask |= uint8_t(1u << s);
        node.meta[s] = kGlWideInner;
        inner.push_back({b, uint32_t(out.nodes.size() + inner.size()), p.depth + 1});
        continue;
      }
      const uint32_t offset = uint32_t(out.order.size()) - node.leafBase;
      if (n.count > kGlWideLeafMaxCount || offset + n.count > kLeafBits)
        throw GlError(fmt::format("a BVH leaf of {} primitives is too large for the wide layout (at most {}, {} a node; BT_GL_BVH=binary "
                                  "traces it)",
                                  n.count, kGlWideLeafMaxCount, kLeafBits));
      node.meta[s] = uint8_t(n.count << 5 | offset);
      for (uint32_t i = n.leftFirst; i < n.leftFirst + n.count; ++i) out.order.push_back(i);
    }
    for (int a = 0; a < 3; ++a) quantise(node, a, slots);
    out.nodes[p.wide] = node;
    out.nodes.resize(out.nodes.size() + inner.size());
    todo.insert(todo.end(), inner.rbegin(), inner.rend());
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

WideScene wideSceneForGl(const TraceScene& tracer) {
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
  appendInOrder(out.primitiveWords, tracer.brushes(), brushes.order);
  appendInOrder(out.primitiveWords, tracer.triangles(), triangles.order);
  return out;
}

} // namespace bt::gl
