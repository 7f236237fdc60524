#include "lighting/light_grid.h"
#include "lighting/faithful.h"
#include "lighting/light_tree.h"
#include "lighting/physical_light.h"
#include "scene/parallel_for.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

namespace bt {

namespace {

// Cells no smaller than this (a typical light reaches 200-300 units, so finer cells only repeat
// the lists).
constexpr float kMinCellSize = 64.0f;

// Reach padding: distanceValue() is computed in float, so a point a hair beyond the exact reach
// may still round to a tiny non-zero value; the lists must never miss it.
constexpr float kReachRelativeSlack = 1e-3f;
constexpr float kReachSlack = 1.0f;

// How far a _deviance jitter moves a light: its copies fill the cube of half-size deviance
// (faithful_light.h jitteredOrigin), whose corners are sqrt(3) deviance away.
float maxJitter(const GpuLight& light) {
  return std::sqrt(3.0f) * std::max(light.deviance, 0.0f);
}

// Physical mode's point lights: negative lights have no physical meaning, local minlight is a
// faithful floor, and points spread over _surface faces are area emitters there instead.
bool isPhysicalCandidate(const GpuLight& l) {
  return l.type == uint32_t(LightType::Point) && l.formula != uint32_t(LightFormula::LocalMin) && l.value > 0.0f &&
      !(l.flags & kLightFlagFromSurface);
}

bool isFaithfulCandidate(const GpuLight& l) {
  return l.type == uint32_t(LightType::Point) && l.formula != uint32_t(LightFormula::LocalMin) && l.value != 0.0f;
}

// A cell's box, where a side at the grid's border extends to infinity: a point outside the grid
// is looked up in the border cell, so that cell lists the lights that reach anything beyond it.
struct CellBox {
  glm::vec3 lo, hi;
};

CellBox cellBox(const GpuLightGrid& g, const uint32_t cell[3]) {
  CellBox box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = cell[a] == 0 ? -std::numeric_limits<float>::infinity() : g.origin[a] + float(cell[a]) * g.cellSize;
    box.hi[a] = cell[a] + 1 == g.dims[a] ? std::numeric_limits<float>::infinity() : g.origin[a] + float(cell[a] + 1) * g.cellSize;
  }
  return box;
}

// Squared distance from the box [pointsLo, pointsHi] to the cell.
float distanceToCell2(const CellBox& cell, const glm::vec3& pointsLo, const glm::vec3& pointsHi) {
  float d2 = 0.0f;
  for (int a = 0; a < 3; ++a) {
    const float d = pointsHi[a] < cell.lo[a] ? cell.lo[a] - pointsHi[a] : (pointsLo[a] > cell.hi[a] ? pointsLo[a] - cell.hi[a] : 0.0f);
    d2 += d * d;
  }
  return d2;
}

float distanceToCell2(const CellBox& cell, const glm::vec3& p) {
  return distanceToCell2(cell, p, p);
}

// A bounce light lights only what lies in front of its face (faithful::emitterTerm: 0 behind its
// plane), so a cell wholly behind it, by more than float rounding at Quake's extents, never sees
// it: the farthest of the cell's corners along the light's normal (summed over the axes where
// the normal has a component; infinite at a border) is below -kBehindMargin. About half of a
// level's cells lie behind any one face.
constexpr float kBehindMargin = 1.0f;

uint32_t clampedCell(const GpuLightGrid& g, int axis, float coordinate) {
  const float f = (coordinate - g.origin[axis]) / g.cellSize;
  if (!(f >= 0.0f)) return 0; // also NaN
  if (f >= float(g.dims[axis])) return g.dims[axis] - 1;
  return std::min(uint32_t(f), g.dims[axis] - 1);
}

GpuLightGrid gridOver(const Bounds& bounds, uint32_t maxCellsPerAxis) {
  GpuLightGrid g;
  if (bounds.empty()) return g; // one cell, extended to infinity on every side
  maxCellsPerAxis = std::max(maxCellsPerAxis, 1u);
  const glm::vec3 lo(bounds.min), hi(bounds.max);
  const glm::vec3 extent = hi - lo;
  const float longest = std::max({extent.x, extent.y, extent.z});
  g.origin = lo;
  g.cellSize = std::max(longest / float(maxCellsPerAxis), kMinCellSize);
  for (int a = 0; a < 3; ++a) g.dims[a] = std::clamp(uint32_t(std::ceil(extent[a] / g.cellSize)), 1u, maxCellsPerAxis);
  return g;
}

// --- Physical near lists -----------------------------------------------------------------------
//
// A cell lists the kPhysicalNearLights lights of largest rank key (nearKey), the largest first,
// ties to the lower light index. Ranking each of a large level's ~2,700 lights in each of its
// ~20,000 cells took most of the level's preparation; instead the lights sit in a tree of
// spatial groups, each with a bound of its members' keys (a light BVH), and a cell opens a group
// only when that bound can beat the last light of its list so far. Starting from a neighbour's
// list, a cell ranks about a hundred lights instead of all. The lists are exactly those of
// ranking every light (tests/render/light_selection_test.cpp compares them).

// Rank key: an upper bound of a light's irradiance in the cell, power / d^2, d the distance from
// the (jittered) light to the cell, at least half a cell (nearest2 = that squared) so that
// lights inside the cell do not all tie at infinity.
float nearKey(float distance2, float jitter, float power, float nearest2) {
  const float d = std::max(std::sqrt(distance2) - jitter, 0.0f);
  return power / std::max(d * d, nearest2);
}

// A light's ranking inputs side by side (a GpuLight is 96 bytes, of which this reads 5 floats).
struct NearCandidate {
  glm::vec3 origin;
  float jitter;
  float power;
  uint32_t light;
};

// Candidates [first, end) and what bounds their keys: every float operation in nearKey rounds
// monotonically, so with the box's distance (no larger than any member's), the largest jitter
// and the largest power it gives a key no smaller than any member's, exactly, not only up to
// rounding. A node of a binary tree over the candidates, in depth-first order: an inner node's
// first child follows it, its second child is at `second`.
struct CandidateNode {
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  float jitter = 0.0f, power = 0.0f;
  uint32_t first = 0, end = 0;
  uint32_t second = 0; // 0 for a leaf
};

// Leaves of at most this many lights: few enough that a cell does not rank many lights it does
// not keep, enough that the tree stays shallow.
constexpr uint32_t kNearLeafSize = 8;

// Splits candidates [first, end) at the median of their box's longest axis until a part is
// small enough for a leaf.
void buildCandidateTree(std::vector<NearCandidate>& candidates, uint32_t first, uint32_t end, std::vector<CandidateNode>& nodes) {
  const size_t self = nodes.size();
  CandidateNode node;
  node.first = first;
  node.end = end;
  for (uint32_t i = first; i < end; ++i) {
    const NearCandidate& c = candidates[i];
    node.lo = glm::min(node.lo, c.origin);
    node.hi = glm::max(node.hi, c.origin);
    node.jitter = std::max(node.jitter, c.jitter);
    node.power = std::max(node.power, c.power);
  }
  nodes.push_back(node);
  if (end - first <= kNearLeafSize) return;
  const glm::vec3 extent = node.hi - node.lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  const uint32_t middle = first + (end - first) / 2;
  std::nth_element(candidates.begin() + first, candidates.begin() + middle, candidates.begin() + end,
                   [axis](const NearCandidate& a, const NearCandidate& b) { return a.origin[axis] < b.origin[axis]; });
  buildCandidateTree(candidates, first, middle, nodes);
  nodes[self].second = uint32_t(nodes.size());
  buildCandidateTree(candidates, middle, end, nodes);
}

// The best lights found so far for one cell, best first: the largest key, then the lower light
// index, the order of a sort over every light, whatever order they are found in.
class NearList {
public:
  struct Entry {
    float key;
    uint32_t light;
    uint32_t candidate; // its place in NearRanking's candidates
  };
  uint32_t size() const { return size_; }
  const Entry& operator[](uint32_t i) const { return entries_[i]; }
  bool full() const { return size_ == kPhysicalNearLights; }
  float lastKey() const { return entries_[size_ - 1].key; }
  bool admits(float key, uint32_t light) const { return !full() || before(key, light, entries_[size_ - 1]); }
  // Only what admits(): the last entry of a full list drops out.
  void insert(const Entry& e) {
    uint32_t at = full() ? size_ - 1 : size_++;
    for (; at > 0 && before(e.key, e.light, entries_[at - 1]); --at) entries_[at] = entries_[at - 1];
    entries_[at] = e;
  }

private:
  static bool before(float key, uint32_t light, const Entry& e) { return key > e.key || (key == e.key && light < e.light); }
  std::array<Entry, kPhysicalNearLights> entries_{};
  uint32_t size_ = 0;
};

class NearRanking {
public:
  // power: the light's physical intensity times its emitted colour's channels summed
  // (physical_light.h colourSum, as the pick's selectionWeight has it); its window only
  // lowers the light further out, so power / d^2 stays a bound.
  NearRanking(const GpuLightGrid& g, const std::vector<GpuLight>& lights, std::span<const uint32_t> physical, float scaledist)
      : grid_(g), nearest2_(0.25f * g.cellSize * g.cellSize) {
    for (uint32_t i : physical) {
      const GpuLight& l = lights[i];
      const float power = physical::colourSum(l.color) * physical::intensity(l, scaledist);
      if (power > 0.0f) candidates_.push_back({l.origin, maxJitter(l), power, i});
    }
    if (!candidates_.empty()) buildCandidateTree(candidates_, 0, uint32_t(candidates_.size()), nodes_);
  }

