// Light selection (lighting/light_grid.h and the integrator's selected paths) against the
// exhaustive loop over every light: the grid's lists never drop a light that lights a point,
// faithful mode gives the exhaustive value, physical mode converges to the exhaustive mean.
#include "lighting/faithful.h"
#include "renderer/cpu/integrator.h"
#include "lighting/light_grid.h"
#include "lighting/physical_light.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

namespace bt {
namespace {

RenderScene buildRs(const Scene& scene) {
  Diagnostics diags;
  return buildRenderScene(scene, {}, diags);
}

// A surface point and its normal: the first visible hit of a random ray from inside the room.
struct SurfacePoint {
  glm::vec3 p, n;
};
std::vector<SurfacePoint> randomSurfacePoints(const RenderScene& rs, int count, uint32_t seed) {
  std::vector<SurfacePoint> points;
  for (uint32_t i = 0; points.size() < size_t(count); ++i) {
    Rng rng = pixelRng(i, 0, 0, seed);
    const glm::vec3 from(-500.0f + 1000.0f * rng.next(), -500.0f + 1000.0f * rng.next(), 5.0f + 245.0f * rng.next());
    const glm::vec3 dir = sampleUniformHemisphere(glm::vec3(0, 0, rng.next() < 0.7f ? -1.0f : 1.0f), rng.next2());
    const SurfaceHit hit = traceVisible(rs, Ray{from, 0.0f, dir, 1e9f});
    if (hit.found) points.push_back({hit.position, hit.normal});
  }
  return points;
}

// Quake's lights reach a finite distance; a light missing from a cell's list must give exactly
// 0 anywhere in that cell, for any jitter of its position, for any surface orientation.
TEST(LightGrid, CellListsNeverDropALightThatReachesThePoint) {
  const Scene scene = test::manyLightsRoom(160, true, 11);
  const RenderScene rs = buildRs(scene);
  const LightGrid& grid = rs.lightGrid;
  ASSERT_GT(grid.cells.size(), 8u);

  std::mt19937 gen(5);
  // Points in the room and well outside the grid (clamped to border cells).
  std::uniform_real_distribution<float> coord(-900.0f, 900.0f), height(-200.0f, 500.0f);
  int checkedPairs = 0, culledPairs = 0;
  for (int k = 0; k < 3000; ++k) {
    const glm::vec3 p(coord(gen), coord(gen), height(gen));
    std::vector<bool> listed(rs.lights.size(), false);
    for (uint32_t i : grid.fixedLights()) listed[i] = true;
    for (uint32_t i : grid.globalLights()) listed[i] = true;
    for (uint32_t i : grid.cellLights(p)) listed[i] = true;
    for (uint32_t i = 0; i < rs.lights.size(); ++i) {
      ++checkedPairs;
      if (listed[i]) continue;
      ++culledPairs;
      const GpuLight& light = rs.lights[i];
      ASSERT_EQ(light.type, uint32_t(LightType::Point));
      // The closest any jittered position gets, and a few actual jitters, head-on.
      const float closest = std::max(glm::length(light.origin - p) - std::sqrt(3.0f) * light.deviance, 0.0f);
      ASSERT_EQ(faithful::distanceValue(light, closest, rs.world.scaledist), 0.0f) << "light " << i;
      Rng rng = pixelRng(uint32_t(k), i, 0, 1);
      for (int j = 0; j < 4; ++j) {
        // A corner of the jitter cube (integrator.cpp jitteredOrigin), towards p or not.
        const glm::vec3 corner(rng.next() < 0.5f ? -1.0f : 1.0f, rng.next() < 0.5f ? -1.0f : 1.0f, rng.next() < 0.5f ? -1.0f : 1.0f);
        const glm::vec3 pos = light.origin + light.deviance * corner;
        const glm::vec3 d = pos - p;
        const float dist = glm::length(d);
        ASSERT_EQ(faithful::pointLightValue(light, d / dist, d / dist, dist, rs.world.scaledist), 0.0f) << "light " << i;
      }
    }
  }
  // The grid must actually cull: most (point, light) pairs are out of reach in this room.
  EXPECT_GT(culledPairs, checkedPairs / 3);
}

TEST(LightGrid, EveryLightIsInTheListsOfItsKind) {
  const Scene scene = test::manyLightsRoom(64, true, 3);
  const RenderScene rs = buildRs(scene);
  const LightGrid& grid = rs.lightGrid;
  std::vector<int> seen(rs.lights.size(), 0);
  for (uint32_t i : grid.fixedLights()) ++seen[i];
  for (uint32_t i : grid.globalLights()) ++seen[i];
  const size_t cellCount = grid.cells.size() / 3; // faithful cells, physical near lists, physical rest lists
  for (size_t cell = 0; cell < cellCount; ++cell)
    for (uint32_t k = grid.cells[cell].first; k < grid.cells[cell].first + grid.cells[cell].count; ++k)
      seen[grid.indices[k]] = std::max(seen[grid.indices[k]], 1);
  for (uint32_t i = 0; i < rs.lights.size(); ++i) EXPECT_EQ(seen[i], 1) << "light " << i;
  int physical = 0;
  for (const GpuLight& l : rs.lights)
    physical += l.type == uint32_t(LightType::Point) && l.formula != uint32_t(LightFormula::LocalMin) && l.value > 0.0f &&
        !(l.flags & kLightFlagFromSurface);
  EXPECT_EQ(int(grid.physicalLights().size()), physical);
  EXPECT_EQ(grid.fixedLights().size(), 2u); // the sun and the local minlight

  // Near lists: kPhysicalNearLights distinct lights of the physical list, the strongest bound
  // first; a light right next to a point is in that point's list.
  const std::vector<uint32_t> physicalList(grid.physicalLights().begin(), grid.physicalLights().end());
  for (size_t cell = cellCount; cell < 2 * cellCount; ++cell) {
    const GpuLightCell& c = grid.cells[cell];
    ASSERT_EQ(c.count, std::min<uint32_t>(kPhysicalNearLights, uint32_t(physicalList.size())));
    std::vector<uint32_t> listed(grid.indices.begin() + c.first, grid.indices.begin() + c.first + c.count);
    for (uint32_t i : listed) EXPECT_NE(std::find(physicalList.begin(), physicalList.end(), i), physicalList.end());
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(std::unique(listed.begin(), listed.end()), listed.end());
  }
  for (uint32_t i : grid.physicalLights()) {
    const std::span<const uint32_t> near = grid.physicalNearLights(rs.lights[i].origin + glm::vec3(1.0f));
    EXPECT_NE(std::find(near.begin(), near.end(), i), near.end()) << "light " << i;
  }
}

TEST(LightGrid, EmptyLevelHasOneCellWithEveryFiniteLight) {
  std::vector<GpuLight> lights(3);
  lights[0].origin = {1e5f, 0, 0};
  lights[1].formula = uint32_t(LightFormula::Inverse);
  lights[2].value = 0.0f; // lights nothing: in no list
  const LightGrid grid = buildLightGrid(lights, Bounds{}, 1.0f);
  ASSERT_EQ(grid.cells.size(), 3u); // one faithful cell, one physical near list, one rest list
  EXPECT_EQ(grid.cellLights({0, 0, 0}).size(), 1u);
  EXPECT_EQ(grid.globalLights().size(), 1u);
  EXPECT_EQ(grid.cellLights({NAN, 0, 0}).size(), 1u);
  EXPECT_EQ(grid.physicalNearLights({0, 0, 0}).size(), 2u);
  EXPECT_EQ(grid.physicalRestLights({0, 0, 0}).size(), 0u);
}

// Physical mode's pick draws from a point's near list or, uniformly, from its rest list: a light
// that can light the point (its windowed falloff above 0 there, for any jitter of its position)
// is in one of the two, never in both; the rest lists are in index order, and hold fewer lights
// than the level has (else the uniform draw would be the old one among every light).
TEST(LightGrid, PhysicalRestListsHoldEveryOtherLightThatReachesThePoint) {
  const Scene scene = test::manyLightsRoom(300, true, 5);
  const RenderScene rs = buildRs(scene);
  const LightGrid& grid = rs.lightGrid;
  const auto holds = [](std::span<const uint32_t> list, uint32_t i) { return std::find(list.begin(), list.end(), i) != list.end(); };
  size_t restListed = 0, points = 0, missing = 0;
  for (const SurfacePoint& s : randomSurfacePoints(rs, 1000, 11)) {
    const std::span<const uint32_t> near = grid.physicalNearLights(s.p), rest = grid.physicalRestLights(s.p);
    EXPECT_TRUE(std::is_sorted(rest.begin(), rest.end()));
    restListed += rest.size(), ++points;
    for (uint32_t i : grid.physicalLights()) {
      const GpuLight& l = rs.lights[i];
      const bool inNear = holds(near, i), inRest = holds(rest, i);
      EXPECT_FALSE(inNear && inRest) << "light " << i << " is in both lists";
      const float d = std::max(glm::distance(l.origin, s.p) - std::sqrt(3.0f) * std::max(l.deviance, 0.0f), 1e-3f);
      missing += physical::falloff(l, d * d) > 0.0f && !inNear && !inRest;
    }
  }
  EXPECT_EQ(missing, 0u) << "lights that light a point but that its pick can never draw";
  const double meanRest = double(restListed) / double(points);
  std::printf("rest lists: %.1f lights a point on average, of %zu physical lights\n", meanRest, grid.physicalLights().size());
  EXPECT_GT(meanRest, 0.0) << "no point has a light beyond its near list: the test cannot tell";
  EXPECT_LT(meanRest + kPhysicalNearLights, double(grid.physicalLights().size()));
}

// The near lists against the plain ranking they stand for: every physical light of positive
// power (physical intensity times the channels of the colour physical mode emits, summed; the
// grids here have _dist 1) ranked in every cell by power / d^2 (d from the jittered light to the cell, whose border
// sides reach to infinity, at least half a cell), largest first, ties to the lower index.
// Lights in clusters and in exact duplicates (ties), far outside the grid, jittered, and of kinds
// that physical mode leaves out.
std::vector<uint32_t> referenceNearList(const std::vector<GpuLight>& lights, const LightGrid& grid, const uint32_t cell[3]) {
  const GpuLightGrid& g = grid.header;
  std::vector<std::pair<float, uint32_t>> ranked;
  for (uint32_t i : grid.physicalLights()) {
    const GpuLight& l = lights[i];
    const glm::vec3 emitted = physical::colour(l.color);
    const float power = (emitted.x + emitted.y + emitted.z) * physical::intensity(l, 1.0f);
    if (!(power > 0.0f)) continue;
    float d2 = 0.0f;
    for (int a = 0; a < 3; ++a) {
      const float lo = cell[a] == 0 ? -INFINITY : g.origin[a] + float(cell[a]) * g.cellSize;
      const float hi = cell[a] + 1 == g.dims[a] ? INFINITY : g.origin[a] + float(cell[a] + 1) * g.cellSize;
      const float d = l.origin[a] < lo ? lo - l.origin[a] : (l.origin[a] > hi ? l.origin[a] - hi : 0.0f);
      d2 += d * d;
    }
    const float d = std::max(std::sqrt(d2) - std::sqrt(3.0f) * l.deviance, 0.0f);
    ranked.push_back({power / std::max(d * d, 0.25f * g.cellSize * g.cellSize), i});
  }
  const size_t keep = std::min<size_t>(ranked.size(), kPhysicalNearLights);
  std::partial_sort(ranked.begin(), ranked.begin() + std::ptrdiff_t(keep), ranked.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
  std::vector<uint32_t> list;
  for (size_t r = 0; r < keep; ++r) list.push_back(ranked[r].second);
  return list;
}

TEST(LightGrid, PhysicalNearListsAreTheStrongestLightsOfAPlainRanking) {
  std::mt19937 gen(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<GpuLight> lights;
  for (int i = 0; i < 500; ++i) {
    GpuLight l;
    const bool clustered = i % 4 == 0; // a dense cluster: many lights in one cell
    l.origin = clustered ? glm::vec3(300.0f + 40.0f * u(gen), -200.0f + 40.0f * u(gen), 100.0f + 40.0f * u(gen))
                         : glm::vec3(-1200.0f + 2400.0f * u(gen), -1200.0f + 2400.0f * u(gen), -300.0f + 900.0f * u(gen));
    l.value = 50.0f + 400.0f * u(gen);
    l.color = i % 5 == 0 ? glm::vec3(1.0f, 0.5f, 0.25f) : glm::vec3(1.0f);
    if (i % 7 == 0) l.deviance = 30.0f * u(gen);
    if (i % 11 == 0) l.formula = uint32_t(LightFormula::Inverse2);
    if (i % 13 == 0) l.value = -l.value;               // negative: not physical
    if (i % 17 == 0) l.flags |= kLightFlagFromSurface; // a _surface point: not physical
    if (i % 19 == 0) l.formula = uint32_t(LightFormula::LocalMin);
    lights.push_back(l);
    if (i % 9 == 0) lights.push_back(l); // an exact tie everywhere, decided by the index
  }
  Bounds bounds;
  bounds.grow(dvec3(-1024.0, -1024.0, 0.0));
  bounds.grow(dvec3(1024.0, 1024.0, 256.0));
  const LightGrid grid = buildLightGrid(lights, bounds, 1.0f);
  const GpuLightGrid& g = grid.header;
  ASSERT_EQ(g.dims[0], 32u);
  ASSERT_EQ(g.dims[2], 4u);
  const size_t cellCount = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  uint32_t cell[3];
  for (cell[2] = 0; cell[2] < g.dims[2]; ++cell[2])
    for (cell[1] = 0; cell[1] < g.dims[1]; ++cell[1])
      for (cell[0] = 0; cell[0] < g.dims[0]; ++cell[0]) {
        const size_t k = cell[0] + g.dims[0] * (cell[1] + g.dims[1] * size_t(cell[2]));
        const GpuLightCell& c = grid.cells[cellCount + k];
        const std::vector<uint32_t> listed(grid.indices.begin() + c.first, grid.indices.begin() + c.first + c.count);
        ASSERT_EQ(listed, referenceNearList(lights, grid, cell)) << "cell " << cell[0] << " " << cell[1] << " " << cell[2];
      }
}

TEST(LightGrid, PhysicalNearListsOfFewLightsHoldThemAll) {
  std::vector<GpuLight> lights(5);
  for (int i = 0; i < 5; ++i) lights[size_t(i)].origin = {100.0f * float(i), 0.0f, 0.0f};
  lights[2].value = 0.0f; // lights nothing
  Bounds bounds;
  bounds.grow(dvec3(0.0));
  bounds.grow(dvec3(1000.0, 300.0, 300.0));
  const LightGrid grid = buildLightGrid(lights, bounds, 1.0f);
  const std::span<const uint32_t> near = grid.physicalNearLights({950.0f, 10.0f, 10.0f});
  EXPECT_EQ(std::vector<uint32_t>(near.begin(), near.end()), (std::vector<uint32_t>{4, 3, 1, 0})); // nearest first
}

// The pick weighs its near lights four at a time (SSE2), and four lights without a cone skip the
// cone's terms: every weight is still the scalar expression's float, bit for bit, so the pick and
// the image do not change. A room where every eighth light is a spot, so that some fours hold
// one and most hold none, and points inside, outside and on the edge of the spots' cones.
TEST(LightSelection, NearListWeightsAreTheScalarWeightsBitForBit) {
  const Scene scene = test::manyLightsRoom(120, false, 7);
  RenderScene rs = buildRs(scene);
  for (GpuLight& l : rs.lights) // the room's spots have no _softangle: give them a fade, whose division the weights take
    if (l.cosOuter >= -1.0f) l.cosInner = 0.5f * (1.0f + l.cosOuter);
  int foursWithSpot = 0, foursWithout = 0, litByFade = 0, lit = 0;
  for (const SurfacePoint& s : randomSurfacePoints(rs, 400, 5)) {
    const std::span<const uint32_t> listed = rs.lightGrid.physicalNearLights(s.p);
    const std::span<const uint32_t> near = listed.first(std::min<size_t>(listed.size(), kPhysicalNearLights));
    const std::vector<float> weights = nearListWeights(rs, s.p, s.n);
    ASSERT_EQ(weights.size(), near.size());
    for (size_t k = 0; k < near.size(); ++k) {
      const GpuLight& light = rs.lights[near[k]];
      const float expected = physical::selectionWeight(light, s.p, s.n);
      ASSERT_EQ(std::bit_cast<uint32_t>(weights[k]), std::bit_cast<uint32_t>(expected))
          << "light " << near[k] << " at " << s.p.x << " " << s.p.y << " " << s.p.z << ": " << weights[k] << " against " << expected;
      const float spot = faithful::spotTerm(light, glm::normalize(light.origin - s.p));
      litByFade += expected > 0.0f && spot > 0.0f && spot < 1.0f;
      lit += expected > 0.0f;
    }
    for (size_t k = 0; k < near.size(); k += 4) {
      bool spot = false;
      for (size_t j = k; j < std::min(k + 4, near.size()); ++j) spot = spot || rs.lights[near[j]].cosOuter >= -1.0f;
      ++(spot ? foursWithSpot : foursWithout);
    }
  }
  EXPECT_GT(foursWithSpot, 100);
  EXPECT_GT(foursWithout, 100);
  EXPECT_GT(litByFade, 10); // points in the spots' fade, where the cone's division counts
  EXPECT_GT(lit, 1000);
}

// Hard lights: the grid's sum is the exhaustive sum, point by point (float summation order
// aside), and so is every faithful pixel.
TEST(LightSelection, FaithfulGridEqualsExhaustiveForHardLights) {
  const Scene scene = test::manyLightsRoom(120, false, 7);
  const RenderScene rs = buildRs(scene);
  int lit = 0;
  for (const SurfacePoint& s : randomSurfacePoints(rs, 400, 2)) {
    Rng a = pixelRng(1, 2, 3, 4), b = a;
    const glm::vec3 exhaustive = faithfulLight(rs, {.p = s.p, .n = s.n, .lights = LightSet::All}, a);
    const glm::vec3 grid = faithfulLight(rs, {.p = s.p, .n = s.n, .lights = LightSet::Grid}, b);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(grid[c], exhaustive[c], 1e-4f * std::max(1.0f, std::abs(exhaustive[c])));
    lit += exhaustive.x > 50.0f;
  }
  EXPECT_GT(lit, 100); // the comparison is about lit points, not darkness
  for (int i = 0; i < 200; ++i) {
    Rng pick = pixelRng(uint32_t(i), 9, 0, 0);
    const Ray ray{{-450.0f + 900.0f * pick.next(), -450.0f + 900.0f * pick.next(), 200.0f},
                  0.0f,
                  glm::normalize(glm::vec3(pick.next() - 0.5f, pick.next() - 0.5f, -1.0f)),
                  1e9f};
    Rng a = pixelRng(uint32_t(i), 0, 0, 0), b = a;
    const glm::vec3 exhaustive = radiance(rs, {LightingMode::Faithful, 0, false}, ray, a);
    const glm::vec3 selected = radiance(rs, {LightingMode::Faithful, 0, true}, ray, b);
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(selected[c], exhaustive[c], 1e-4f * std::max(1.0f, exhaustive[c]));
  }
}

struct MeanAndError {
  double mean = 0.0, error = 0.0; // standard error of the mean
};
template <class Fn> MeanAndError sampleMean(int n, const Fn& sample) {
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double v = sample(uint32_t(i));
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n;
  return {mean, std::sqrt(std::max(sum2 / n - mean * mean, 0.0) / n)};
}

// Soft lights (_deviance): both are random, with the same mean.
TEST(LightSelection, FaithfulGridConvergesToExhaustiveForSoftLights) {
  const Scene scene = test::manyLightsRoom(48, true, 8);
  const RenderScene rs = buildRs(scene);
  for (const SurfacePoint& s : randomSurfacePoints(rs, 6, 21)) {
    const int n = 3000;
    const MeanAndError e = sampleMean(n, [&](uint32_t i) {
      Rng r = pixelRng(i, 0, 0, 1);
      return faithfulLight(rs, {.p = s.p, .n = s.n, .lights = LightSet::All}, r).y;
    });
    const MeanAndError g = sampleMean(n, [&](uint32_t i) {
      Rng r = pixelRng(i, 0, 0, 2);
      return faithfulLight(rs, {.p = s.p, .n = s.n, .lights = LightSet::Grid}, r).y;
    });
    EXPECT_NEAR(g.mean, e.mean, 4.5 * std::hypot(e.error, g.error) + 1e-3 * e.mean) << "at " << s.p.x << " " << s.p.y << " " << s.p.z;
  }
}

// Physical mode: one selected point light per hit against every light per hit, whole paths
// (two bounces, so selection also runs at secondary hits), mean radiance of the same rays.
TEST(LightSelection, PhysicalSelectedConvergesToExhaustiveMean) {
  const Scene scene = test::manyLightsRoom(96, true, 13);
  const RenderScene rs = buildRs(scene);
  int compared = 0;
  for (int k = 0; k < 8; ++k) {
    Rng pick = pixelRng(uint32_t(k), 77, 0, 0);
    const Ray ray{{-450.0f + 900.0f * pick.next(), -450.0f + 900.0f * pick.next(), 200.0f},
                  0.0f,
                  glm::normalize(glm::vec3(pick.next() - 0.5f, pick.next() - 0.5f, -1.0f)),
                  1e9f};
    // One weighted sum of red and blue instead of two runs: a wrong colour still moves it.
    auto channels = [](const glm::vec3& l) { return double(l.x) + 2.0 * double(l.z); };
    const int n = 1000;
    const MeanAndError e = sampleMean(n, [&](uint32_t i) {
      Rng r = pixelRng(i, uint32_t(k), 0, 3);
      return channels(radiance(rs, {LightingMode::Physical, 2, false}, ray, r));
    });
    const MeanAndError s = sampleMean(n * 4, [&](uint32_t i) {
      Rng r = pixelRng(i, uint32_t(k), 0, 4);
      return channels(radiance(rs, {LightingMode::Physical, 2, true}, ray, r));
    });
    EXPECT_NEAR(s.mean, e.mean, 4.5 * std::hypot(e.error, s.error)) << "ray " << k;
    compared += e.mean > 0.0;
  }
  EXPECT_GE(compared, 6);
}

} // namespace
} // namespace bt
