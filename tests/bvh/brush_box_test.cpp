// The brush box test of the walks' leaves in SSE (bvh/ray_brush.h brushBoxLanes) against the
// scalar brushBox, bit for bit: every walk's hits, so the CPU bake's luxels, rest on it. Boxes and
// rays on a coarse grid, so that most rays meet some box at an edge or a corner, where two or
// three axes give the same t and brushBox's tie rule (the axis met most head-on, the earliest of
// equals) picks the face.
#include "bvh/ray_brush.h"

#include <gtest/gtest.h>

#include <glm/vec3.hpp>

#include <bit>
#include <cstdint>
#include <random>

namespace bt {
namespace {

using trace_detail::Slab;

TEST(BrushBoxLanes, AnswersAsTheScalarBrushBox) {
#if !BT_SSE_NODE_TEST
  GTEST_SKIP() << "no SSE2: the walks use the scalar brushBox itself";
#else
  std::mt19937 rng(21);
  const auto grid = [&](int lo, int hi) { return float(std::uniform_int_distribution<int>(lo, hi)(rng)); };
  // Direction components of a few magnitudes, some equal: equal magnitudes tie head-on too.
  const float steps[] = {0.5f, 1.0f, 1.0f, 2.0f, 3.0f, 0.25f};
  const float limits[] = {0.0f, 0.5f, 1.0f, 2.0f, 3.0f, trace_detail::kInfinity};
  int accepted = 0, nearTies = 0, farTies = 0;
  for (int i = 0; i < 200000; ++i) {
    GpuBrush brush{};
    for (int a = 0; a < 3; ++a) {
      brush.boundsMin[a] = grid(-4, 3);
      brush.boundsMax[a] = brush.boundsMin[a] + grid(1, 3);
    }
    brush.firstSide = uint32_t(rng()), brush.sideCount = uint32_t(rng()); // the words after the bounds are masked
    Ray ray;
    for (int a = 0; a < 3; ++a) {
      ray.origin[a] = 0.5f * grid(-12, 12);
      ray.direction[a] = steps[rng() % std::size(steps)] * (rng() & 1 ? 1.0f : -1.0f);
    }
    // Most rays aimed at a corner of the box or a point on one of its edges, in or out: two or
    // three slabs meet there at one t.
    if (rng() % 4 != 0) {
      glm::vec3 target;
      for (int a = 0; a < 3; ++a) target[a] = rng() & 1 ? brush.boundsMax[a] : brush.boundsMin[a];
      if (rng() & 1) target[rng() % 3] += 0.5f;
      const glm::vec3 d = (target - ray.origin) * steps[rng() % std::size(steps)];
      if (d.x != 0.0f && d.y != 0.0f && d.z != 0.0f) ray.direction = rng() & 1 ? d : -d;
    }
    ray.tMin = limits[rng() % 3];
    ray.tMax = limits[2 + rng() % 4];
    const float tLimit = rng() & 1 ? ray.tMax : limits[rng() % std::size(limits)];
    const RayContext r(ray);
    ASSERT_FALSE(r.hasZeroComponent);

    const Slab want = trace_detail::brushBox<false>(r, brush);
    const bool rejected = want.near > want.far || want.far <= r.tMin || want.near >= r.tMax || want.near > tLimit;
    Slab got{};
    ASSERT_EQ(trace_detail::brushBoxLanes(r, brush, tLimit, got), !rejected) << "ray " << i;
    if (rejected) continue;
    ++accepted;
    EXPECT_EQ(std::bit_cast<uint32_t>(got.near), std::bit_cast<uint32_t>(want.near)) << "ray " << i;
    EXPECT_EQ(std::bit_cast<uint32_t>(got.far), std::bit_cast<uint32_t>(want.far)) << "ray " << i;
    EXPECT_EQ(got.nearAxis, want.nearAxis) << "ray " << i;
    EXPECT_EQ(got.farAxis, want.farAxis) << "ray " << i;
    int nearEqual = 0, farEqual = 0;
    for (int a = 0; a < 3; ++a) {
      const float t0 = (brush.boundsMin[a] - r.origin[a]) * r.invDirection[a], t1 = (brush.boundsMax[a] - r.origin[a]) * r.invDirection[a];
      nearEqual += std::min(t0, t1) == want.near, farEqual += std::max(t0, t1) == want.far;
    }
    nearTies += nearEqual > 1, farTies += farEqual > 1;
  }
  // The grid makes ties common: the tie rule is exercised, not only the plain case.
  EXPECT_GT(accepted, 15000);
  EXPECT_GT(nearTies, 4000);
  EXPECT_GT(farTies, 4000);
  std::printf("%d boxes met, %d near ties, %d far ties\n", accepted, nearTies, farTies);
#endif
}

} // namespace
} // namespace bt