  size_t candidateCount() const { return candidates_.size(); }

  // The list of `cell`, starting from the lights of `hint`: a neighbour's list, most of which
  // ranks high here too, so that few groups can beat its last key. rankedFor[c] == stamp marks
  // the candidates this cell has ranked already; stamp must differ from cell to cell.
  NearList rank(const uint32_t cell[3], const NearList& hint, std::vector<uint32_t>& rankedFor, uint32_t stamp) const {
    const CellBox box = cellBox(grid_, cell);
    NearList list;
    auto consider = [&](uint32_t c) {
      if (rankedFor[c] == stamp) return;
      rankedFor[c] = stamp;
      const NearCandidate& light = candidates_[c];
      const float distance2 = distanceToCell2(box, light.origin);
      if (list.full() && ranksBelow(distance2, light.jitter, light.power, list.lastKey())) return;
      const float key = nearKey(distance2, light.jitter, light.power, nearest2_);
      if (list.admits(key, light.light)) list.insert({key, light.light, c});
    };
    for (uint32_t i = 0; i < hint.size(); ++i) consider(hint[i].candidate);
    // The tree, the nearer child first. A member ties with the last entry at best when a bound
    // equals its key; it may still win on its index then, so only a smaller bound rules a node out.
    struct Pending {
      uint32_t node;
      float distance2; // from the node's box to the cell
    };
    std::array<Pending, 64> stack; // depth-first: at most one pending node per level, plus one
    uint32_t depth = 0;
    if (!nodes_.empty()) stack[depth++] = {0, distanceToCell2(box, nodes_[0].lo, nodes_[0].hi)};
    while (depth > 0) {
      const Pending pending = stack[--depth];
      const CandidateNode& node = nodes_[pending.node];
      if (list.full() && ranksBelow(pending.distance2, node.jitter, node.power, list.lastKey())) continue;
      if (node.second == 0) {
        for (uint32_t c = node.first; c < node.end; ++c) consider(c);
        continue;
      }
      const CandidateNode &first = nodes_[pending.node + 1], &second = nodes_[node.second];
      const Pending a{pending.node + 1, distanceToCell2(box, first.lo, first.hi)};
      const Pending b{node.second, distanceToCell2(box, second.lo, second.hi)};
      stack[depth++] = a.distance2 <= b.distance2 ? b : a;
      stack[depth++] = a.distance2 <= b.distance2 ? a : b;
    }
    return list;
  }

private:
  // Whether every light of at most this power and jitter, at a squared distance from the cell of
  // at least distance2, ranks below `key`. nearKey is monotonic in each input (see
  // CandidateNode); without jitter the test skips its square root and division, with a margin
  // far above their few roundings, so it never rules out a light that nearKey would rank at
  // `key` or above.
  bool ranksBelow(float distance2, float jitter, float power, float key) const {
    constexpr float kRoundingMargin = 1.0f + 1e-5f;
    if (jitter > 0.0f) return nearKey(distance2, jitter, power, nearest2_) < key;
    return power * kRoundingMargin < key * std::max(distance2, nearest2_);
  }

