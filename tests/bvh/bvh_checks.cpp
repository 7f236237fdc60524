#include "tests/bvh/bvh_test_util.h"
#include "tests/bvh/full_sweep_sah.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

namespace bt::test {
namespace {

bool contains(const float* outerMin, const float* outerMax, const float* innerMin, const float* innerMax) {
  for (int a = 0; a < 3; ++a)
    if (innerMin[a] < outerMin[a] || innerMax[a] > outerMax[a]) return false;
  return true;
}

std::vector<Aabb> brushBoxes(const TraceScene& ts) {
  std::vector<Aabb> boxes;
  for (const GpuBrush& g : ts.brushes())
    boxes.push_back({{g.boundsMin[0], g.boundsMin[1], g.boundsMin[2]}, {g.boundsMax[0], g.boundsMax[1], g.boundsMax[2]}});
  return boxes;
}

} // namespace

// Walks the tree from the root and checks everything a traversal relies on.
void expectWellFormed(const TraceScene& ts) {
  const auto nodes = ts.nodes();
  const auto brushes = ts.brushes();
  if (brushes.empty()) {
    EXPECT_TRUE(nodes.empty());
    return;
  }
  ASSERT_FALSE(nodes.empty());
  std::vector<int> brushSeen(brushes.size(), 0), nodeSeen(nodes.size(), 0);
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 0}}; // node, depth
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    ASSERT_LT(index, nodes.size());
    ++nodeSeen[index];
    ASSERT_LE(depth, kBvhMaxDepth);
    const GpuBvhNode& n = nodes[index];
    if (n.count > 0) {
      ASSERT_LE(n.leftFirst + n.count, brushes.size());
      for (uint32_t b = n.leftFirst; b < n.leftFirst + n.count; ++b) {
        ++brushSeen[b];
        EXPECT_TRUE(contains(n.boundsMin, n.boundsMax, brushes[b].boundsMin, brushes[b].boundsMax)) << "brush " << b;
      }
    } else {
      ASSERT_LT(n.leftFirst + 1, nodes.size());
      for (uint32_t c : {n.leftFirst, n.leftFirst + 1}) {
        EXPECT_TRUE(contains(n.boundsMin, n.boundsMax, nodes[c].boundsMin, nodes[c].boundsMax)) << "node " << c;
        stack.push_back({c, depth + 1});
      }
    }
  }
  for (size_t b = 0; b < brushes.size(); ++b) EXPECT_EQ(brushSeen[b], 1) << "brush " << b << " reached that often";
  for (size_t n = 0; n < nodes.size(); ++n) EXPECT_EQ(nodeSeen[n], 1) << "node " << n << " reached that often";
  expectWideWellFormed(ts);
}

