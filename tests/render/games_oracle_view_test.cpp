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
// 5 % of its luxels and views) so that it cannot get worse unseen:
//   light_q2_translucent_shadow: the compiler's glass (SURF_TRANS33/66, game_rules.h
//     compilerGlass) now passes the light and is lit from both sides as `light` does with the
//     level's textures missing; its luxels are at 88 % (82 % before the bounce's sample points
//     left the walls, 85 % before the faces were cut by qbsp's tree of the whole world,
//     qbsp_tree.h, 86.7 % before qbsp's T-junction fix, qbsp_tjunc.h, 87.5 % before the tree
//     valued a brush's axial sides first). Its view from (-168 -666.667 192) (560 lit pixels,
//     no glass in it) went from 85 % to 100 % within 5 % with the T-junction fix, and to 95.7 %
//     with the axial sides first. What misses are dim luxels (8 to 19 stored, where one unit is
//     more than 5 %) one unit brighter than the compiler's, on two metal4_2 faces lit by bounce
//     alone (the ceiling at z = 464, the wall at y = -752): before the T-junction fix, on the
//     ceiling 25-35 % of the luxels of each value from 1 to 19 were one unit above the
//     compiler's and the rest equal (none below), a bias of a fraction of a unit, not an offset.
//     Measured again (after the merge by contents, which moved nothing here): over its luxels
//     stored 10 to 19 ours are 0.22 of a unit above the compiler's on average, on the ceiling's
//     faces (z = 464) 0.3 to 0.64, while from 60 to 250 the mean ratio is within 0.5 % of 1:
//     the bounce into the ceiling is some 3 % too bright. Its floor is not the compiler's under
//     the four mist panes at x -24 to -8 (CONTENTS_MIST, which qbsp3 does not make solid: the
//     .bsp's floor is whole under them, ours carved); made whole (and their sample points not
//     solid), more light bounced into that ceiling and its luxels fell to 87.2 %, that view to
//     84.6 %: not taken until the bias is found.
//     The glass is drawn as ref_gl draws it (game_rules.h engineGlassAlpha: its texture, unlit,
//     blended at 0.33 / 0.66) and its pixels are left out here with sky and unlit liquids, as
//     the engine shows no lightmap there: the view from (-448 -16 87) leaves out 207 of them.
// Off this list: q2_areaportals (its third room, x > 320, lit by the Quake 2 target's default
// `_bounce 1` alone) at 99.7 % of its luxels within 5 % since qbsp's merge keeps apart the faces
// that look into different contents (qbsp_faces.cpp mergeNodeFaces): the floor under each
// doorway looks into its area portal and is a face of its own, and the middle room's floor is
// subdivided from its own edge (qbsp_faces_test.cpp), which moved the bounce lights that light
// the third room through the doorway. It was at 63 % before the bounce sampled a face's light
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
      {"ericw-tools_testmaps_light_q2_translucent_shadow", {0.02, 0.88}},
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