  GpuLightGrid grid_;
  float nearest2_;
  std::vector<NearCandidate> candidates_; // in the tree's order: a node holds a range of it
  std::vector<CandidateNode> nodes_;
};

} // namespace

float faithfulReach(const GpuLight& light, float scaledist) {
  float reach = std::numeric_limits<float>::infinity();
  if (light.formula == uint32_t(LightFormula::Linear)) {
    // faithful::distanceValue: _falloff wins; otherwise value - dist * wait * _dist hits 0.
    if (light.falloff > 0.0f)
      reach = light.falloff;
    else if (scaledist * light.atten > 0.0f)
      reach = std::abs(light.value) / (scaledist * light.atten);
  } else if (light.formula == uint32_t(LightFormula::Q3Point) || light.formula == uint32_t(LightFormula::Q3Linear) ||
             light.formula == uint32_t(LightFormula::Q3Area)) {
    reach = light.falloff; // faithful::q3map2Value: q3map2's envelope
  } else if (light.formula == uint32_t(LightFormula::Bounce)) {
    // faithful::pointLightValue: value / d^2 (both cosines at most 1) under the gate gives 0.
    reach = std::sqrt(std::max(light.value * light.faithfulScale * faithful::maxChannel(light.color), 0.0f) / faithful::kBounceGate);
  }
  if (!std::isfinite(reach)) return reach;
  return (reach + maxJitter(light)) * (1.0f + kReachRelativeSlack) + kReachSlack;
}

