// Physical mode's light tree (lighting/light_tree.h): its nodes bound their lights, every light
// that lights a point keeps a non-zero probability there, a picture with it converges to the
// exhaustive light loop in every pixel and colour, and where a point sees few of many
// short-reach lights it is less noisy than the light grid's near lists.
#include "lighting/faithful.h"
#include "lighting/light_tree.h"
#include "lighting/physical_light.h"
#include "renderer/camera.h"
#include "renderer/cpu/integrator.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <set>

namespace bt {
namespace {

RenderScene buildRs(const Scene& scene) {
  Diagnostics diags;
  return buildRenderScene(scene, {}, diags);
}

// Every leaf's probability at (p, n): the product of the walk's branch probabilities.
void leafProbabilities(std::span<const LightTreeNode> nodes, uint32_t node, double probability, const glm::vec3& p, const glm::vec3& n,
                       std::map<uint32_t, double>& out) {
  if (nodes[node].second == 0) {
    out[nodes[node].light] += probability;
    return;
  }
  const float ia = lightNodeImportance(nodes[node + 1], p, n), ib = lightNodeImportance(nodes[nodes[node].second], p, n);
  if (!(ia + ib > 0.0f)) return;
  const float pa = ia / (ia + ib);
  if (pa > 0.0f) leafProbabilities(nodes, node + 1, probability * pa, p, n, out);
  if (pa < 1.0f) leafProbabilities(nodes, nodes[node].second, probability * (1.0f - pa), p, n, out);
}

TEST(LightTree, NodesBoundTheirLights) {
  const Scene scene = test::manyLightsRoom(200, true, 31); // rs points at it
  const RenderScene rs = buildRs(scene);
  const std::vector<LightTreeNode>& nodes = rs.lightGrid.physicalTree;
  std::set<uint32_t> leaves;
  for (uint32_t i = 0; i < nodes.size(); ++i) {
    const LightTreeNode& node = nodes[i];
    if (node.second == 0) {
      EXPECT_TRUE(leaves.insert(node.light).second) << "light " << node.light << " in two leaves";
      const GpuLight& l = rs.lights[node.light];
      EXPECT_TRUE(glm::all(glm::lessThanEqual(node.lo, l.origin - l.deviance)) &&
                  glm::all(glm::greaterThanEqual(node.hi, l.origin + l.deviance)));
      EXPECT_LE(node.invReach, l.physicalInvReach);
      continue;
    }
    ASSERT_GT(node.second, i + 1);
    for (const LightTreeNode& child : {nodes[i + 1], nodes[node.second]}) {
      EXPECT_TRUE(glm::all(glm::lessThanEqual(node.lo, child.lo)) && glm::all(glm::greaterThanEqual(node.hi, child.hi))) << "node " << i;
      EXPECT_LE(node.invReach, child.invReach);
    }
    EXPECT_NEAR(node.power, nodes[i + 1].power + nodes[node.second].power, 1e-5f * node.power);
  }
  // Every physical point light with power is a leaf: 200 less the spots' and the others' none.
  size_t lit = 0;
  for (uint32_t i : rs.lightGrid.physicalLights()) lit += physical::intensity(rs.lights[i], rs.world.scaledist) > 0.0f;
  EXPECT_EQ(leaves.size(), lit);
  EXPECT_GE(lit, 190u);
}

// Unbiased selection needs a non-zero probability for every light whose unshadowed light at the
// point is non-zero, for any of its jittered positions. The walk's probabilities sum to at most
// 1: the rest is where a node's bound lets the point see it and neither child's does (a sample
// that finds no light, which only lights that cannot light the point would have used).
TEST(LightTree, EveryLightThatLightsAPointCanBePicked) {
  const Scene scene = test::manyLightsRoom(200, true, 31); // rs points at it
  const RenderScene rs = buildRs(scene);
  const std::vector<LightTreeNode>& nodes = rs.lightGrid.physicalTree;
  int points = 0, checked = 0;
  for (uint32_t k = 0; k < 300; ++k) {
    Rng rng = pixelRng(k, 5, 0, 3);
    const glm::vec3 p(-500.0f + 1000.0f * rng.next(), -500.0f + 1000.0f * rng.next(), 1.0f + 250.0f * rng.next());
    const glm::vec3 n = sampleUniformHemisphere(glm::vec3(0.0f, 0.0f, rng.next() < 0.5f ? 1.0f : -1.0f), rng.next2());
    std::map<uint32_t, double> probability;
    leafProbabilities(nodes, 0, 1.0, p, n, probability);
    double total = 0.0;
    for (const auto& [light, pr] : probability) total += pr;
    EXPECT_LE(total, 1.0 + 1e-5) << "point " << k;
    const LightPick pick = pickLightFromTree(nodes, p, n, rng.next());
    if (pick.found) EXPECT_NEAR(pick.pdf, probability[pick.light], 1e-5 * probability[pick.light]);
    for (uint32_t i : rs.lightGrid.physicalLights()) {
      const GpuLight& l = rs.lights[i];
      for (int j = 0; j < 4; ++j) {
        const glm::vec3 d = jitteredOrigin(l, rng) - p;
        const float dist2 = glm::dot(d, d);
        const glm::vec3 wi = d / std::sqrt(dist2);
        const float light = physical::falloff(l, dist2) * faithful::spotTerm(l, wi) * glm::dot(n, wi);
        if (!(light > 0.0f)) continue;
        ++checked;
        EXPECT_GT(probability[i], 0.0) << "light " << i << " lights point " << k << " but cannot be picked";
      }
    }
    points += !probability.empty();
  }
  EXPECT_GT(points, 250);
  EXPECT_GT(checked, 5000);
}

// A pixel's mean and the variance of one sample, per channel, from `spp` samples drawn as the
// CPU renderer draws them.
struct PixelStats {
  glm::dvec3 mean{0.0}, variance{0.0};
};

std::vector<PixelStats> pixelStats(const RenderScene& rs, const Camera& camera, int width, int height, const IntegratorSettings& settings,
                                   int spp, uint32_t seed) {
  std::vector<PixelStats> out(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      glm::dvec3 sum(0.0), sum2(0.0);
      for (int s = 0; s < spp; ++s) {
        Rng rng = pixelRng(uint32_t(x), uint32_t(y), uint32_t(s), seed);
        const glm::vec2 jitter = rng.next2();
        const glm::dvec3 l(radiance(rs, settings, camera.ray(float(x) + jitter.x, float(y) + jitter.y), rng));
        sum += l, sum2 += l * l;
      }
      PixelStats& p = out[size_t(y) * width + x];
      p.mean = sum / double(spp);
      p.variance = glm::max(sum2 / double(spp) - p.mean * p.mean, 0.0) * double(spp) / double(spp - 1);
    }
  return out;
}

// Done-when of issue 18 ("without a visible bias against the exhaustive light loop"): the tree's
// picture of a room of 200 lights of every kind and reach (spots, soft lights, a sun) against
// the picture that shadow-tests every light at every hit, pixel by pixel, in each colour: the
// means agree within 5 standard errors of their difference (1,536 comparisons, so a correct
// estimator fails one by chance about once in a thousand runs), and the whole image's mean
// within 1 %. Direct light only (bounces 0): what a wrong pick changes, seen at its largest.
TEST(LightTree, PictureConvergesToTheExhaustiveLoopInEveryPixel) {
  const Scene scene = test::manyLightsRoom(200, true, 31); // rs points at it
  const RenderScene rs = buildRs(scene);
  const int width = 32, height = 16;
  const Camera camera(CameraPose{{-480.0f, -480.0f, 220.0f}, 20.0f, 45.0f, 0.0f, "test"}, width, height);
  const IntegratorSettings exhaustive{LightingMode::Physical, 0, false};
  const IntegratorSettings tree{LightingMode::Physical, 0, true, IntegratorSettings::PhysicalPick::Tree};
  const std::vector<PixelStats> e = pixelStats(rs, camera, width, height, exhaustive, 24, 1);
  const std::vector<PixelStats> t = pixelStats(rs, camera, width, height, tree, 384, 2);
  int lit = 0, off = 0;
  glm::dvec3 sumE(0.0), sumT(0.0);
  for (size_t i = 0; i < e.size(); ++i) {
    const glm::dvec3 error = glm::sqrt(e[i].variance / 24.0 + t[i].variance / 384.0);
    for (int c = 0; c < 3; ++c) {
      const bool agrees = std::abs(t[i].mean[c] - e[i].mean[c]) <= 5.0 * error[c] + 1e-6 * e[i].mean[c];
      if (!agrees && ++off <= 10)
        ADD_FAILURE() << "pixel " << i % width << " " << i / width << " channel " << c << ": tree " << t[i].mean[c] << " exhaustive "
                      << e[i].mean[c] << " +- " << error[c];
    }
    lit += e[i].mean.g > 0.0;
    sumE += e[i].mean, sumT += t[i].mean;
  }
  EXPECT_EQ(off, 0);
  EXPECT_GT(lit, int(e.size()) * 9 / 10);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sumT[c], sumE[c], 0.01 * sumE[c]) << "channel " << c;
}

// Where the tree wins: in a hall of 600 short-reach lights cut into rooms, a point's cell lists
// 32 lights ranked by power / distance, blind to the surface's orientation and to the reach, and
// the 10 % uniform pick among the cell's other lights in reach often finds one the wall hides or
// faces away from; the tree's walk follows the reach and the orientation. Summed over the pixels
// of a view down the hall, the variance of a sample is at least kNoiseFactor times lower with the
// tree (1.67x measured; 2.2x while the uniform pick drew among all 600 lights). The means are not
// compared: both estimators have long tails here (a pixel whose jitter lands next to a light),
// and PictureConvergesToTheExhaustiveLoopInEveryPixel holds the tree's.
//
// The hall keeps the light its bar was set on: its lights matched by the fixed rule
// (physical::matchDistance), not where their light lands (bright18d), which changes every
// light's intensity and so the variance of both picks (the tree's 0.44x of the lists' there, at
// these seeds; bench/README.md, issue 18's colour step, shows the ratio is the seeds' too).
TEST(LightTree, LessNoisyThanTheNearListsInAHallOfManyLights) {
  constexpr double kNoiseFactor = 1.5;
  const Scene scene = test::manyLightsHall(600, 7); // rs points at it
  RenderScene rs = buildRs(scene);
  for (GpuLight& l : rs.lights) physical::prepare(l, rs.world.scaledist);
  rs.lightGrid = buildLightGrid(rs.lights, rs.tracer.bounds(), rs.world.scaledist);
  ASSERT_GT(rs.lightGrid.physicalTree.size(), 1000u);
  const int width = 32, height = 16, spp = 48;
  const Camera camera(CameraPose{{-1950.0f, -150.0f, 150.0f}, 8.0f, 8.0f, 0.0f, "test"}, width, height);
  const IntegratorSettings tree{LightingMode::Physical, 0, true, IntegratorSettings::PhysicalPick::Tree};
  const IntegratorSettings near{LightingMode::Physical, 0, true, IntegratorSettings::PhysicalPick::NearList};
  const std::vector<PixelStats> t = pixelStats(rs, camera, width, height, tree, spp, 1);
  const std::vector<PixelStats> g = pixelStats(rs, camera, width, height, near, spp, 2);
  double varianceTree = 0.0, varianceNear = 0.0, meanTree = 0.0, meanNear = 0.0;
  for (size_t i = 0; i < t.size(); ++i) {
    varianceTree += t[i].variance.x + t[i].variance.y + t[i].variance.z;
    varianceNear += g[i].variance.x + g[i].variance.y + g[i].variance.z;
    meanTree += t[i].mean.x + t[i].mean.y + t[i].mean.z;
    meanNear += g[i].mean.x + g[i].mean.y + g[i].mean.z;
  }
  std::cout << "variance of a sample, summed over pixels: tree " << varianceTree << ", near lists " << varianceNear << " ("
            << varianceNear / varianceTree << "x); image mean tree " << meanTree << ", near lists " << meanNear << "\n";
  EXPECT_GT(meanTree, 0.0);
  EXPECT_GT(meanNear, 0.0);
  EXPECT_LT(varianceTree * kNoiseFactor, varianceNear);
}

} // namespace
} // namespace bt
