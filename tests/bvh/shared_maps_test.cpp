// The BVH on real levels from ../shared: structure, SAH against the full-sweep reference,
// closest hit against brute force, and no self-hits for bounce rays.
#include "bvh/trace_scene.h"
#include "importers/import.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace bt {
namespace {

struct SharedMap {
  const char* path; // under ../shared/maps
  int rays;         // brute force costs rays x brushes
};

class BvhOnSharedMap : public ::testing::TestWithParam<SharedMap> {};

TEST_P(BvhOnSharedMap, BuildsAndMatchesBruteForce) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path path = shared / "maps" / GetParam().path;
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  const Scene scene = importScene(path.string(), {.textures = {.load = false}});
  ASSERT_GT(scene.brushes.size(), 100u);
  const TraceScene ts = TraceScene::build(scene);
  std::printf("%s: %zu brushes, %zu traced, %zu nodes\n", GetParam().path, scene.brushes.size(), ts.brushes().size(), ts.nodes().size());

  test::expectWellFormed(ts);
  test::expectSahNearFullSweep(ts, BvhBuildOptions{}.leafSize, GetParam().path);

  // Brushes the importer could build all take part (the rest have no windings at all).
  size_t withWindings = 0;
  for (const Brush& b : scene.brushes) {
    bool any = false;
    for (uint32_t f = b.firstFace; f < b.firstFace + b.faceCount; ++f) any |= !scene.faces[f].winding.empty();
    withWindings += any;
  }
  EXPECT_EQ(ts.brushes().size(), withWindings);

  const std::vector<Ray> rays = test::randomRays(ts.bounds(), GetParam().rays, 41);
  int hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const auto bvh = ts.closestHit(rays[i]);
    const auto brute = test::bruteForceClosestHit(ts, rays[i]);
    ASSERT_EQ(bvh.has_value(), brute.has_value()) << "ray " << i;
    if (!bvh) continue;
    ++hits;
    ASSERT_EQ(bvh->t, brute->t) << "ray " << i;
    ASSERT_EQ(bvh->face, brute->face) << "ray " << i;
    ASSERT_EQ(bvh->inside, brute->inside) << "ray " << i;
  }
  EXPECT_GT(hits, GetParam().rays / 10); // random rays over the bounds: levels are mostly void

  // Bounce rays from the surfaces rays from outside-of-brush points find: never a start
  // inside a brush (unless the surface point itself lies inside another, overlapping brush),
  // never the plane they left.
  std::mt19937 rng(42);
  int bounces = 0;
  for (const Ray& r : rays) {
    const auto hit = ts.closestHit(r);
    if (!hit || hit->inside) continue;
    const GpuFace& face = ts.faces()[hit->face];
    const glm::vec3 n(face.plane[0], face.plane[1], face.plane[2]);
    glm::vec3 d = test::randomUnitVector(rng);
    if (glm::dot(d, n) < 0.0f) d = -d;
    const auto bounce = ts.closestHit({offsetRayOrigin(r.origin + r.direction * hit->t, n), 0.0f, d});
    ++bounces;
    if (!bounce) continue;
    const GpuFace& next = ts.faces()[bounce->face];
    const bool samePlane = next.plane[0] == face.plane[0] && next.plane[1] == face.plane[1] && next.plane[2] == face.plane[2] &&
        next.plane[3] == face.plane[3];
    EXPECT_FALSE(samePlane && !bounce->inside && bounce->t < 1.0f) << "self hit at t " << bounce->t;
  }
  EXPECT_GT(bounces, 0);
}

INSTANTIATE_TEST_SUITE_P(Maps, BvhOnSharedMap,
                         ::testing::Values(SharedMap{"quake_map_source/e1m1.map", 1500}, SharedMap{"quake_map_source/dm3.map", 1500},
                                           SharedMap{"librequake/lq1/maps/src/e4/lq_e4m3.map", 600},
                                           SharedMap{"unvanquished-chasm/maps/chasm.map", 600}),
                         [](const auto& info) {
                           std::string name = std::filesystem::path(info.param.path).stem().string();
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

} // namespace
} // namespace bt