size_t trailingBounceLights(const std::vector<GpuLight>& lights, std::span<const uint32_t> list) {
  size_t count = 0;
  while (count < list.size() && lights[list[list.size() - 1 - count]].formula == uint32_t(LightFormula::Bounce)) ++count;
  return count;
}

std::span<const uint32_t> LightGrid::physicalNearLights(const glm::vec3& p) const {
  const size_t cellCount = size_t(header.dims[0]) * header.dims[1] * header.dims[2];
  const GpuLightCell& c = cells[cellCount + lightGridCell(header, p)];
  return {indices.data() + c.first, c.count};
}

std::span<const uint32_t> LightGrid::physicalRestLights(const glm::vec3& p) const {
  const size_t cellCount = size_t(header.dims[0]) * header.dims[1] * header.dims[2];
  const GpuLightCell& c = cells[2 * cellCount + lightGridCell(header, p)];
  return {indices.data() + c.first, c.count};
}

std::span<const uint32_t> LightGrid::cellLights(const glm::vec3& p) const {
  const GpuLightCell& c = cells[lightGridCell(header, p)];
  return {indices.data() + c.first, c.count};
}

uint32_t lightGridCell(const GpuLightGrid& g, const glm::vec3& p) {
  return clampedCell(g, 0, p.x) + g.dims[0] * (clampedCell(g, 1, p.y) + g.dims[1] * clampedCell(g, 2, p.z));
}

