// Faithful mode for Quake 2 and Half-Life as a user sees it, against the reference compiler:
// every level under ../shared/oracle/lit-games/ (ericw-tools `light` 2.0.0-alpha11 with its game
// target's defaults; manifest.json gives the flags) is rendered from its source .map from three
// cameras, in colour, and compared pixel by pixel and luxel by luxel with its RGB lightmaps
// (oracle_view.h, the Quake 1 test's comparison).
//
// Both engines draw texture × luxel / 255 (no overbright: Quake 2's ref_gl at gl_modulate 1,
// Half-Life's GoldSrc, lighting/README.md "The compiled view"), so here the luxel shown is
// 255 × linearToSrgb(beauty) / texture per channel. Quake 2 shows the stored value; GoldSrc its
// light gamma table of it (about × 1.36), which oracle_view.h applies to the compiled luxels with
// its own copy of the table (goldsrc_display.h) before comparing.
#include "tests/render/oracle_levels.h"
#include "tests/render/oracle_view.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace bt {
namespace {

using test::Bar;

constexpr double kEngineDisplayScale = 1.0 / 255.0;

// Levels below the bar today, each held at what it reaches (the worst median and share within
// 5 % of its luxels and views) so that it cannot get worse unseen: none.
// Off this list: light_q2_translucent_shadow (issue 22), at 90.9 % of its luxels within 5 % and
// its views at 97.1 / 100 / 100 % since a bounce face's luxels lie where the compiler puts them
// (bounce.cpp compilerLuxelPoint, ltface.cc CalcPointNormal): a luxel of the face's grid that
// falls off the face takes its light on the coplanar face across the edge it lies behind, up to
// three faces on, and only then is snapped onto the face (within a luxel) or left dark, still one
// of the luxels the face's mean light is taken over. Before, every such luxel was pulled onto the
// face's nearest edge: the T-junction fix cuts the floor under the spotlights into fans whose
// grids reach far past their diagonal edges, and those luxels were lit at the edge instead of
// where they lie, so the floor bounced too much into the ceiling at z = 464 (lit by bounce
// alone): its luxels stored 8 to 60 were 1.6 % above the compiler's on average (those below 8,
// 2.9 %; those 8 to 19, 0.27 of a unit), now 1.1 % (1.7 %; 0.18 of a unit). Occluding them
// instead (no neighbours) left the ceiling 2.5 % too dark and the level at 75.5 %. The level was at 88.4 % (82 % before the bounce's sample points left the walls, 85 %
// before the faces were cut by qbsp's tree of the whole world, qbsp_tree.h, 86.7 % before qbsp's
// T-junction fix, qbsp_tjunc.h, 87.5 % before the tree valued a brush's axial sides first); its
// view from (-168 -666.667 192) (560 lit pixels, no glass in it) 95.7 % -> 100 %, the one from
// (-448 -16 87) 96.2 -> 97.1 %. What is left: the ceiling is still 1 % bright, and its floor is not the compiler's under the four mist panes at x -24 to -8
// (CONTENTS_MIST, which qbsp3 does not make solid: the .bsp's floor is whole under them, ours
// carved; made whole before this fix, its luxels fell to 87.2 %: not tried since).
// The compiler's glass (SURF_TRANS33/66, game_rules.h compilerGlass) passes the light and is lit
// from both sides as `light` does with the level's textures missing. The glass is drawn as ref_gl
// draws it (game_rules.h engineGlassAlpha: its texture, unlit, blended at 0.33 / 0.66) and its
// pixels are left out here with sky and unlit liquids, as the engine shows no lightmap there: the
// view from (-448 -16 87) leaves out 207 of them.
// q2_areaportals (its third room, x > 320, lit by the Quake 2 target's default
// `_bounce 1` alone) at 99.7 % of its luxels within 5 % since qbsp's merge keeps apart the faces
// that look into different contents (qbsp_faces.cpp mergeNodeFaces): the floor under each
// doorway looks into its area portal and is a face of its own, and the middle room's floor is
// subdivided from its own edge (qbsp_faces_test.cpp), which moved the bounce lights that light
// the third room through the doorway (99.9 % with the luxels placed as the compiler places them).
// It was at 63 % before the bounce sampled a face's light
// where the compiler does, 71 % before the world's faces were cut by qbsp's tree of the whole
// world, 82 % before qbsp's T-junction fix and 88.6 % before the merge by contents. With the
// compiler's own faces in place of ours it reaches the same 99.7 %.
// q2_light_visapprox (a light under the same water as q2_light_visapprox2) once
// the water casts shadows (4 % -> 95 % of its lit pixels within 5 %); q2_light_visapprox2 once a
// faithful shadow ray leaving a Quake 2 liquid brush through a face drawn as a wall is blocked as
// the compiler's is (RenderScene::blocksFromInside: qbsp gives such a brush's faces on both sides,
// Embree hits them either way): a camera inside the water saw the ceiling lit from the light at
// x = 516 through the water's x = 544 side, 66 % -> 100 % within 5 %, its luxels' dark ones 75 %
// -> 100 % within one step.
const std::map<std::string, Bar>& knownGaps() {
  // One level a line, whatever their number.
  // clang-format off
  static const std::map<std::string, Bar> gaps = {
  };
  // clang-format on
  return gaps;
}

class GamesOracleView : public ::testing::TestWithParam<const char*> {};

TEST_P(GamesOracleView, FaithfulPixelsMatchTheCompiledLightmaps) {
  BT_REQUIRE_SHARED(shared);
  const std::string bspName = std::string("maps_") + GetParam() + ".bsp";
  const std::filesystem::path map = test::oracleSourceMap(shared, bspName, "lit-games");
  ASSERT_FALSE(map.empty()) << "no manifest entry for " << bspName;
  const auto gap = knownGaps().find(GetParam());
  const Bar bar = gap == knownGaps().end() ? Bar{} : gap->second;
  test::checkOracleLevel(GetParam(), map, shared / "oracle" / "lit-games" / bspName, kEngineDisplayScale, bar, gap != knownGaps().end());
}

// No level under oracle/lit-games/ is left out of kLitGameLevels unseen.
TEST(GamesOracleView, EveryLitGameLevelIsListed) {
  BT_REQUIRE_SHARED(shared);
  size_t levels = 0;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "oracle" / "lit-games")) {
    const std::string file = entry.path().filename().string();
    if (entry.path().extension() != ".bsp" || !file.starts_with("maps_")) continue;
    const std::string name = file.substr(5, file.size() - 9);
    EXPECT_TRUE(std::find(std::begin(test::kLitGameLevels), std::end(test::kLitGameLevels), name) != std::end(test::kLitGameLevels))
        << name;
    ++levels;
  }
  EXPECT_EQ(levels, std::size(test::kLitGameLevels));
}

INSTANTIATE_TEST_SUITE_P(LitGames, GamesOracleView, ::testing::ValuesIn(test::kLitGameLevels), [](const auto& info) {
  std::string n = info.param;
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
});

} // namespace
} // namespace bt
