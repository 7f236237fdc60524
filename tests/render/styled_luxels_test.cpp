// The luxels of a level baked one set per light style and summed with the style sliders' weights
// (lighting/lightmap_bake.h bakeStyledLuxels, sumStyles), against today's whole bake of the level
// with the lights of each style scaled (LightOptions::styleScale), every luxel in colour, on
// maps/light_styles.map (a light of style 0, one of style 5, a switchable one: style 32).
#include "importers/import.h"
#include "lighting/lightmap_bake.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace bt {
namespace {

std::array<float, 256> weights(float style5, float style32) {
  std::array<float, 256> w{};
  w.fill(1.0f);
  w[5] = style5;
  w[32] = style32;
  return w;
}

class StyledLuxelsTest : public ::testing::Test {
protected:
  StyledLuxelsTest() : scene_(importScene((test::mapsDir() / "light_styles.map").string(), ImportOptions{})) {}

  // today's path: the level's lights scaled as it loads, then baked whole
  std::vector<uint32_t> bakedWith(const std::array<float, 256>& scale) const {
    Diagnostics diags;
    const RenderScene rs = buildRenderScene(scene_, RenderSceneOptions{.lights = LightOptions{.styleScale = scale}}, diags);
    Lightmaps lm = layoutLightmaps(rs);
    bakeLightmaps(rs, lm);
    return lm.luxels;
  }

  Scene scene_;
};

// The largest difference of a colour channel between two luxel sets (256: sizes differ).
int worstChannel(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  if (a.size() != b.size() || a.empty()) return 256;
  int worst = 0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int((a[i] >> (8 * c)) & 255u) - int((b[i] >> (8 * c)) & 255u)));
  return worst;
}

TEST_F(StyledLuxelsTest, TheSumAtTheSlidersIsTheBakeOfTheLevelWithItsStylesScaled) {
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene_, RenderSceneOptions{}, diags);
  const Lightmaps lm = layoutLightmaps(rs);
  const StyledLuxels styled = bakeStyledLuxels(rs, lm);
  ASSERT_EQ(styled.styles, (std::vector<int>{0, 5, 32}));
  ASSERT_EQ(styled.light.size(), 3u);
  ASSERT_EQ(styled.light[1].size(), lm.luxels.size());

  // Float rounding before the truncation to bytes may move a luxel by one level, no more.
  EXPECT_LE(worstChannel(sumStyles(styled, weights(1.0f, 1.0f)), bakedWith(weights(1.0f, 1.0f))), 1) << "every slider at 1";
  const std::vector<uint32_t> moved = bakedWith(weights(0.5f, 1.5f));
  EXPECT_LE(worstChannel(sumStyles(styled, weights(0.5f, 1.5f)), moved), 1) << "style 5 at 0.5, style 32 at 1.5";
  EXPECT_EQ(worstChannel(sumStyles(styled, weights(0.0f, 0.0f)), bakedWith(weights(0.0f, 0.0f))), 0) << "both styles off";
  EXPECT_GT(worstChannel(moved, bakedWith(weights(1.0f, 1.0f))), 20) << "the sliders change nothing: the test cannot tell";
}

} // namespace
} // namespace bt
