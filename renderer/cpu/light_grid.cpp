#include "renderer/cpu/light_grid.h"
#include "renderer/cpu/faithful.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

namespace bt {

namespace {

// Grid resolution: at most this many cells along the longest axis, and cells no smaller than
// kMinCellSize (a typical light reaches 200-300 units, so finer cells only repeat the lists).
constexpr uint32_t kMaxCellsPerAxis = 32;
constexpr float kMinCellSize = 64.0f;

// Reach padding: distanceValue() is computed in float, so a point a hair beyond the exact reach
// may still round to a tiny non-zero value; the lists must never miss it.
constexpr float kReachRelativeSlack = 1e-3f;
constexpr float kReachSlack = 1.0f;

// How far a _deviance jitter moves a light: its copies fill the cube of half-size deviance
// (integrator.cpp jitteredOrigin), whose corners are sqrt(3) deviance away.
float maxJitter(const GpuLight& light) { return std::sqrt(3.0f) * std::max(light.deviance, 0.0f); }

// Physical mode's point lights: negative lights have no physical meaning, local minlight is a
// faithful floor, and points spread over _surface faces are area emitters there instead.
bool isPhysicalCandidate(const GpuLight& l) {
  return l.type == uint32_t(LightType::Point) && l.formula != uint32_t(LightFormula::LocalMin) && l.value > 0.0f &&
         !(l.flags & kLightFlagFromSurface);
}

bool isFaithfulCandidate(const GpuLight& l) {
  return l.type == uint32_t(LightType::Point) && l.formula != uint32_t(LightFormula::LocalMin) && l.value != 0.0f;
}

// Squared distance from c to the box, where a side at the grid's border extends to infinity:
// a point outside the grid is looked up in the border cell, so that cell lists the lights that
// reach anything beyond it.
float distanceToCell2(const GpuLightGrid& g, const uint32_t cell[3], const glm::vec3& c) {
  float d2 = 0.0f;
  for (int a = 0; a < 3; ++a) {
    const float lo = cell[a] == 0 ? -std::numeric_limits<float>::infinity() : g.origin[a] + float(cell[a]) * g.cellSize;
    const float hi = cell[a] + 1 == g.dims[a] ? std::numeric_limits<float>::infinity()
                                              : g.origin[a] + float(cell[a] + 1) * g.cellSize;
    const float d = c[a] < lo ? lo - c[a] : (c[a] > hi ? c[a] - hi : 0.0f);
    d2 += d * d;
  }
  return d2;
}

uint32_t clampedCell(const GpuLightGrid& g, int axis, float coordinate) {
  const float f = (coordinate - g.origin[axis]) / g.cellSize;
  if (!(f >= 0.0f)) return 0; // also NaN
  if (f >= float(g.dims[axis])) return g.dims[axis] - 1;
  return std::min(uint32_t(f), g.dims[axis] - 1);
}

GpuLightGrid gridOver(const Bounds& bounds) {
  GpuLightGrid g;
  if (bounds.empty()) return g; // one cell, extended to infinity on every side
  const glm::vec3 lo(bounds.min), hi(bounds.max);
  const glm::vec3 extent = hi - lo;
  const float longest = std::max({extent.x, extent.y, extent.z});
  g.origin = lo;
  g.cellSize = std::max(longest / float(kMaxCellsPerAxis), kMinCellSize);
  for (int a = 0; a < 3; ++a)
    g.dims[a] = std::clamp(uint32_t(std::ceil(extent[a] / g.cellSize)), 1u, kMaxCellsPerAxis);
  return g;
}

} // namespace

float faithfulReach(const GpuLight& light, float scaledist) {
  float reach = std::numeric_limits<float>::infinity();
  if (light.formula == uint32_t(LightFormula::Linear)) {
    // faithful::distanceValue: _falloff wins; otherwise value - dist * wait * _dist hits 0.
    if (light.falloff > 0.0f) reach = light.falloff;
    else if (scaledist * light.atten > 0.0f) reach = std::abs(light.value) / (scaledist * light.atten);
  } else if (light.formula == uint32_t(LightFormula::Bounce)) {
    // faithful::pointLightValue: value / d^2 (both cosines at most 1) under the gate gives 0.
    reach = std::sqrt(std::max(light.value * light.faithfulScale * faithful::maxChannel(light.color), 0.0f) / faithful::kBounceGate);
  }
  if (!std::isfinite(reach)) return reach;
  return (reach + maxJitter(light)) * (1.0f + kReachRelativeSlack) + kReachSlack;
}

std::span<const uint32_t> LightGrid::physicalNearLights(const glm::vec3& p) const {
  const size_t cellCount = size_t(header.dims[0]) * header.dims[1] * header.dims[2];
  const GpuLightCell& c = cells[cellCount + lightGridCell(header, p)];
  return {indices.data() + c.first, c.count};
}

std::span<const uint32_t> LightGrid::cellLights(const glm::vec3& p) const {
  const GpuLightCell& c = cells[lightGridCell(header, p)];
  return {indices.data() + c.first, c.count};
}

uint32_t lightGridCell(const GpuLightGrid& g, const glm::vec3& p) {
  return clampedCell(g, 0, p.x) + g.dims[0] * (clampedCell(g, 1, p.y) + g.dims[1] * clampedCell(g, 2, p.z));
}

LightGrid buildLightGrid(const std::vector<GpuLight>& lights, const Bounds& bounds, float scaledist) {
  LightGrid grid;
  grid.header = gridOver(bounds);
  const GpuLightGrid& g = grid.header;

  for (uint32_t i = 0; i < lights.size(); ++i)
    if (lights[i].type != uint32_t(LightType::Point) || lights[i].formula == uint32_t(LightFormula::LocalMin))
      grid.indices.push_back(i);
  grid.header.fixedCount = uint32_t(grid.indices.size());

  grid.header.globalFirst = uint32_t(grid.indices.size());
  for (uint32_t i = 0; i < lights.size(); ++i)
    if (isFaithfulCandidate(lights[i]) && !std::isfinite(faithfulReach(lights[i], scaledist))) grid.indices.push_back(i);
  grid.header.globalCount = uint32_t(grid.indices.size()) - grid.header.globalFirst;

  grid.header.physicalFirst = uint32_t(grid.indices.size());
  for (uint32_t i = 0; i < lights.size(); ++i)
    if (isPhysicalCandidate(lights[i])) grid.indices.push_back(i);
  grid.header.physicalCount = uint32_t(grid.indices.size()) - grid.header.physicalFirst;

  // Finite-reach lights into every cell their reach sphere touches: a large level's thousands of
  // lights reach thousands of cells each, so the z-slices of cells are shared among threads
  // (each slice takes the lights in index order, so the lists do not depend on the threads).
  const size_t cellCount = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  struct Reach {
    uint32_t light;
    uint32_t lo[3], hi[3]; // the cells of its reach box
  };
  std::vector<Reach> reaches;
  for (uint32_t i = 0; i < lights.size(); ++i) {
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
  const unsigned threads = reaches.size() * cellCount < 100000 ? 1u : std::max(1u, std::min(std::thread::hardware_concurrency(), g.dims[2]));
  auto forSlices = [&](const auto& perSlice) {
    std::atomic<uint32_t> next{0};
    auto work = [&] {
      for (uint32_t z = next++; z < g.dims[2]; z = next++) perSlice(z);
    };
    std::vector<std::thread> helpers;
    for (unsigned t = 1; t < threads; ++t) helpers.emplace_back(work);
    work();
    for (std::thread& t : helpers) t.join();
  };
  forSlices([&](uint32_t z) {
    for (const Reach& r : reaches) {
      if (z < r.lo[2] || z > r.hi[2]) continue;
      const GpuLight& l = lights[r.light];
      const float reach = faithfulReach(l, scaledist);
      uint32_t cell[3] = {0, 0, z};
      for (cell[1] = r.lo[1]; cell[1] <= r.hi[1]; ++cell[1])
        for (cell[0] = r.lo[0]; cell[0] <= r.hi[0]; ++cell[0])
          if (distanceToCell2(g, cell, l.origin) <= reach * reach)
            lists[cell[0] + g.dims[0] * (cell[1] + g.dims[1] * size_t(z))].push_back(r.light);
    }
  });
  grid.cells.resize(2 * cellCount);
  for (size_t k = 0; k < cellCount; ++k) {
    grid.cells[k] = {uint32_t(grid.indices.size()), uint32_t(lists[k].size())};
    grid.indices.insert(grid.indices.end(), lists[k].begin(), lists[k].end());
  }

  // Physical near lists: the kPhysicalNearLights lights of largest bound power / d^2, d the
  // distance from the (jittered) light to the cell, at least half a cell so that lights inside
  // the cell do not all tie at infinity. Every cell ranks every physical light, slice by slice
  // on the same threads; each cell's list depends on nothing else.
  const std::vector<uint32_t> physical(grid.physicalLights().begin(), grid.physicalLights().end());
  const float nearest2 = 0.25f * g.cellSize * g.cellSize;
  std::vector<uint32_t> nearLists(cellCount * kPhysicalNearLights);
  std::vector<uint32_t> nearCounts(cellCount);
  // The lights' ranking inputs side by side (a GpuLight is 96 bytes, of which this reads 5 floats).
  struct Candidate {
    glm::vec3 origin;
    float jitter;
    float power;
    uint32_t light;
  };
  std::vector<Candidate> candidates;
  for (uint32_t i : physical) {
    const GpuLight& l = lights[i];
    const float power = (l.color.x + l.color.y + l.color.z) * l.value;
    if (power > 0.0f) candidates.push_back({l.origin, maxJitter(l), power, i});
  }
  forSlices([&](uint32_t z) {
    std::vector<std::pair<float, uint32_t>> ranked(candidates.size());
    uint32_t cell[3] = {0, 0, z};
    for (cell[1] = 0; cell[1] < g.dims[1]; ++cell[1])
      for (cell[0] = 0; cell[0] < g.dims[0]; ++cell[0]) {
        for (size_t j = 0; j < candidates.size(); ++j) {
          const Candidate& c = candidates[j];
          const float d = std::max(std::sqrt(distanceToCell2(g, cell, c.origin)) - c.jitter, 0.0f);
          ranked[j] = {c.power / std::max(d * d, nearest2), c.light};
        }
        const size_t keep = std::min<size_t>(ranked.size(), kPhysicalNearLights);
        // Largest bound first, ties by light index: the same lists on every run.
        std::partial_sort(ranked.begin(), ranked.begin() + keep, ranked.end(),
                          [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
        const size_t k = cell[0] + g.dims[0] * (cell[1] + g.dims[1] * size_t(cell[2]));
        nearCounts[k] = uint32_t(keep);
        for (size_t r = 0; r < keep; ++r) nearLists[k * kPhysicalNearLights + r] = ranked[r].second;
      }
  });
  for (size_t k = 0; k < cellCount; ++k) {
    grid.cells[cellCount + k] = {uint32_t(grid.indices.size()), nearCounts[k]};
    grid.indices.insert(grid.indices.end(), nearLists.begin() + k * kPhysicalNearLights,
                        nearLists.begin() + k * kPhysicalNearLights + nearCounts[k]);
  }
  return grid;
}

} // namespace bt