namespace {

// Suns, domes and local minlights: looked at everywhere, one by one.
bool isFixed(const GpuLight& l) {
  return l.type != uint32_t(LightType::Point) || l.formula == uint32_t(LightFormula::LocalMin);
}

bool hasInfiniteReach(const GpuLight& l, float scaledist) {
  return isFaithfulCandidate(l) && !std::isfinite(faithfulReach(l, scaledist));
}

// One axis's terms of distanceToCell2 (the squared distance from the light's origin to the
// cell's slab) and of the test behind a bounce light (kBehindMargin: the farthest the slab
// reaches along the light's normal, 0 where the normal has no component): listing a light
// tests every cell in its reach, and a cell's test is then two sums of three terms.
struct CellTerms {
  float distance2 = 0.0f;
  float farthest = 0.0f;
};

CellTerms cellTerms(const GpuLightGrid& g, int axis, uint32_t c, const GpuLight& light) {
  uint32_t cell[3] = {0, 0, 0};
  cell[axis] = c;
  const CellBox box = cellBox(g, cell);
  const float lo = box.lo[axis], hi = box.hi[axis], p = light.origin[axis], d = light.direction[axis];
  const float distance = p < lo ? lo - p : (p > hi ? p - hi : 0.0f);
  return {distance * distance, d != 0.0f ? d * ((d > 0.0f ? hi : lo) - p) : 0.0f};
}

// 0 (every core, at most one per z-slice) where a grid's work is large enough to share.
unsigned gridThreads(size_t lights, const GpuLightGrid& g) {
  return lights * g.dims[0] * g.dims[1] * g.dims[2] < 100000 ? 1u : 0u;
}

// The finite-reach faithful lights among lights[first, end) in every cell their reach sphere
// touches: a large level's thousands of lights reach thousands of cells each, so the z-slices of
// cells are shared among threads (each slice takes the lights in the order below, so the lists do
// not depend on the threads). Bounce lights last, so that they end every cell's list
// (trailingBounceLights): the others, then the bounce lights, in index order.
std::vector<std::vector<uint32_t>> finiteReachLists(const GpuLightGrid& g, const std::vector<GpuLight>& lights, uint32_t first,
                                                    float scaledist) {
  const size_t cellCount = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  struct Reach {
    uint32_t light;
    uint32_t lo[3], hi[3]; // the cells of its reach box
  };
  std::vector<uint32_t> order;
  for (uint32_t i = first; i < lights.size(); ++i) order.push_back(i);
  std::stable_partition(order.begin(), order.end(), [&](uint32_t i) { return lights[i].formula != uint32_t(LightFormula::Bounce); });
  std::vector<Reach> reaches;
  for (uint32_t i : order) {
    if (!isFaithfulCandidate(lights[i])) continue;
    const float reach = faithfulReach(lights[i], scaledist);
    if (!std::isfinite(reach)) continue;
    Reach r{i, {}, {}};
    for (int a = 0; a < 3; ++a) {
      r.lo[a] = clampedCell(g, a, lights[i].origin[a] - reach);
      r.hi[a] = clampedCell(g, a, lights[i].origin[a] + reach);
    }
    reaches.push_back(r);
  }
  std::vector<std::vector<uint32_t>> lists(cellCount);
  parallelFor(g.dims[2], gridThreads(reaches.size(), g), [&](size_t slice) {
    const uint32_t z = uint32_t(slice);
    std::array<std::vector<CellTerms>, 2> row; // the x and y terms of the light being listed
    for (const Reach& r : reaches) {
      if (z < r.lo[2] || z > r.hi[2]) continue;
      const GpuLight& l = lights[r.light];
      const float reach = faithfulReach(l, scaledist);
      const float reach2 = reach * reach;
      const bool bounce = l.formula == uint32_t(LightFormula::Bounce);
      for (int a = 0; a < 2; ++a) {
        row[a].resize(g.dims[a]);
        for (uint32_t c = r.lo[a]; c <= r.hi[a]; ++c) row[a][c] = cellTerms(g, a, c, l);
      }
      const CellTerms tz = cellTerms(g, 2, z, l);
      for (uint32_t y = r.lo[1]; y <= r.hi[1]; ++y) {
        const CellTerms& ty = row[1][y];
        // The sums grow with the x term (>= 0): a row out of reach without it stays out.
        if (ty.distance2 + tz.distance2 > reach2) continue;
        for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
          const CellTerms& tx = row[0][x];
          // distanceToCell2 and the test behind a bounce light, each summed x, y, z.
          if ((tx.distance2 + ty.distance2) + tz.distance2 <= reach2 &&
              !(bounce && (tx.farthest + ty.farthest) + tz.farthest < -kBehindMargin))
            lists[x + g.dims[0] * (y + g.dims[1] * size_t(z))].push_back(r.light);
        }
      }
    }
  });
  return lists;
}

