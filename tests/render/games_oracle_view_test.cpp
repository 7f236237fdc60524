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
//     The glass is drawn as ref_gl draws it (game_rules.h engineGlassAlpha: its texture, unlit,
//     blended at 0.33 / 0.66) and its pixels are left out here with sky and unlit liquids, as
//     the engine shows no lightmap there: the view from (-448 -16 87) leaves out 207 of them.
//   q2_areaportals: the bounced light (the Quake 2 target's default `_bounce 1`). Since the
//     bounce samples a face's light where the compiler does (bounce.cpp: an edge luxel beside a
//     wall moved out of it, as PositionSamplePointOnFace moves it, instead of seeing the light
//     behind that wall), its luxels went from 63 % to 71 % within 5 % (q2_areaportal and
//     q2_areaportal_with_detail, the same level without its third room, from 85 % to 98 % and
//     96 %: off this list). The rest lies in the third room (x > 320), lit by bounce alone and
//     dimly (30-180). Its walls were cut where the compiler's are not (the north and south walls
//     at the doorway's top, z = 192, where qbsp merges them across it and subdivides them at
//     z = 128; the east wall the other way round), which moved the bounce lights: since the
//     world's faces are cut by qbsp's tree of the whole world above their node and merged on it
//     (qbsp_faces.h, qbsp_tree.h; qbsp_faces_test.cpp holds those walls) its luxels went from 71 %
//     to 82 % within 5 % (median 0.39 % -> 0.00 %); since qbsp's T-junction fix re-cuts them
//     (qbsp_tjunc.h: the north wall's upper face a pentagon and a triangle, the floor between
//     the doorways too, each its own bounce light, as in the .bsp) to 88.6 % (its dark luxels
//     79 % -> 100 % within 5 %). What is left is not found yet: the third room's north wall and
//     floor are now the compiler's faces (qbsp_faces_test.cpp); the luxel layout and the
//     surface lights still take the faces before the T-junction fix. Not the areaportal: the compiler's bounce crosses it
//     as ours does (stopping our bounce light there takes q2_areaportal from 98 % to 93 %).
// Off this list: q2_light_visapprox (a light under the same water as q2_light_visapprox2) once
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
      {"ericw-tools_testmaps_q2_areaportals", {0.02, 0.88}},
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
