#include "tests/bvh/bvh_test_util.h"
#include "tests/bvh/full_sweep_sah.h"

#include <gtest/gtest.h>

#include <cstdio>

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