// Per cell, the physical candidates whose windowed reach touches it and that its near list does
// not hold, in index order: what the pick's uniform draw chooses among. A light beyond its reach
// gives exactly 0 (physical::falloff's window), so leaving it out keeps the estimate unbiased,
// and the draw's probability is that of one light among the few that can matter, not among the
// level's thousands (a pick of 1 in 2,685 on lq_e4m3 made fireflies that 4,096 spp did not
// average out). `near`: kPhysicalNearLights entries a cell, `nearCounts` of them used.
std::vector<std::vector<uint32_t>> physicalRestLists(const GpuLightGrid& g, const std::vector<GpuLight>& lights,
                                                     std::span<const uint32_t> physical, const std::vector<uint32_t>& near,
                                                     const std::vector<uint32_t>& nearCounts, float scaledist) {
  const size_t cellCount = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  struct Reach {
    uint32_t light;
    float padded;          // reach + jitter, with the lists' slack; infinite: every cell
    uint32_t lo[3], hi[3]; // the cells of its reach box
  };
  std::vector<Reach> reaches;
  for (uint32_t i : physical) {
    const float reach = physical::reach(lights[i], scaledist);
    Reach r{i, std::numeric_limits<float>::infinity(), {0, 0, 0}, {g.dims[0] - 1, g.dims[1] - 1, g.dims[2] - 1}};
    if (std::isfinite(reach)) {
      r.padded = (reach + maxJitter(lights[i])) * (1.0f + kReachRelativeSlack) + kReachSlack;
      for (int a = 0; a < 3; ++a) {
        r.lo[a] = clampedCell(g, a, lights[i].origin[a] - r.padded);
        r.hi[a] = clampedCell(g, a, lights[i].origin[a] + r.padded);
      }
    }
    reaches.push_back(r);
  }
  std::sort(reaches.begin(), reaches.end(), [](const Reach& a, const Reach& b) { return a.light < b.light; });
  std::vector<std::vector<uint32_t>> lists(cellCount);
  parallelFor(g.dims[2], gridThreads(reaches.size(), g), [&](size_t slice) {
    uint32_t cell[3] = {0, 0, uint32_t(slice)};
    for (const Reach& r : reaches) {
      if (cell[2] < r.lo[2] || cell[2] > r.hi[2]) continue;
      for (cell[1] = r.lo[1]; cell[1] <= r.hi[1]; ++cell[1])
        for (cell[0] = r.lo[0]; cell[0] <= r.hi[0]; ++cell[0]) {
          const size_t k = cell[0] + g.dims[0] * (cell[1] + g.dims[1] * size_t(cell[2]));
          if (std::isfinite(r.padded) && distanceToCell2(cellBox(g, cell), lights[r.light].origin) > r.padded * r.padded) continue;
          const auto nearBegin = near.begin() + std::ptrdiff_t(k * kPhysicalNearLights);
          if (std::find(nearBegin, nearBegin + nearCounts[k], r.light) != nearBegin + nearCounts[k]) continue;
          lists[k].push_back(r.light);
        }
    }
  });
  return lists;
}

} // namespace

LightGrid buildLightGrid(const std::vector<GpuLight>& lights, const Bounds& bounds, float scaledist, uint32_t maxCellsPerAxis) {
  LightGrid grid;
  grid.header = gridOver(bounds, maxCellsPerAxis);
  const GpuLightGrid& g = grid.header;

  for (uint32_t i = 0; i < lights.size(); ++i)
    if (isFixed(lights[i])) grid.indices.push_back(i);
  grid.header.fixedCount = uint32_t(grid.indices.size());

  grid.header.globalFirst = uint32_t(grid.indices.size());
  for (uint32_t i = 0; i < lights.size(); ++i)
    if (hasInfiniteReach(lights[i], scaledist)) grid.indices.push_back(i);
  grid.header.globalCount = uint32_t(grid.indices.size()) - grid.header.globalFirst;

  grid.header.physicalFirst = uint32_t(grid.indices.size());
  for (uint32_t i = 0; i < lights.size(); ++i)
    if (isPhysicalCandidate(lights[i])) grid.indices.push_back(i);
  grid.header.physicalCount = uint32_t(grid.indices.size()) - grid.header.physicalFirst;

  const size_t cellCount = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  const std::vector<std::vector<uint32_t>> lists = finiteReachLists(g, lights, 0, scaledist);
  grid.cells.resize(3 * cellCount);
  for (size_t k = 0; k < cellCount; ++k) {
    grid.cells[k] = {uint32_t(grid.indices.size()), uint32_t(lists[k].size())};
    grid.indices.insert(grid.indices.end(), lists[k].begin(), lists[k].end());
  }

  grid.physicalTree = buildLightTree(lights, grid.physicalLights(), scaledist);

  // Physical near lists: every cell on the same threads; each cell's list depends on nothing else.
  const NearRanking ranking(g, lights, grid.physicalLights(), scaledist);
  std::vector<uint32_t> nearLists(cellCount * kPhysicalNearLights);
  std::vector<uint32_t> nearCounts(cellCount);
  parallelFor(g.dims[2], gridThreads(ranking.candidateCount(), g), [&](size_t slice) {
    const uint32_t z = uint32_t(slice);
    std::vector<uint32_t> rankedFor(ranking.candidateCount(), 0);
    // Each cell starts from its neighbour's list: the cell before it in the row, or for a row's
    // first cell the first cell of the row before.
    NearList previous, rowStart;
    uint32_t cell[3] = {0, 0, z};
    for (cell[1] = 0; cell[1] < g.dims[1]; ++cell[1])
      for (cell[0] = 0; cell[0] < g.dims[0]; ++cell[0]) {
        const size_t k = cell[0] + g.dims[0] * (cell[1] + g.dims[1] * size_t(cell[2]));
        const NearList list = ranking.rank(cell, cell[0] == 0 ? rowStart : previous, rankedFor, uint32_t(k) + 1);
        nearCounts[k] = list.size();
        for (uint32_t r = 0; r < list.size(); ++r) nearLists[k * kPhysicalNearLights + r] = list[r].light;
        if (cell[0] == 0) rowStart = list;
        previous = list;
      }
  });
  for (size_t k = 0; k < cellCount; ++k) {
    grid.cells[cellCount + k] = {uint32_t(grid.indices.size()), nearCounts[k]};
    grid.indices.insert(grid.indices.end(), nearLists.begin() + k * kPhysicalNearLights,
                        nearLists.begin() + k * kPhysicalNearLights + nearCounts[k]);
  }
  const std::vector<std::vector<uint32_t>> rest = physicalRestLists(g, lights, grid.physicalLights(), nearLists, nearCounts, scaledist);
  for (size_t k = 0; k < cellCount; ++k) {
    grid.cells[2 * cellCount + k] = {uint32_t(grid.indices.size()), uint32_t(rest[k].size())};
    grid.indices.insert(grid.indices.end(), rest[k].begin(), rest[k].end());
  }
  return grid;
}

