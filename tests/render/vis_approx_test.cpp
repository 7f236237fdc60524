// ericw-tools `light` without vis data culls a light from every face whose bounds lie apart from
// the light's box, the bounds of where 32 x 32 rays from it stop, grown by a quarter (lighting/
// vis_approx.h). A light that shines through a gap none of those rays find leaves what it would
// light beyond black in the compiled lightmaps, and faithful mode's luxels are the compiler's.
#include "lighting/lightmap_bake.h"
#include "lighting/render_scene.h"
#include "lighting/vis_approx.h"
#include "tests/render/box_scene.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bt {
namespace {

// A hall 1536 long, cut at x = 300 by a wall with a 16 x 16 hole at its middle; a light 300
// units before the hole shines through it onto the hall's far wall (x = 1024). The hole takes
// 2e-4 of the light's sphere, and the compiler's rays pass beside it (their z steps of 2/31 miss
// the hole's +-0.027), so the light's box ends in its own half, well before the far wall.
// `bounce`: the level bounces light (BounceLightsAreCulledByTheirOwnBoxes).
Scene holedWallHall(const std::string& format, const std::string& lightOrigin = "0 0 0", bool bounce = false) {
  test::BoxSceneBuilder b;
  if (bounce) b.worldKey("_bounce", "1"), b.worldKey("_bouncescale", "4");
  const std::string wall = b.material("wall", 128, 128, 128);
  b.room({-512, -512, -128}, {1024, 512, 128}, wall);
  b.box({300, -512, -128}, {316, -8, 128}, wall);
  b.box({300, 8, -128}, {316, 512, 128}, wall);
  b.box({300, -8, -128}, {316, 8, -8}, wall);
  b.box({300, -8, 8}, {316, 8, 128}, wall);
  if (bounce) b.box({140, 130, 30}, {160, 170, 70}, wall); // shades the hole from a light at (0 300 100)
  b.entity({{"classname", "light"}, {"origin", lightOrigin}, {"light", "1500"}});
  Scene scene = b.build();
  scene.format = format;
  return scene;
}

// The stored luxels of the far wall's face (x = 1024, facing -x): their largest value.
float farWallLight(const Scene& scene, RenderSceneOptions options = {}) {
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  std::vector<uint32_t> faces;
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    const Face& face = scene.faces[f];
    if (face.plane.normal.x < -0.99 && std::abs(face.plane.dist + 1024.0) < 0.01 && faceHasLightmap(rs, f)) faces.push_back(f);
  }
  EXPECT_EQ(faces.size(), 1u);
  Lightmaps lm = layoutLightmaps(rs, faces);
  bakeLightmaps(rs, lm);
  float peak = 0.0f;
  for (uint32_t v : lm.luxels) {
    const glm::vec3 c = unpackLuxel(v);
    peak = std::max({peak, c.x, c.y, c.z});
  }
  return peak;
}

TEST(VisApprox, TheLightsBoxEndsBeforeTheHole) {
  const Scene scene = holedWallHall("valve220");
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diagnostics);
  ASSERT_EQ(rs.visBoxes.size(), 1u);
  ASSERT_EQ(rs.lights.front().visBox, 1u);
  const GpuVisBox& box = rs.visBoxes.front();
  // Its half of the hall, [-512, 300] x [-512, 512] x [-128, 128], grown by a quarter each side.
  EXPECT_NEAR(box.mins.x, -512.0f - 0.25f * 812.0f, 0.5f);
  EXPECT_NEAR(box.maxs.x, 300.0f + 0.25f * 812.0f, 0.5f);
  EXPECT_NEAR(box.maxs.z, 128.0f + 0.25f * 256.0f, 0.5f);
}

// From its .map the compiler runs without vis data and culls the light from the far wall, which
// stays black (minlight 0); a compiled .bsp's compile had vis data, which faithful mode does not
// cull by, and the light through the hole reaches the wall there.
TEST(VisApprox, ALightBehindAWallDoesNotLightTheFaceTheCompilerCullsItFrom) {
  EXPECT_EQ(farWallLight(holedWallHall("valve220")), 0.0f);
  EXPECT_GT(farWallLight(holedWallHall("bsp29")), 20.0f) << "the light reaches the far wall through the hole";
}

// A level prepared for the GL tracer leaves the boxes to the GPU bake (VisBoxes::Gpu: `render`
// on a GL backend, the viewer). Where it is baked on the CPU after all (no GL context, the
// viewer's CPU window or its style sets), the CPU bake computes them as it starts: the far wall
// stays black.
TEST(VisApprox, ACpuBakeOfALevelPreparedForTheGpuCullsAsWell) {
  RenderSceneOptions options;
  options.visApproxBoxes = RenderSceneOptions::VisBoxes::Gpu;
  Diagnostics diagnostics;
  const Scene scene = holedWallHall("valve220");
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  EXPECT_EQ(rs.visBoxLights.size(), 1u);
  EXPECT_TRUE(rs.visBoxes.empty()) << "left to the GPU";
  EXPECT_EQ(farWallLight(scene, options), 0.0f);
}

// The compiler culls bounce lights by their boxes too (ltface.cc SurfaceLight_SphereCull). With
// `_bounce 1` (`_bouncescale 4`), the light at (0 300 100) and a block at x = 140..160 between it
// and the hole, no direct light gets through the hole: only bounce light reaches the far wall,
// from the first half's faces (the end wall behind the light faces the hole). None of their
// lights' rays finds the hole, so the compiler culls them all from the far wall, which stays
// black; a compiled .bsp (no cull) shows what they would give it.
TEST(VisApprox, BounceLightsAreCulledByTheirOwnBoxes) {
  const std::string light = "0 300 100";
  EXPECT_EQ(farWallLight(holedWallHall("bsp29", light, false)), 0.0f) << "no direct light reaches the far wall";
  EXPECT_GT(farWallLight(holedWallHall("bsp29", light, true)), 4.0f)
      << "bounce light reaches the far wall through the hole where nothing is culled";
  EXPECT_EQ(farWallLight(holedWallHall("valve220", light, true)), 0.0f) << "the compiler culls it from the far wall";
}

} // namespace
} // namespace bt