// The wide tree (bvh/wide_bvh.h): every wide node and brush reached once, each lane's box one of
// the binary tree's node boxes or its one brush's (so its floats are the binary walk's), holding
// the boxes below it, unused lanes NaN, and no deeper than the walk's stack allows.
void expectWideWellFormed(const TraceScene& ts) {
  const auto wide = ts.wideNodes();
  const auto nodes = ts.nodes();
  const auto brushes = ts.brushes();
  ASSERT_EQ(wide.empty(), nodes.empty());
  if (wide.empty()) return;
  std::set<std::array<float, 6>> binaryBoxes;
  for (const GpuBvhNode& n : nodes)
    binaryBoxes.insert({n.boundsMin[0], n.boundsMin[1], n.boundsMin[2], n.boundsMax[0], n.boundsMax[1], n.boundsMax[2]});
  std::vector<int> brushSeen(brushes.size(), 0), wideSeen(wide.size(), 0);
  struct Visit {
    uint32_t node, depth;
    std::array<float, 6> box; // the lane's that leads here; the root's holds everything
  };
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Visit> stack{{0, 0, {-inf, -inf, -inf, inf, inf, inf}}};
  while (!stack.empty()) {
    const Visit v = stack.back();
    stack.pop_back();
    ASSERT_LT(v.node, wide.size());
    ++wideSeen[v.node];
    ASSERT_LE(v.depth, kBvhMaxDepth);
    const WideBvhNode& n = wide[v.node];
    int used = 0;
    for (int lane = 0; lane < 4; ++lane) {
      const std::array<float, 6> box{n.lo[0][lane], n.lo[1][lane], n.lo[2][lane], n.hi[0][lane], n.hi[1][lane], n.hi[2][lane]};
      if (std::isnan(box[0])) {
        for (float f : box) EXPECT_TRUE(std::isnan(f)) << "wide node " << v.node << " lane " << lane;
        continue;
      }
      ++used;
      const bool ownBrush = n.count[lane] == 1 && n.child[lane] < brushes.size() &&
          box == std::array<float, 6>{brushes[n.child[lane]].boundsMin[0], brushes[n.child[lane]].boundsMin[1],
                                      brushes[n.child[lane]].boundsMin[2], brushes[n.child[lane]].boundsMax[0],
                                      brushes[n.child[lane]].boundsMax[1], brushes[n.child[lane]].boundsMax[2]};
      EXPECT_TRUE(binaryBoxes.count(box) || ownBrush)
          << "wide node " << v.node << " lane " << lane << ": neither a node's nor its brush's box";
      EXPECT_TRUE(contains(v.box.data(), v.box.data() + 3, box.data(), box.data() + 3)) << "wide node " << v.node << " lane " << lane;
      if (n.count[lane] == 0) {
        stack.push_back({n.child[lane], v.depth + 1, box});
        continue;
      }
      ASSERT_LE(n.child[lane] + n.count[lane], brushes.size());
      for (uint32_t b = n.child[lane]; b < n.child[lane] + n.count[lane]; ++b) {
        ++brushSeen[b];
        EXPECT_TRUE(contains(box.data(), box.data() + 3, brushes[b].boundsMin, brushes[b].boundsMax)) << "brush " << b;
      }
    }
    EXPECT_GE(used, v.node == 0 && nodes.size() == 1 ? 1 : 2) << "wide node " << v.node;
  }
  for (size_t b = 0; b < brushes.size(); ++b) EXPECT_EQ(brushSeen[b], 1) << "brush " << b << " reached that often in the wide tree";
  for (size_t n = 0; n < wide.size(); ++n) EXPECT_EQ(wideSeen[n], 1) << "wide node " << n << " reached that often";
}

// Every scene brush with a winding is in brushes() exactly once, with its faces split into
// the axial slots and the side list.
void expectAllBrushesPresent(const Scene& scene, const TraceScene& ts) {
  std::vector<int> seen(scene.brushes.size(), 0);
  for (const GpuBrush& g : ts.brushes()) {
    ASSERT_LT(g.sceneBrush, scene.brushes.size());
    ++seen[g.sceneBrush];
    const Brush& b = scene.brushes[g.sceneBrush];
    uint32_t facesWithWinding = 0;
    for (uint32_t f = b.firstFace; f < b.firstFace + b.faceCount; ++f) facesWithWinding += !scene.faces[f].winding.empty();
    uint32_t axial = 0;
    for (uint32_t f : g.axialFace) axial += f != kNoFace;
    EXPECT_LE(axial + g.sideCount, facesWithWinding);
    for (uint32_t i = g.firstSide; i < g.firstSide + g.sideCount; ++i) {
      const uint32_t f = ts.sides()[i];
      EXPECT_GE(f, b.firstFace);
      EXPECT_LT(f, b.firstFace + b.faceCount);
    }
  }
  for (size_t b = 0; b < scene.brushes.size(); ++b) EXPECT_EQ(seen[b], 1) << "scene brush " << b;
}

void expectSahNearFullSweep(const TraceScene& ts, int leafSize, const std::string& what) {
  const FlatBvh reference = buildFullSweepSah(brushBoxes(ts), leafSize);
  const double full = sahCost(reference.nodes);
  ASSERT_GT(full, 0.0);
  ::testing::Test::RecordProperty(what + "_binned_sah", std::to_string(ts.sahCost()));
  ::testing::Test::RecordProperty(what + "_full_sweep_sah", std::to_string(full));
  EXPECT_LE(ts.sahCost(), 1.03 * full) << what << ": binned " << ts.sahCost() << " vs full sweep " << full;
  std::printf("%s: binned SAH %.3f, full sweep %.3f (ratio %.4f)\n", what.c_str(), ts.sahCost(), full, ts.sahCost() / full);
}

} // namespace bt::test
