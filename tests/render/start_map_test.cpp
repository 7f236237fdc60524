// The default level maps/start.map: it imports cleanly, every texture it names is one we ship,
// it has every light type, and its AOVs are exact and deterministic.
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace bt {
namespace {

Scene importStart() {
  return importScene((test::mapsDir() / "start.map").string(), ImportOptions{});
}

TEST(StartMap, ImportsWithEveryTextureAndLightType) {
  const Scene scene = importStart();
  for (const Diagnostic& d : scene.diagnostics) ADD_FAILURE() << format(d);
  for (const Material& m : scene.materials) EXPECT_FALSE(m.missing()) << m.name;
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  EXPECT_TRUE(diags.empty());
  bool point = false, spot = false, coloured = false, inverse2 = false, sun = false, dome = false;
  for (const GpuLight& l : rs.lights) {
    point |= l.type == uint32_t(LightType::Point) && l.cosOuter < -1.0f;
    spot |= l.type == uint32_t(LightType::Point) && l.cosOuter >= -1.0f;
    coloured |= l.color != glm::vec3(1.0f);
    inverse2 |= l.formula == uint32_t(LightFormula::Inverse2);
    sun |= l.type == uint32_t(LightType::Sun);
    dome |= l.type == uint32_t(LightType::Dome);
  }
  EXPECT_TRUE(point && spot && coloured && inverse2 && sun && dome);
  EXPECT_FALSE(rs.emitters.empty()); // the _surface lamp with its _glow texture
  EXPECT_GT(rs.world.minlight.x, 0.0f);
  const uint32_t lamp = *scene.findMaterial("lamp");
  EXPECT_TRUE(rs.materials[lamp].flags & kMaterialEmissive);
}

TEST(StartMap, AovsExactAndDeterministic) {
  const Scene scene = importStart();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  // Straight down from 100 units above the floor: the centre pixel sees the floor at depth 100.
  CameraPose pose;
  pose.origin = {-150, 60, 100};
  pose.pitch = 90;
  RenderSettings s;
  s.width = 33;
  s.height = 21;
  s.spp = 1;
  s.threads = 1;
  const RenderImage a = renderCpu(rs, Camera(pose, s.width, s.height), s);
  s.threads = 2;
  s.seed = 99;
  const RenderImage b = renderCpu(rs, Camera(pose, s.width, s.height), s);
  EXPECT_EQ(a.albedo, b.albedo);
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.face, b.face);

  const size_t centre = size_t(10) * 33 + 16;
  ASSERT_NE(a.face[centre], 0u);
  EXPECT_EQ(scene.faces[a.face[centre] - 1].texture, "floor");
  EXPECT_FLOAT_EQ(a.depth[centre], 100.0f);
  EXPECT_EQ(a.normal[centre], glm::vec3(0, 0, 1));
  EXPECT_GT(a.albedo[centre].x, 0.0f);
  // Everything in this view is floor, seen from straight above.
  for (size_t i = 0; i < a.face.size(); ++i) EXPECT_EQ(scene.faces[a.face[i] - 1].texture, "floor") << i;
}

} // namespace
} // namespace bt
