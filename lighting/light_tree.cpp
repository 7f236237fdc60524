#include "lighting/light_tree.h"

#include "lighting/physical_light.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace bt {

namespace {

// A light's reach is padded so that the window the importance computes at a node stays above
// zero wherever physical::falloff's own window is (both round in float).
constexpr float kReachRelativeSlack = 1e-3f;
constexpr float kReachSlack = 1.0f;

// Binned SAH: split candidates per axis, as pbrt-v4's BVHLightSampler does.
constexpr int kBins = 12;

struct TreeLight {
  glm::vec3 lo, hi; // its jitter cube (faithful_light.h jitteredOrigin), a point without _deviance
  glm::vec3 centroid;
  float power;
  float reach; // padded; +infinity for a light that never ends
  uint32_t light;
};

struct Bounds3 {
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  void add(const glm::vec3& a, const glm::vec3& b) { lo = glm::min(lo, a), hi = glm::max(hi, b); }
  float area() const {
    if (lo.x > hi.x) return 0.0f;
    const glm::vec3 e = hi - lo;
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

// pbrt-v4's split cost without the orientation term (every light is omnidirectional here):
// power x surface area, times how much longer the box's longest side is than the split axis's,
// which keeps the children from growing thin along other axes.
float splitCost(float power, const Bounds3& b, float kr) {
  return power * b.area() * kr;
}

int binIndex(float centroid, float lo, float extent) {
  return std::min(int(float(kBins) * (centroid - lo) / extent), kBins - 1);
}

// Where to split items [first, end): the best bin boundary over the three axes, as the item
// count left of it; 0 when no split beats none (all centroids in one place).
uint32_t bestSplit(std::vector<TreeLight>& items, uint32_t first, uint32_t end, const Bounds3& box) {
  Bounds3 centroids;
  for (uint32_t i = first; i < end; ++i) centroids.add(items[i].centroid, items[i].centroid);
  const glm::vec3 extent = centroids.hi - centroids.lo, diagonal = box.hi - box.lo;
  const float longest = std::max({diagonal.x, diagonal.y, diagonal.z});
  float bestCost = std::numeric_limits<float>::infinity();
  int bestAxis = -1, bestBin = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!(extent[axis] > 0.0f)) continue;
    std::array<Bounds3, kBins> bins;
    std::array<float, kBins> power{};
    for (uint32_t i = first; i < end; ++i) {
      const int b = binIndex(items[i].centroid[axis], centroids.lo[axis], extent[axis]);
      bins[b].add(items[i].lo, items[i].hi);
      power[b] += items[i].power;
    }
    const float kr = diagonal[axis] > 0.0f ? longest / diagonal[axis] : 1.0f;
    for (int split = 1; split < kBins; ++split) {
      Bounds3 left, right;
      float powerLeft = 0.0f, powerRight = 0.0f;
      for (int b = 0; b < split; ++b) left.add(bins[b].lo, bins[b].hi), powerLeft += power[b];
      for (int b = split; b < kBins; ++b) right.add(bins[b].lo, bins[b].hi), powerRight += power[b];
      const float cost = splitCost(powerLeft, left, kr) + splitCost(powerRight, right, kr);
      if (cost < bestCost) bestCost = cost, bestAxis = axis, bestBin = split;
    }
  }
  if (bestAxis < 0) return 0;
  const auto middle = std::partition(items.begin() + first, items.begin() + end, [&](const TreeLight& t) {
    return binIndex(t.centroid[bestAxis], centroids.lo[bestAxis], extent[bestAxis]) < bestBin;
  });
  return uint32_t(middle - items.begin()) - first;
}

void buildNode(std::vector<TreeLight>& items, uint32_t first, uint32_t end, std::vector<LightTreeNode>& nodes) {
  Bounds3 box;
  float power = 0.0f, reach = 0.0f;
  for (uint32_t i = first; i < end; ++i) {
    box.add(items[i].lo, items[i].hi);
    power += items[i].power;
    reach = std::max(reach, items[i].reach);
  }
  const size_t self = nodes.size();
  nodes.push_back({box.lo, power, box.hi, std::isfinite(reach) ? 1.0f / reach : 0.0f, 0, 0});
  if (end - first == 1) {
    nodes[self].light = items[first].light;
    return;
  }
  uint32_t left = bestSplit(items, first, end, box);
  if (left == 0 || left == end - first) left = (end - first) / 2; // lights in one place: halve the list
  buildNode(items, first, first + left, nodes);
  nodes[self].second = uint32_t(nodes.size());
  buildNode(items, first + left, end, nodes);
}

} // namespace

