// The viewer's "why is this spot lit" (faithfulLightShares): the shares of the lights, the
// ambient term and the floors add up to the light the surface shows, each light's share is what
// it gives alone, and the shown light is the one the tracer shows there. Physical mode's
// (physicalLightShares): without bounces the lights' direct shares are the whole of what the
// paths show, and with them the rest is the bounced light.
#include "lighting/faithful_light.h"
#include "lighting/visibility.h"
#include "renderer/cpu/integrator.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

namespace bt {
namespace {

// Points the camera could see in manyLightsRoom: floor, walls and pillars hit from above and
// sideways through the room.
std::vector<SurfaceHit> roomPoints(const RenderScene& rs) {
  std::vector<SurfaceHit> hits;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 from(-480.0f + 15.0f * float(i), -470.0f + 14.0f * float(i % 9), 200.0f);
    const glm::vec3 dir = glm::normalize(glm::vec3(i % 2 ? 0.7f : -0.3f, float(i % 5) * 0.2f - 0.4f, -0.5f));
    const SurfaceHit hit = traceVisible(rs, Ray{from, 0.0f, dir, 1e9f});
    if (hit.found && !(rs.faceFlags[hit.face] & kFaceSky)) hits.push_back(hit);
  }
  return hits;
}

FaithfulQuery queryAt(const RenderScene& rs, const SurfaceHit& hit) {
  FaithfulQuery q;
  q.p = hit.position;
  q.n = hit.normal;
  q.faceMinlight = faithfulFaceMinlight(rs, hit.face);
  q.lights = LightSet::All;
  return q;
}

void expectNear(const glm::vec3& a, const glm::vec3& b, const char* what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-3f * std::max(1.0f, std::abs(b[c]))) << what << " channel " << c;
}

TEST(LightShares, AddUpToTheShownLightWhichIsTheTracersLight) {
  Diagnostics diags;
  Scene scene = test::manyLightsRoom(60, false, 3);
  scene.entities[0].keys.emplace_back("_minlight", "120"); // dim corners show the floor
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const std::vector<SurfaceHit> hits = roomPoints(rs);
  ASSERT_GT(hits.size(), 40u);
  int floored = 0, lit = 0;
  for (const SurfaceHit& hit : hits) {
    Rng rng(7), reference(7);
    const LightShares shares = faithfulLightShares(rs, queryAt(rs, hit), 4, rng);
    ASSERT_EQ(shares.perLight.size(), rs.lights.size());
    glm::vec3 sum = shares.ambient + shares.floors;
    for (const glm::vec3& share : shares.perLight) sum += share;
    expectNear(sum, shares.shown, "shares against the shown light");
    // No soft light in this room: the tracer's exhaustive light is exact, whatever it draws.
    expectNear(shares.shown, faithfulLight(rs, queryAt(rs, hit), reference), "shown light against the tracer's");
    floored += shares.floors != glm::vec3(0.0f);
    lit += shares.shown != shares.floors;
  }
  EXPECT_GT(floored, 0) << "no point shows a floor (minlight 120)";
  EXPECT_GT(lit, 20) << "too few lit points to say anything";
}

TEST(LightShares, EachLightsShareIsWhatItGivesAlone) {
  Diagnostics diags;
  const Scene scene = test::manyLightsRoom(60, false, 5); // rs points at it
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  int checked = 0;
  for (const SurfaceHit& hit : roomPoints(rs)) {
    Rng rng(1);
    const LightShares shares = faithfulLightShares(rs, queryAt(rs, hit), 4, rng);
    for (size_t i = 0; i < rs.lights.size(); ++i) {
      if (rs.lights[i].formula == uint32_t(LightFormula::LocalMin)) continue; // a floor, not a term
      const GivenLights alone{std::span<const GpuLight>(&rs.lights[i], 1)};
      FaithfulQuery q = queryAt(rs, hit);
      q.lights = LightSet::Given;
      q.given = &alone;
      q.occlusion = shares.occlusion;
      Rng own(1);
      expectNear(shares.perLight[i], faithfulLight(rs, q, own), "one light's share");
      checked += shares.perLight[i] != glm::vec3(0.0f);
    }
  }
  EXPECT_GT(checked, 100);
}

// The camera rays of roomPoints, for physical mode (which takes the ray, not the point).
std::vector<Ray> roomRays() {
  std::vector<Ray> rays;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 from(-480.0f + 15.0f * float(i), -470.0f + 14.0f * float(i % 9), 200.0f);
    rays.push_back(Ray{from, 0.0f, glm::normalize(glm::vec3(i % 2 ? 0.7f : -0.3f, float(i % 5) * 0.2f - 0.4f, -0.5f)), 1e9f});
  }
  return rays;
}

// No bounce, every light at every hit, and no sky or emitting surface to see (manyLightsHall):
// each path is the sum of the lights' direct light, so the shares add up to what the paths show
// with nothing left over, at every lit point.
TEST(PhysicalShares, WithoutBouncesTheLightsSharesAreAllOfTheShownLight) {
  Diagnostics diags;
  const Scene scene = test::manyLightsHall(60, 3);
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  IntegratorSettings direct;
  direct.mode = LightingMode::Physical;
  direct.bounces = 0;
  direct.lightSelection = false;
  int lit = 0;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 from(-1900.0f + 60.0f * float(i), -200.0f + 45.0f * float(i % 9), 200.0f);
    const Ray ray{from, 0.0f, glm::normalize(glm::vec3(i % 2 ? 0.4f : -0.4f, float(i % 5) * 0.2f - 0.4f, -0.5f)), 1e9f};
    Rng rng(3);
    const PhysicalShares shares = physicalLightShares(rs, direct, ray, 4, rng);
    ASSERT_EQ(shares.perLight.size(), rs.lights.size());
    glm::vec3 lights(0.0f);
    for (const glm::vec3& share : shares.perLight) lights += share;
    expectNear(lights, shares.shown, "the lights' shares against the paths' light");
    expectNear(shares.rest, glm::vec3(0.0f), "what is left without bounces");
    lit += shares.shown != glm::vec3(0.0f);
  }
  EXPECT_GT(lit, 20) << "too few lit points to say anything";
}

// With bounces the paths show more than the direct light: the rest is the bounced light (and the
// skylight's sky seen from the first surface, in both estimates alike), about
// what the same paths show less their first surface's direct light (a second, independent
// estimate: within the noise of 256 paths).
TEST(PhysicalShares, WithBouncesTheRestIsTheBouncedLight) {
  Diagnostics diags;
  const Scene scene = test::manyLightsRoom(60, false, 3);
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  IntegratorSettings withBounces, direct;
  withBounces.mode = direct.mode = LightingMode::Physical;
  direct.bounces = 0;
  double rest = 0.0, bounced = 0.0;
  for (const Ray& ray : roomRays()) {
    Rng rng(5), other(9), again(9);
    const PhysicalShares shares = physicalLightShares(rs, withBounces, ray, 256, rng);
    rest += shares.rest.r + shares.rest.g + shares.rest.b;
    glm::vec3 all(0.0f), first(0.0f);
    for (int i = 0; i < 256; ++i) all += radiance(rs, withBounces, ray, other), first += radiance(rs, direct, ray, again);
    bounced += double((all - first).r + (all - first).g + (all - first).b) / 256.0;
  }
  EXPECT_GT(bounced, 0.0) << "the room bounces no light: the test cannot tell";
  EXPECT_NEAR(rest, bounced, 0.04 * bounced) << "rest " << rest << ", bounced " << bounced;
}

} // namespace
} // namespace bt
