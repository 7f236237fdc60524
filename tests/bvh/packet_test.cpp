// TraceScene::closestHits (the packet walk) against closestHit, ray by ray, bit for bit, on real
// levels: the CPU bake casts a luxel's penumbra suns and dome directions through it and its
// luxels must not move.
#include "bvh/trace_scene.h"
#include "importers/import.h"
#include "tests/bvh/bvh_test_util.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <array>
#include <cmath>
#include <random>

namespace bt {
namespace {

// Packets of `rays` (cut into runs of 1 to kPacketRays rays) answer as the rays one by one.
// Returns how many hit something.
int expectPacketsMatch(const TraceScene& ts, const std::vector<Ray>& rays, std::mt19937& rng) {
  int hits = 0;
  for (size_t first = 0; first < rays.size();) {
    const size_t count = std::min(rays.size() - first, size_t(rng() % TraceScene::kPacketRays) + 1);
    const std::span<const Ray> packet = std::span(rays).subspan(first, count);
    std::array<std::optional<Hit>, TraceScene::kPacketRays> got;
    ts.closestHits(packet, std::span(got).first(count));
    for (size_t k = 0; k < count; ++k) {
      const std::optional<Hit> want = ts.closestHit(packet[k]);
      const size_t i = first + k;
      EXPECT_EQ(got[k].has_value(), want.has_value()) << "ray " << i;
      if (!got[k] || !want) continue;
      ++hits;
      EXPECT_EQ(got[k]->t, want->t) << "ray " << i;
      EXPECT_EQ(got[k]->face, want->face) << "ray " << i;
      EXPECT_EQ(got[k]->brush, want->brush) << "ray " << i;
      EXPECT_EQ(got[k]->slot, want->slot) << "ray " << i;
      EXPECT_EQ(got[k]->inside, want->inside) << "ray " << i;
    }
    first += count;
  }
  return hits;
}

// 64 directions in a cone of `degrees` around `axis` (a penumbra's suns).
std::vector<glm::vec3> cone(const glm::vec3& axis, float degrees, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const glm::vec3 a = glm::normalize(std::abs(axis.x) < 0.6f ? glm::cross(axis, glm::vec3(1, 0, 0)) : glm::cross(axis, glm::vec3(0, 1, 0)));
  const glm::vec3 b = glm::cross(axis, a);
  std::vector<glm::vec3> dirs;
  for (size_t k = 0; k < TraceScene::kPacketRays; ++k) {
    const float r = std::tan(glm::radians(degrees)) * std::sqrt(u(rng)), phi = 6.2831853f * u(rng);
    dirs.push_back(glm::normalize(axis + r * (std::cos(phi) * a + std::sin(phi) * b)));
  }
  return dirs;
}

class PacketOnSharedMap : public ::testing::TestWithParam<const char*> {};

TEST_P(PacketOnSharedMap, AnswersAsSingleRays) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path path = shared / "maps" / GetParam();
  ASSERT_TRUE(std::filesystem::exists(path)) << path;
  const Scene scene = importScene(path.string(), {.textures = {.load = false}});
  const TraceScene ts = TraceScene::build(scene);
  ASSERT_TRUE(ts.triangleNodes().empty()); // else every ray goes one by one
  std::mt19937 rng(7);

  // Incoherent rays of every kind the traversal tests use (zero components, tMin, tMax).
  const std::vector<Ray> random = test::randomRays(ts.bounds(), 2000, 43);
  EXPECT_GT(expectPacketsMatch(ts, random, rng), 200);

  // Coherent packets from points just off the surfaces that random rays find, as the bake's:
  // a narrow cone of directions (a penumbra), and wide ones over the hemisphere (a dome).
  std::vector<Ray> coherent;
  int points = 0;
  for (const Ray& r : random) {
    const std::optional<Hit> hit = ts.closestHit(r);
    if (!hit || hit->inside || points == 60) continue;
    const GpuFace& face = ts.faces()[hit->face];
    const glm::vec3 n(face.plane[0], face.plane[1], face.plane[2]);
    const glm::vec3 origin = offsetRayOrigin(r.origin + r.direction * hit->t, n);
    glm::vec3 axis = test::randomUnitVector(rng);
    if (glm::dot(axis, n) < 0.0f) axis = -axis;
    for (const glm::vec3& d : cone(axis, points % 2 ? 3.0f : 60.0f, rng)) coherent.push_back(Ray{origin, 0.0f, d});
    ++points;
  }
  ASSERT_EQ(points, 60);
  EXPECT_GT(expectPacketsMatch(ts, coherent, rng), 1000);
}

INSTANTIATE_TEST_SUITE_P(Maps, PacketOnSharedMap, ::testing::Values("quake_map_source/e1m1.map", "librequake/lq1/maps/src/dm/lqdm5.map"),
                         [](const auto& info) { return std::filesystem::path(info.param).stem().string(); });

} // namespace
} // namespace bt