std::vector<LightTreeNode> buildLightTree(const std::vector<GpuLight>& lights, std::span<const uint32_t> candidates, float scaledist) {
  std::vector<TreeLight> items;
  for (uint32_t i : candidates) {
    const GpuLight& l = lights[i];
    const float reach = physical::reach(l, scaledist);
    const float power = physical::colourSum(l.color) * physical::intensity(l, scaledist, reach);
    if (!(power > 0.0f)) continue;
    const glm::vec3 jitter(std::max(l.deviance, 0.0f) * (1.0f + kReachRelativeSlack));
    const float padded = std::isfinite(reach) ? reach * (1.0f + kReachRelativeSlack) + kReachSlack : reach;
    items.push_back({l.origin - jitter, l.origin + jitter, l.origin, power, padded, i});
  }
  std::vector<LightTreeNode> nodes;
  if (!items.empty()) buildNode(items, 0, uint32_t(items.size()), nodes);
  return nodes;
}

float lightNodeImportance(const LightTreeNode& node, const glm::vec3& p, const glm::vec3& n) {
  // The window at the box's nearest point, with the largest reach: no member's is larger there.
  const glm::vec3 nearest = glm::clamp(p, node.lo, node.hi) - p;
  const float x2 = glm::dot(nearest, nearest) * node.invReach * node.invReach;
  float window = std::clamp(1.0f - x2 * x2, 0.0f, 1.0f);
  window *= window;
  if (!(window > 0.0f)) return 0.0f;
  // The box's bounding sphere seen from p: the smallest angle between n and a direction into it.
  const glm::vec3 d = 0.5f * (node.lo + node.hi) - p, half = 0.5f * (node.hi - node.lo);
  const float d2 = glm::dot(d, d), r2 = glm::dot(half, half);
  float cosBound = 1.0f; // p inside the sphere: any direction
  if (d2 > r2) {
    const float cosTheta = glm::dot(n, d) / std::sqrt(d2);
    const float sin2Sphere = r2 / d2, cosSphere = std::sqrt(1.0f - sin2Sphere);
    // cos(max(theta - sphere's half angle, 0))
    if (cosTheta < cosSphere)
      cosBound = cosTheta * cosSphere + std::sqrt(std::max(1.0f - cosTheta * cosTheta, 0.0f)) * std::sqrt(sin2Sphere);
  }
  if (!(cosBound > 0.0f)) return 0.0f;
  const float distance2 = std::max(d2, r2);
  if (!(distance2 > 0.0f)) return 0.0f; // p on a light without extent: no direction to it
  return node.power * window * cosBound / distance2;
}

LightPick pickLightFromTree(std::span<const LightTreeNode> nodes, const glm::vec3& p, const glm::vec3& n, float u) {
  LightPick pick;
  if (nodes.empty() || !(lightNodeImportance(nodes[0], p, n) > 0.0f)) return pick;
  constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
  uint32_t node = 0;
  float pdf = 1.0f;
  while (nodes[node].second != 0) {
    const uint32_t a = node + 1, b = nodes[node].second;
    const float ia = lightNodeImportance(nodes[a], p, n), ib = lightNodeImportance(nodes[b], p, n);
    if (!(ia + ib > 0.0f)) return pick;
    const float pa = ia / (ia + ib);
    if (u < pa) {
      node = a, pdf *= pa;
      u = std::min(u / pa, kOneMinusEpsilon);
    } else {
      node = b, pdf *= 1.0f - pa;
      u = std::min((u - pa) / (1.0f - pa), kOneMinusEpsilon);
    }
  }
  pick.found = pdf > 0.0f;
  pick.light = nodes[node].light;
  pick.pdf = pdf;
  return pick;
}

} // namespace bt
