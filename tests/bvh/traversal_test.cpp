// BVH traversal against brute force over all brushes: the same hit, bit for bit, for
// thousands of random rays, on generated scenes with several builder settings.
#include "bvh/trace_scene.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/bvh/generated_scenes.h"

#include <gtest/gtest.h>

namespace bt {
namespace {

// Returns how many rays hit something, so callers can check the rays were not all misses.
int expectClosestHitsMatchBruteForce(const TraceScene& ts, const std::vector<Ray>& rays) {
  int hits = 0, failures = 0;
  for (size_t i = 0; i < rays.size() && failures < 10; ++i) {
    const Ray& r = rays[i];
    const std::optional<Hit> bvh = ts.closestHit(r);
    const std::optional<Hit> brute = test::bruteForceClosestHit(ts, r);
    const bool same = bvh.has_value() == brute.has_value() &&
        (!bvh || (bvh->t == brute->t && bvh->face == brute->face && bvh->brush == brute->brush && bvh->inside == brute->inside));
    if (!same) {
      ++failures;
      ADD_FAILURE() << "ray " << i << " (" << r.origin.x << " " << r.origin.y << " " << r.origin.z << ") dir (" << r.direction.x << " "
                    << r.direction.y << " " << r.direction.z << ") [" << r.tMin << ", " << r.tMax << "]: bvh "
                    << (bvh ? std::to_string(bvh->t) + " face " + std::to_string(bvh->face) : "miss") << ", brute force "
                    << (brute ? std::to_string(brute->t) + " face " + std::to_string(brute->face) : "miss");
    }
    EXPECT_EQ(ts.occluded(r), brute.has_value()) << "ray " << i;
    hits += brute.has_value();
  }
  return hits;
}

TEST(Traversal, ClosestHitEqualsBruteForceOnALevel) {
  const test::GeneratedLevel level = test::generateLevel(1500, 31);
  const TraceScene ts = TraceScene::build(level.scene);
  std::vector<Ray> rays = test::randomRays(ts.bounds(), 2000, 32);
  // Rays from the room interiors, as a camera and bounces see the level.
  std::mt19937 rng(33);
  for (int i = 0; i < 1000; ++i)
    rays.push_back({glm::vec3(level.openPoints[i % level.openPoints.size()]), 0.0f, test::randomUnitVector(rng)});
  const int hits = expectClosestHitsMatchBruteForce(ts, rays);
  EXPECT_GT(hits, 1500);
}

TEST(Traversal, ClosestHitEqualsBruteForceOnOverlappingRandomBrushes) {
  const Scene scene = test::generateRandomBrushes(1500, 34, 1024.0);
  for (const BvhBuildOptions& options :
       {BvhBuildOptions{}, BvhBuildOptions{.leafSize = 1, .binCount = 4}, BvhBuildOptions{.leafSize = 12, .binCount = 64}}) {
    const TraceScene ts = TraceScene::build(scene, options);
    const int hits = expectClosestHitsMatchBruteForce(ts, test::randomRays(ts.bounds(), 2000, 35));
    EXPECT_GT(hits, 700);
  }
}

TEST(Traversal, TouchingGridOfBoxesWithAxisAlignedRays) {
  // A solid 8x8x8 block of unit-16 boxes sharing all their faces, rays along the grid lines
  // and planes: every tie between neighbours must resolve the same way as brute force.
  Scene scene;
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 8; ++z)
        if ((x + y + z) % 5 != 0) test::addBox(scene, dvec3(x, y, z) * 16.0, dvec3(x + 1, y + 1, z + 1) * 16.0);
  const TraceScene ts = TraceScene::build(scene);
  std::vector<Ray> rays;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
          glm::vec3 o(i * 16.0f, j * 16.0f, 0.0f);
          o = axis == 0 ? glm::vec3(o.z, o.x, o.y) : axis == 1 ? glm::vec3(o.x, o.z, o.y) : o;
          o[axis] = sign > 0 ? -20.0f : 150.0f;
          glm::vec3 d(0.0f);
          d[axis] = sign;
          rays.push_back({o, 0.0f, d});
          rays.push_back({o + glm::vec3(8.0f) - glm::vec3(axis == 0 ? 8 : 0, axis == 1 ? 8 : 0, axis == 2 ? 8 : 0), 0.0f, d});
        }
  const int hits = expectClosestHitsMatchBruteForce(ts, rays);
  EXPECT_GT(hits, 400);
}

} // namespace
} // namespace bt
