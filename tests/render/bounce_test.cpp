// Faithful `_bounce` (lighting/bounce.h): ericw-tools' bounce lights, against values worked
// out by hand from bounce.cc / IndirectLightFace.
#include "lighting/bounce.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/faithful.h"
#include "renderer/cpu/integrator.h"
#include "lighting/light_grid.h"
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "tests/render/box_scene.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>

namespace bt {
namespace {

// A 128 x 128 x 16 slab (its top at z = 16) under a light 184 units above the top's middle. The
// light is delay 3 (no falloff) with _anglescale 0, so every luxel of the top face gets exactly
// its value, 200; the sides and the bottom face away from it and get nothing.
test::BoxSceneBuilder litSlab(std::vector<std::pair<std::string, std::string>> slabEntity = {}) {
  test::BoxSceneBuilder b;
  b.material("grey", 128, 128, 128);
  b.worldKey("_bounce", "1");
  const uint32_t owner = slabEntity.empty() ? 0 : b.entity(std::move(slabEntity));
  b.box({0, 0, 0}, {128, 128, 16}, "grey", owner);
  b.entity({{"classname", "light"}, {"origin", "64 64 200"}, {"light", "200"}, {"delay", "3"}, {"_anglescale", "0"}});
  return b;
}

std::vector<GpuLight> bounceLightsOf(const RenderScene& rs) {
  std::vector<GpuLight> out;
  std::copy_if(rs.lights.begin(), rs.lights.end(), std::back_inserter(out),
               [](const GpuLight& l) { return l.formula == uint32_t(LightFormula::Bounce); });
  return out;
}

// The hand-worked case: one emitting face (the slab's top), one receiver.
//   mean direct light on the top face          L = 200 (every luxel)
//   emit = L x 127/255 (_bouncecolorscale 0)      = 99.6078
//   intensity = its brightest channel, > 1: colour (1, 1, 1)
//   value = intensity x area x _bouncescale x 0.5 = 99.6078 x 16384 x 0.5 = 815 987.5
//   at (64 64 17), the top's vertex mean 1 unit up, facing +z.
// A receiver facing down 300 units straight above it: 815 987.5 / 300^2 = 9.0665.
// One 300 across and 400 up (d = 500): both cosines 0.8, 815 987.5 x 0.64 / 500^2 = 2.0889.
TEST(FaithfulBounce, OneFaceLightsAReceiverAsWorkedOutByHand) {
  const Scene scene = litSlab().build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  const std::vector<GpuLight> bounced = bounceLightsOf(rs);
  ASSERT_EQ(bounced.size(), 1u) << "only the slab's top face is lit";
  const GpuLight& l = bounced[0];
  EXPECT_NEAR(l.value, 815987.5f, 1.0f);
  EXPECT_EQ(l.color, glm::vec3(1.0f));
  EXPECT_EQ(l.origin, glm::vec3(64.0f, 64.0f, 17.0f));
  EXPECT_EQ(l.direction, glm::vec3(0.0f, 0.0f, 1.0f));

  const glm::vec3 down(0.0f, 0.0f, -1.0f);
  Rng rng = pixelRng(0, 0, 0, 1);
  const GivenLights given{bounced};
  EXPECT_NEAR(faithfulLight(rs, {.p = {64.0f, 64.0f, 317.0f}, .n = down, .lights = LightSet::Given, .given = &given}, rng).x, 9.0665f,
              1e-3f);
  EXPECT_NEAR(faithfulLight(rs, {.p = {364.0f, 64.0f, 417.0f}, .n = down, .lights = LightSet::Given, .given = &given}, rng).x, 2.0889f,
              1e-3f);
  // Behind the emitting face, or a receiver turned away: nothing.
  EXPECT_EQ(faithfulLight(rs, {.p = {64.0f, 64.0f, 317.0f}, .n = -down, .lights = LightSet::Given, .given = &given}, rng), glm::vec3(0.0f));
  // Nearer than 128 units the distance is clamped: 815 987.5 / 128^2 = 49.80.
  EXPECT_NEAR(faithful::pointLightValue(l, down, down, 50.0f), 815987.5f / (128.0f * 128.0f), 1e-2f);
}

// Two rooms split by a wall 16 thick (x = 0..16), the light in the first, 32 units from the wall.
// The luxels along the second room's edges lie on the wall's back plane (x = 16), 1 unit off
// their faces; the compiler moves such a point out of the wall (PositionSamplePointOnFace), and
// from there the wall shades it: nothing in the second room is lit, so nothing there bounces, and
// its lightmaps stay black. A bounce that sampled the edge luxels where they lie saw the light
// through the wall and lit the second room (its floor's edge luxels took a tenth of the room's
// light from the first room's side).
TEST(FaithfulBounce, EdgeLuxelsBesideAWallDoNotSeeThroughIt) {
  test::BoxSceneBuilder b;
  const std::string grey = b.material("grey", 128, 128, 128);
  b.worldKey("_bounce", "1");
  b.room({-512, -256, -128}, {528, 256, 128}, grey);
  b.box({0, -256, -128}, {16, 256, 128}, grey);
  b.entity({{"classname", "light"}, {"origin", "-32 0 0"}, {"light", "600"}});
  const Scene scene = b.build();
  Diagnostics diags;
  RenderScene rs = buildRenderScene(scene, {}, diags);
  ASSERT_FALSE(bounceLightsOf(rs).empty()) << "the first room bounces";
  rs.lightmaps = layoutLightmaps(rs);
  bakeLightmaps(rs, rs.lightmaps);
  // The compiled faces wholly in the second room (x >= 16), and the first room's floor.
  float secondRoom = 0.0f, firstRoom = 0.0f;
  size_t secondRoomFaces = 0;
  for (size_t fi = 0; fi < rs.lightmaps.fragments.size(); ++fi) {
    const std::vector<dvec3>& polygon = rs.lightmaps.polygons[fi];
    const bool second = std::all_of(polygon.begin(), polygon.end(), [](const dvec3& v) { return v.x >= 16.0; });
    const bool firstFloor = std::all_of(polygon.begin(), polygon.end(), [](const dvec3& v) { return v.x <= 0.0 && v.z == -128.0; });
    const GpuLightmapFragment& g = rs.lightmaps.fragments[fi];
    for (uint32_t l = g.firstLuxel; l < g.firstLuxel + g.width * g.height; ++l) {
      const float c = glm::length(unpackLuxel(rs.lightmaps.luxels[l]));
      if (second) secondRoom = std::max(secondRoom, c);
      if (firstFloor) firstRoom = std::max(firstRoom, c);
    }
    secondRoomFaces += second;
  }
  ASSERT_GE(secondRoomFaces, 5u);
  EXPECT_GT(firstRoom, 100.0f) << "the first room is lit";
  EXPECT_EQ(secondRoom, 0.0f) << "light from the first room got through the wall";
}

TEST(FaithfulBounce, ScaleAndTextureColourKeys) {
  test::BoxSceneBuilder scaled = litSlab();
  scaled.worldKey("_bouncescale", "2");
  Diagnostics diags;
  const Scene scaledScene = scaled.build();
  const std::vector<GpuLight> twice = bounceLightsOf(buildRenderScene(scaledScene, {}, diags));
  ASSERT_EQ(twice.size(), 1u);
  EXPECT_NEAR(twice[0].value, 2.0f * 815987.5f, 2.0f);

  // _bouncecolorscale 1 takes the texture's mean colour: a red (200 0 0) slab emits
  // 200 x 200/255 = 156.86 in red, normalised to colour (1 0 0).
  test::BoxSceneBuilder red;
  red.material("red", 200, 0, 0);
  red.worldKey("_bounce", "1");
  red.worldKey("_bouncecolorscale", "1");
  red.box({0, 0, 0}, {128, 128, 16}, "red");
  red.entity({{"classname", "light"}, {"origin", "64 64 200"}, {"light", "200"}, {"delay", "3"}, {"_anglescale", "0"}});
  const Scene redScene = red.build();
  const std::vector<GpuLight> tinted = bounceLightsOf(buildRenderScene(redScene, {}, diags));
  ASSERT_EQ(tinted.size(), 1u);
  EXPECT_EQ(tinted[0].color, glm::vec3(1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(tinted[0].value, 200.0f * 200.0f / 255.0f * 16384.0f * 0.5f, 1.0f);
}

// Which faces bounce: models that cast shadows, except brush models with `_bounce -1`; the
// compiler ignored `_bounce -1` on a func_detail (deprecated/nobounce.map's oracle lightmaps).
TEST(FaithfulBounce, BrushEntityBounceKey) {
  auto bounceCount = [](std::vector<std::pair<std::string, std::string>> entity) {
    const Scene scene = litSlab(std::move(entity)).build();
    Diagnostics diags;
    return bounceLightsOf(buildRenderScene(scene, {}, diags)).size();
  };
  EXPECT_EQ(bounceCount({{"classname", "func_wall"}, {"_shadow", "1"}}), 1u);
  EXPECT_EQ(bounceCount({{"classname", "func_wall"}, {"_shadow", "1"}, {"_bounce", "-1"}}), 0u);
  EXPECT_EQ(bounceCount({{"classname", "func_wall"}}), 0u) << "casts no shadow, so bounces nothing";
  EXPECT_EQ(bounceCount({{"classname", "func_detail"}, {"_bounce", "-1"}}), 1u);
}

// Styled lights do not feed the bounce unless `_bouncestyled`; local minlight never does.
TEST(FaithfulBounce, StyledAndLocalMinlightSources) {
  auto bounceCount = [](std::vector<std::pair<std::string, std::string>> light, bool styled) {
    test::BoxSceneBuilder b;
    b.material("grey", 128, 128, 128);
    b.worldKey("_bounce", "1");
    if (styled) b.worldKey("_bouncestyled", "1");
    b.box({0, 0, 0}, {128, 128, 16}, "grey");
    b.entity(std::move(light));
    const Scene scene = b.build();
    Diagnostics diags;
    return bounceLightsOf(buildRenderScene(scene, {}, diags)).size();
  };
  const std::vector<std::pair<std::string, std::string>> styledLight = {
      {"classname", "light"}, {"origin", "64 64 200"}, {"light", "200"}, {"delay", "3"}, {"style", "5"}};
  EXPECT_EQ(bounceCount(styledLight, false), 0u);
  EXPECT_EQ(bounceCount(styledLight, true), 1u);
  EXPECT_EQ(bounceCount({{"classname", "light"}, {"origin", "64 64 200"}, {"light", "200"}, {"delay", "4"}}, false), 0u);
}

// `_bounce 2`: the second pass re-emits only what the first pass's lights brought. A floor and a
// ceiling slab, a light between them: each lights the other in pass 1, so pass 2 makes two more
// (dimmer) lights; `_bounce 1` stops after the first two.
TEST(FaithfulBounce, SecondPassReEmitsTheFirstPassLight) {
  auto make = [](const char* passes) {
    test::BoxSceneBuilder b;
    b.material("grey", 128, 128, 128);
    b.worldKey("_bounce", passes);
    b.box({0, 0, 0}, {128, 128, 16}, "grey");
    b.box({0, 0, 400}, {128, 128, 416}, "grey");
    b.entity({{"classname", "light"}, {"origin", "64 64 208"}, {"light", "200"}, {"delay", "3"}, {"_anglescale", "0"}});
    return b.build();
  };
  Diagnostics diags;
  const Scene one = make("1"), two = make("2");
  const std::vector<GpuLight> first = bounceLightsOf(buildRenderScene(one, {}, diags));
  const std::vector<GpuLight> both = bounceLightsOf(buildRenderScene(two, {}, diags));
  ASSERT_EQ(first.size(), 2u);
  ASSERT_EQ(both.size(), 4u);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(both[size_t(i)].value, first[size_t(i)].value, 1e-3f * first[size_t(i)].value);
  for (int i = 2; i < 4; ++i) {
    EXPECT_GT(both[size_t(i)].value, 0.0f);
    EXPECT_LT(both[size_t(i)].value, 0.1f * both[0].value);
  }
}

// The compiler drops a bounce light's share below 0.01 in every channel: so it has a finite
// reach, and the light grid lists it only in the cells it can light.
TEST(FaithfulBounce, GateGivesAFiniteReach) {
  GpuLight l;
  l.formula = uint32_t(LightFormula::Bounce);
  l.value = 1.0e6f;
  l.anglescale = 1.0f;
  l.direction = glm::vec3(0.0f, 0.0f, 1.0f);
  const float reach = faithfulReach(l, 1.0f);
  ASSERT_TRUE(std::isfinite(reach));
  EXPECT_GE(reach, 10000.0f); // sqrt(1e6 / 0.01)
  const glm::vec3 up(0.0f, 0.0f, 1.0f), down(0.0f, 0.0f, -1.0f);
  // Head-on (both cosines 1) 1e6 / d^2 is the gate at d = 10 000.
  EXPECT_GT(faithful::pointLightValue(l, down, -up, 9900.0f), 0.0f);
  EXPECT_EQ(faithful::pointLightValue(l, down, -up, 10100.0f), 0.0f);
  EXPECT_EQ(faithful::pointLightValue(l, down, -up, reach), 0.0f);
}

// Physical mode has its own bounces (--bounces): the bounce lights are not its point lights.
TEST(FaithfulBounce, PhysicalModeLeavesBounceLightsOut) {
  const Scene scene = litSlab().build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  ASSERT_EQ(bounceLightsOf(rs).size(), 1u);
  for (uint32_t i : rs.lightGrid.physicalLights()) EXPECT_NE(rs.lights[i].formula, uint32_t(LightFormula::Bounce));
}

// The budget: all luxels while the level's total fits, else each face's share, at least one.
TEST(FaithfulBounceBudget, SampleCountPerFace) {
  EXPECT_EQ(bounceSampleCount(289, 10000, 20000), 289u) << "the level fits: every luxel";
  EXPECT_EQ(bounceSampleCount(289, 20000, 20000), 289u);
  EXPECT_EQ(bounceSampleCount(289, 40000, 20000), 145u) << "half the budget: half of each face (rounded)";
  EXPECT_EQ(bounceSampleCount(1, 40000, 20000), 1u) << "at least one";
  EXPECT_EQ(bounceSampleCount(3, 400000, 20000), 1u);
  EXPECT_EQ(bounceSampleCount(0, 40000, 20000), 0u);
}

// test::manyLightsRoom's room of 24 lights with worldspawn `_bounce passes`.
Scene manyLightsBouncing(int passes) {
  Scene s = test::manyLightsRoom(24, false, 7);
  s.entities[0].keys.emplace_back("_bounce", std::to_string(passes));
  return s;
}

// A room of many lights with `_bounce 2`, prepared exactly and within a budget an eighth of its
// luxels with 4 shadow rays per gathered luxel (the path a large level takes).
struct BudgetRoom {
  Scene scene;
  RenderScene rs;
  std::vector<BrushContents> contents;
  explicit BudgetRoom(const std::vector<std::pair<std::string, std::string>>& worldKeys = {})
      : scene(withWorldKeys(manyLightsBouncing(2), worldKeys)), rs(prepared(scene)), contents(scene.brushes.size(), BrushContents::Solid) {}
  static Scene withWorldKeys(Scene s, const std::vector<std::pair<std::string, std::string>>& keys) {
    for (const auto& key : keys) s.entities[0].keys.push_back(key);
    return s;
  }
  static RenderScene prepared(const Scene& s) {
    Diagnostics diags;
    RenderSceneOptions options;
    options.bounceLights = false; // made below, with the budget under test
    return buildRenderScene(s, options, diags);
  }
};

glm::vec3 powerOf(std::span<const GpuLight> lights) {
  glm::vec3 sum(0.0f);
  for (const GpuLight& l : lights) sum += l.value * l.color;
  return sum;
}

TEST(FaithfulBounceBudget, SubsetEstimateIsCloseToTheExactBounce) {
  const BudgetRoom room;
  ASSERT_EQ(room.rs.world.bounces, 2);
  const BounceLights exact = makeBounceLights(room.rs, room.contents, {1u << 30, 1u << 30, 1u << 30, 0, 1u << 30});
  ASSERT_TRUE(exact.exact());
  ASSERT_GT(exact.luxels, 800u);
  BounceBudget budget;
  budget.directLuxels = budget.gatherLuxels = exact.luxels / 8;
  budget.gatherShadowRays = 4;
  budget.renderLights = 1u << 30;
  const BounceLights estimate = makeBounceLights(room.rs, room.contents, budget);
  EXPECT_FALSE(estimate.exact());
  EXPECT_TRUE(estimate.sampledLights);
  EXPECT_EQ(estimate.luxels, exact.luxels);
  EXPECT_LT(estimate.sampledLuxels, exact.luxels / 4) << "an eighth, plus one per small face";
  EXPECT_GE(estimate.sampledLuxels, exact.luxels / 8 - 10);

  // The same faces bounce (each face with light in it under both); per pass, the total power
  // is within 3 % (measured: 0.2 % for the direct pass, 0.7 % for the second) and each light's origin is its face's.
  ASSERT_EQ(estimate.lights.size(), exact.lights.size());
  const size_t perPass = exact.lights.size() / 2;
  for (size_t pass = 0; pass < 2; ++pass) {
    const std::span<const GpuLight> e(exact.lights.data() + pass * perPass, perPass);
    const std::span<const GpuLight> s(estimate.lights.data() + pass * perPass, perPass);
    for (size_t i = 0; i < perPass; ++i) ASSERT_EQ(s[i].origin, e[i].origin);
    const glm::vec3 pe = powerOf(e), ps = powerOf(s);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ps[c], pe[c], 0.03f * pe[c]) << "pass " << pass << " channel " << c;
  }
}

// Every field of two lists of lights, bit for bit (so that -0 and 0 differ, NaN equals itself).
void expectSameLights(const std::vector<GpuLight>& a, const std::vector<GpuLight>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t i = 0; i < a.size(); ++i)
    ASSERT_EQ(std::memcmp(&a[i], &b[i], sizeof(GpuLight)), 0) << what << ": light " << i << " of " << a.size();
}

TEST(FaithfulBounceBudget, EstimateIsTheSameForAnyThreadCount) {
  const BudgetRoom room;
  BounceBudget budget;
  budget.directLuxels = budget.gatherLuxels = 200;
  budget.gatherShadowRays = 4;
  budget.threads = 1;
  const BounceLights one = makeBounceLights(room.rs, room.contents, budget);
  budget.threads = 3;
  const BounceLights three = makeBounceLights(room.rs, room.contents, budget);
  ASSERT_FALSE(one.exact());
  expectSameLights(one.lights, three.lights, "1 and 3 threads");
}

// What the bounce preparation cuts short leaves its lights bit for bit as they were, whatever the
// threads: a later pass's luxel sweeps only the previous pass's lights that a light grid of them
// lists there (BounceBudget::gatherGridCellsPerAxis), and a luxel sampled again reuses its
// `_dirtmode 0` occlusion (reuseDirtOcclusion; `_dirtmode 1` casts its random rays again). The
// reference sweeps every light and casts every ray. The grid does leave lights out here (else the
// comparison could not fail): the room's first-pass lights face every way.
TEST(FaithfulBounceBudget, ShortcutsGiveTheReferenceBitForBit) {
  for (const auto& dirt :
       std::vector<std::vector<std::pair<std::string, std::string>>>{{}, {{"_dirt", "1"}}, {{"_dirt", "1"}, {"_dirtmode", "1"}}}) {
    const BudgetRoom room(dirt);
    const std::string level = dirt.empty() ? "no dirt" : dirt.size() == 1 ? "_dirtmode 0" : "_dirtmode 1";
    ASSERT_EQ(room.rs.world.dirtSettings.enabled, !dirt.empty());
    BounceBudget reference;
    // The same half of the luxels in every pass: later passes sample the direct pass's again.
    reference.directLuxels = reference.gatherLuxels = 400;
    reference.gatherShadowRays = 4; // the draw among the lights, as on a large level
    reference.renderLights = 1u << 30;
    reference.gatherGridCellsPerAxis = 0;
    reference.reuseDirtOcclusion = false;
    reference.threads = 1;
    const BounceLights swept = makeBounceLights(room.rs, room.contents, reference);
    ASSERT_TRUE(swept.sampledLights);
    ASSERT_GT(swept.lights.size(), 100u);
    for (const auto& [cells, threads] : {std::pair{0u, 1u}, {1u, 3u}, {8u, 1u}, {32u, 3u}}) {
      BounceBudget budget = reference;
      budget.gatherGridCellsPerAxis = cells;
      budget.reuseDirtOcclusion = true;
      budget.threads = threads;
      expectSameLights(makeBounceLights(room.rs, room.contents, budget).lights, swept.lights,
                       level + ", " + std::to_string(cells) + " cells, " + std::to_string(threads) + " threads");
    }
  }

  const BudgetRoom room;
  BounceBudget reference;
  reference.renderLights = 1u << 30;
  const BounceLights swept = makeBounceLights(room.rs, room.contents, reference);

  // The first pass's lights (the first half) in the default gather grid: cells list fewer than all.
  const std::vector<GpuLight> firstPass(swept.lights.begin(), swept.lights.begin() + std::ptrdiff_t(swept.lights.size() / 2));
  const LightGrid grid = buildLightGrid(firstPass, room.rs.tracer.bounds(), room.rs.world.scaledist, BounceBudget{}.gatherGridCellsPerAxis);
  const size_t cells = size_t(grid.header.dims[0]) * grid.header.dims[1] * grid.header.dims[2];
  ASSERT_GT(cells, 1u);
  size_t listed = 0;
  for (size_t c = 0; c < cells; ++c) listed += grid.cells[c].count;
  EXPECT_LT(listed, cells * firstPass.size() * 3 / 4)
      << "per cell on average " << double(listed) / double(cells) << " of " << firstPass.size();
}

// Clustering keeps the bounce lights' power and, seen from afar, their light; it leaves a
// level with few lights as it is.
TEST(FaithfulBounceBudget, ClusteredLightsKeepPowerAndLightFarAway) {
  const BudgetRoom room;
  const BounceLights exact = makeBounceLights(room.rs, room.contents, {1u << 30, 1u << 30, 1u << 30, 0, 1u << 30});
  ASSERT_GT(exact.lights.size(), 64u);
  EXPECT_EQ(clusterBounceLights(exact.lights, room.rs.tracer.bounds(), exact.lights.size()).size(), exact.lights.size());
  const std::vector<GpuLight> merged = clusterBounceLights(exact.lights, room.rs.tracer.bounds(), 32);
  ASSERT_LE(merged.size(), 32u);
  ASSERT_GE(merged.size(), 6u);
  const glm::vec3 pe = powerOf(exact.lights), pm = powerOf(merged);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(pm[c], pe[c], 1e-4f * pe[c]);
  // Unshadowed, 3000 units above the room looking down: within 5 %.
  auto unshadowed = [](std::span<const GpuLight> lights, const glm::vec3& p, const glm::vec3& n) {
    float sum = 0.0f;
    for (const GpuLight& l : lights) {
      const glm::vec3 d = l.origin - p;
      const float dist = glm::length(d);
      sum += faithful::pointLightValue(l, n, d / dist, dist) * faithful::maxChannel(l.color);
    }
    return sum;
  };
  const glm::vec3 above(0.0f, 0.0f, 3128.0f), down(0.0f, 0.0f, -1.0f);
  const float e = unshadowed(exact.lights, above, down);
  ASSERT_GT(e, 0.0f);
  EXPECT_NEAR(unshadowed(merged, above, down), e, 0.05f * e);
}

// A render says when its bounce was estimated; a level within the budget is exact and says nothing.
TEST(FaithfulBounceBudget, DiagnosticsNoteOnlyWhenEstimated) {
  Diagnostics small;
  (void)buildRenderScene(litSlab().build(), {}, small);
  for (const Diagnostic& d : small) EXPECT_EQ(d.message.find("_bounce estimated"), std::string::npos) << d.message;

  // A 4096 x 4096 slab: some 130 000 luxels, over the default budget's 20 000.
  test::BoxSceneBuilder b;
  b.material("grey", 128, 128, 128);
  b.worldKey("_bounce", "1");
  b.box({0, 0, 0}, {4096, 4096, 16}, "grey");
  b.entity({{"classname", "light"}, {"origin", "2048 2048 400"}, {"light", "300"}, {"delay", "3"}});
  Diagnostics large;
  (void)buildRenderScene(b.build(), {}, large);
  const auto note =
      std::find_if(large.begin(), large.end(), [](const Diagnostic& d) { return d.message.starts_with("_bounce estimated from "); });
  ASSERT_NE(note, large.end());
  EXPECT_EQ(note->severity, Severity::Note);
  EXPECT_NE(note->message.find(" luxels per pass"), std::string::npos) << note->message;
}

// --- A shown point draws among its cell's bounce lights (faithful_light.h LightSet::GridSampledBounce) ---

// The many-lights room with `_bounce 1`: its compiled faces bounce through hundreds of lights,
// and most cells list more than kBounceShadowRays of them.
struct BouncingRoom {
  Scene scene;
  RenderScene rs;
  BouncingRoom() : scene(manyLightsBouncing(1)), rs(prepared(scene)) {}
  static RenderScene prepared(const Scene& s) {
    Diagnostics diags;
    return buildRenderScene(s, {}, diags);
  }
  // Surface points seen from the room's middle, in directions spread over the sphere.
  std::vector<SurfaceHit> shownPoints(int count) const {
    std::vector<SurfaceHit> hits;
    for (int i = 0; i < count; ++i) {
      const float z = 1.0f - 2.0f * (float(i) + 0.5f) / float(count);
      const float phi = 2.39996323f * float(i);
      const float r = std::sqrt(1.0f - z * z);
      const SurfaceHit hit = traceVisible(rs, Ray{{100.0f, -100.0f, 128.0f}, 0.0f, {r * std::cos(phi), r * std::sin(phi), z}, 1e30f});
      if (hit.found) hits.push_back(hit);
    }
    return hits;
  }
};

// Mean, and standard error of the mean, of n draws.
struct MeanAndError {
  glm::dvec3 mean{0.0};
  glm::dvec3 error{0.0};
};

template <class Draw> MeanAndError meanOf(int n, const Draw& draw) {
  glm::dvec3 sum(0.0), sum2(0.0);
  for (int s = 0; s < n; ++s) {
    const glm::dvec3 v(draw(s));
    sum += v, sum2 += v * v;
  }
  MeanAndError m;
  m.mean = sum / double(n);
  m.error = glm::sqrt(glm::max(sum2 / double(n) - m.mean * m.mean, 0.0) / double(n - 1));
  return m;
}

// At points whose cell lists about 250 bounce lights: at most kBounceShadowRays shadow rays go to
// them, and over many draws the estimate's mean is the exact sum (LightSet::Grid, every
// light shadow-tested; the room has no soft lights, so that is one number) within its Monte
// Carlo error. Measured: |z| <= 2.5 at all 24 points, one draw's spread 0.4-5 % of the sum.
TEST(FaithfulBounceDraw, FewShadowRaysAndTheExactSumOnAverage) {
  const BouncingRoom room;
  size_t drawnPoints = 0;
  for (const SurfaceHit& hit : room.shownPoints(24)) {
    const size_t inCell = trailingBounceLights(room.rs.lights, room.rs.lightGrid.cellLights(hit.position));
    if (inCell <= kBounceShadowRays) continue;
    ++drawnPoints;
    Rng any = pixelRng(0, 0, 0, 1);
    const glm::dvec3 exact(faithfulLight(room.rs, {.p = hit.position, .n = hit.normal, .lights = LightSet::Grid}, any));
    const MeanAndError m = meanOf(400, [&](int s) {
      Rng rng = pixelRng(uint32_t(s), 7, 0, 3);
      int rays = 0;
      const glm::vec3 v = faithfulLight(
          room.rs,
          {.p = hit.position, .n = hit.normal, .twoSided = false, .lights = LightSet::GridSampledBounce, .bounceShadowRays = &rays}, rng);
      EXPECT_LE(rays, int(kBounceShadowRays)) << "of " << inCell << " bounce lights";
      return v;
    });
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(m.mean[c], exact[c], 4.5 * m.error[c] + 1e-4 * exact[c])
          << "channel " << c << " at " << hit.position.x << " " << hit.position.y << " " << hit.position.z;
  }
  EXPECT_GE(drawnPoints, 20u) << "most cells list more bounce lights than shadow rays";
}

// A bounce light lights nothing behind its face, so the grid leaves it out of the cells wholly
// behind it: in the room, the cells list well under all of its bounce lights (each reaches the
// whole room; measured: 145 of 251 per cell), and what the grid's lists sum is still what every
// light of the level sums.
TEST(FaithfulBounceDraw, CellsBehindABounceLightLeaveItOut) {
  const BouncingRoom room;
  const size_t bounceLights = bounceLightsOf(room.rs).size();
  const LightGrid& grid = room.rs.lightGrid;
  const size_t cells = size_t(grid.header.dims[0]) * grid.header.dims[1] * grid.header.dims[2];
  ASSERT_GT(cells, 100u);
  size_t listed = 0;
  for (size_t c = 0; c < cells; ++c)
    listed += trailingBounceLights(room.rs.lights, {grid.indices.data() + grid.cells[c].first, grid.cells[c].count});
  EXPECT_LT(listed, cells * bounceLights * 3 / 4)
      << "of " << bounceLights << " bounce lights, per cell on average " << double(listed) / double(cells);
  for (const SurfaceHit& hit : room.shownPoints(48)) {
    Rng a = pixelRng(0, 0, 0, 1), b = pixelRng(0, 0, 0, 1);
    const glm::vec3 every = faithfulLight(room.rs, {.p = hit.position, .n = hit.normal, .lights = LightSet::All}, a);
    const glm::vec3 listedSum = faithfulLight(room.rs, {.p = hit.position, .n = hit.normal, .lights = LightSet::Grid}, b);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(listedSum[c], every[c], 1e-4f * every[c] + 1e-4f) << "channel " << c;
  }
}

// A cell of no more than kBounceShadowRays bounce lights keeps the exact loop: the same number.
TEST(FaithfulBounceDraw, FewBounceLightsKeepTheExactLoop) {
  const Scene scene = litSlab().build();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  ASSERT_EQ(bounceLightsOf(rs).size(), 1u);
  const glm::vec3 down(0.0f, 0.0f, -1.0f);
  for (const glm::vec3 p : {glm::vec3(64.0f, 64.0f, 317.0f), glm::vec3(364.0f, 64.0f, 417.0f)}) {
    Rng a = pixelRng(1, 2, 3, 4), b = pixelRng(1, 2, 3, 4);
    int rays = 0;
    const glm::vec3 exact = faithfulLight(rs, {.p = p, .n = down, .lights = LightSet::Grid}, a);
    EXPECT_GT(exact.x, 0.0f);
    EXPECT_EQ(
        faithfulLight(rs, {.p = p, .n = down, .twoSided = false, .lights = LightSet::GridSampledBounce, .bounceShadowRays = &rays}, b),
        exact);
    EXPECT_EQ(rays, 1);
  }
}

// What a pixel shows (radiance(): floors, overbright clamp, sRGB decode of texture x light)
// converges to the exhaustive pixel. The pixel bends the light sum, so the mean of the drawn
// pixels is not exactly the exhaustive one (Jensen), but the bend is small over the draw's spread:
// per pixel (64 pixels, 128 samples each, through the pixel's centre: no jitter) within 4.5
// standard errors, and over a whole 32 x 24 image at 16 spp (the same camera jitter for both)
// within 0.5 % (measured: -0.03 %).
TEST(FaithfulBounceDraw, ShownPixelsConvergeToTheExhaustiveImage) {
  const BouncingRoom room;
  CameraPose pose;
  pose.origin = glm::vec3(400.0f, -400.0f, 200.0f);
  pose.yaw = 135.0f;
  pose.pitch = 20.0f;
  IntegratorSettings drawn, exhaustive;
  exhaustive.lightSelection = false;

  const Camera camera(pose, 8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const Ray ray = camera.ray(float(x) + 0.5f, float(y) + 0.5f);
      Rng any = pixelRng(0, 0, 0, 1);
      const glm::dvec3 exact(radiance(room.rs, exhaustive, ray, any));
      const MeanAndError m = meanOf(128, [&](int s) {
        Rng rng = pixelRng(uint32_t(x), uint32_t(y), uint32_t(s), 11);
        return radiance(room.rs, drawn, ray, rng);
      });
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(m.mean[c], exact[c], 4.5 * m.error[c] + 1e-5) << "pixel " << x << " " << y << " channel " << c;
    }

  RenderSettings settings;
  settings.width = 32;
  settings.height = 24;
  settings.spp = 16;
  settings.seed = 5;
  const Camera view(pose, settings.width, settings.height);
  const RenderImage sampled = renderCpu(room.rs, view, settings);
  settings.integrator = exhaustive;
  const RenderImage reference = renderCpu(room.rs, view, settings);
  glm::dvec3 sampledSum(0.0), referenceSum(0.0);
  for (size_t i = 0; i < reference.beauty.size(); ++i) {
    sampledSum += glm::dvec3(sampled.beauty[i]);
    referenceSum += glm::dvec3(reference.beauty[i]);
  }
  ASSERT_GT(referenceSum.y, 0.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sampledSum[c], referenceSum[c], 0.005 * referenceSum[c]) << "channel " << c;
}

// buildRenderScene makes the grid of a `_bounce` level once, then adds the bounce lights to it
// (extendLightGrid): the very grid of every light, lists, order and physical near lists alike.
void expectSameGrid(const LightGrid& a, const LightGrid& b, const std::string& what) {
  EXPECT_EQ(std::memcmp(&a.header, &b.header, sizeof(GpuLightGrid)), 0) << what;
  ASSERT_EQ(a.cells.size(), b.cells.size()) << what;
  for (size_t c = 0; c < a.cells.size(); ++c) {
    ASSERT_EQ(a.cells[c].first, b.cells[c].first) << what << ": cell " << c;
    ASSERT_EQ(a.cells[c].count, b.cells[c].count) << what << ": cell " << c;
  }
  EXPECT_EQ(a.indices, b.indices) << what;
}

TEST(FaithfulBounceDraw, GridWithBounceLightsAddedIsTheGridOfEveryLight) {
  const BouncingRoom room;
  const RenderScene& rs = room.rs;
  const Bounds bounds = rs.tracer.bounds();
  const float scaledist = rs.world.scaledist;
  const size_t bounce = bounceLightsOf(rs).size();
  ASSERT_GT(bounce, 100u);
  expectSameGrid(rs.lightGrid, buildLightGrid(rs.lights, bounds, scaledist), "buildRenderScene");

  // Any split of the lights: the direct lights' first ones, all of them, some bounce lights.
  // With lights added that are not bounce lights nor physical candidates (here every direct
  // light marked as a _surface point), each cell's order is the others, then the bounce lights.
  std::vector<GpuLight> surfacePoints = rs.lights;
  for (GpuLight& l : surfacePoints)
    if (l.formula != uint32_t(LightFormula::Bounce)) l.flags |= kLightFlagFromSurface;
  const size_t direct = rs.lights.size() - bounce;
  for (const std::vector<GpuLight>* lights : {&rs.lights, static_cast<const std::vector<GpuLight>*>(&surfacePoints)})
    for (const size_t first : {size_t(0), direct / 2, direct, direct + bounce / 3, rs.lights.size()}) {
      const std::vector<GpuLight> before(lights->begin(), lights->begin() + std::ptrdiff_t(first));
      for (const uint32_t cells : {kMaxLightGridCellsPerAxis, 4u})
        expectSameGrid(
            extendLightGrid(buildLightGrid(before, bounds, scaledist, cells), *lights, uint32_t(first), bounds, scaledist, cells),
            buildLightGrid(*lights, bounds, scaledist, cells),
            std::string(lights == &rs.lights ? "level's lights" : "surface points") + " from " + std::to_string(first) + ", " +
                std::to_string(cells) + " cells");
    }
}

} // namespace
} // namespace bt