LightGrid extendLightGrid(const LightGrid& grid, const std::vector<GpuLight>& lights, uint32_t first, const Bounds& bounds, float scaledist,
                          uint32_t maxCellsPerAxis) {
  // A physical candidate among the new lights changes the near lists: those are ranked anew.
  for (uint32_t i = first; i < lights.size(); ++i)
    if (isPhysicalCandidate(lights[i])) return buildLightGrid(lights, bounds, scaledist, maxCellsPerAxis);

  LightGrid out;
  out.header = grid.header;
  const GpuLightGrid& g = out.header;
  // Each list is in index order and the new lights come after the old: they follow them.
  auto append = [&](std::span<const uint32_t> old, auto&& belongs) {
    const uint32_t at = uint32_t(out.indices.size());
    out.indices.insert(out.indices.end(), old.begin(), old.end());
    for (uint32_t i = first; i < lights.size(); ++i)
      if (belongs(lights[i])) out.indices.push_back(i);
    return std::pair{at, uint32_t(out.indices.size()) - at};
  };
  out.header.fixedCount = append(grid.fixedLights(), isFixed).second;
  std::tie(out.header.globalFirst, out.header.globalCount) =
      append(grid.globalLights(), [&](const GpuLight& l) { return hasInfiniteReach(l, scaledist); });
  std::tie(out.header.physicalFirst, out.header.physicalCount) = append(grid.physicalLights(), [](const GpuLight&) { return false; });

  // A cell's list: its old lights other than bounce lights, the new ones, then the old bounce
  // lights and the new ones (the order buildLightGrid gives them).
  const size_t cellCount = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  const std::vector<std::vector<uint32_t>> added = finiteReachLists(g, lights, first, scaledist);
  out.cells.resize(3 * cellCount);
  for (size_t k = 0; k < cellCount; ++k) {
    const std::span<const uint32_t> old(grid.indices.data() + grid.cells[k].first, grid.cells[k].count);
    const std::span<const uint32_t> more(added[k]);
    const size_t oldBounce = trailingBounceLights(lights, old), moreBounce = trailingBounceLights(lights, more);
    out.cells[k] = {uint32_t(out.indices.size()), uint32_t(old.size() + more.size())};
    for (const std::span<const uint32_t> part :
         {old.first(old.size() - oldBounce), more.first(more.size() - moreBounce), old.last(oldBounce), more.last(moreBounce)})
      out.indices.insert(out.indices.end(), part.begin(), part.end());
  }
  // The near and rest lists and the tree hold the physical candidates only: unchanged.
  out.physicalTree = grid.physicalTree;
  for (size_t k = cellCount; k < 3 * cellCount; ++k) {
    const GpuLightCell& list = grid.cells[k];
    out.cells[k] = {uint32_t(out.indices.size()), list.count};
    out.indices.insert(out.indices.end(), grid.indices.begin() + list.first, grid.indices.begin() + list.first + list.count);
  }
  return out;
}

} // namespace bt
