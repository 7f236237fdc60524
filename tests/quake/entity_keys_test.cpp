#include "quake/entity_keys.h"

#include "lighting/lights.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bt::quake {
namespace {

TEST(EntityKeys, NumberRuleTakesALeadingPlusAndRejectsTrailingGarbage) {
  EXPECT_EQ(parseNumber("+5"), 5.0);
  EXPECT_EQ(parseNumber("-0.5"), -0.5);
  EXPECT_EQ(parseNumber(".5"), 0.5);
  EXPECT_EQ(parseNumber("1e3"), 1000.0);
  EXPECT_EQ(parseNumber("64x"), std::nullopt);
  EXPECT_EQ(parseNumber("1,5"), std::nullopt);
  EXPECT_EQ(parseNumber(""), std::nullopt);
  EXPECT_EQ(parseNumber("+"), std::nullopt);
  EXPECT_EQ(parseNumber("++1"), std::nullopt);
  EXPECT_EQ(parseNumber("inf"), std::nullopt);
  EXPECT_EQ(parseNumber("nan"), std::nullopt);
  EXPECT_EQ(parseNumber("1e400"), std::nullopt);
}

TEST(EntityKeys, WordsAreSeparatedBySpacesTabsAndLineBreaks) {
  EXPECT_EQ(parseNumbers(" 1\t+2  3\r\n"), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(parseNumbers(""), std::vector<double>{});
  EXPECT_EQ(parseNumbers("1 2 three"), std::nullopt);
  EXPECT_EQ(parseDvec3("0\t0\t64"), glm::dvec3(0, 0, 64));
  EXPECT_EQ(parseVec3("1 2"), std::nullopt);
  EXPECT_EQ(parseVec3("1 2 3 4"), std::nullopt);
  EXPECT_EQ(parseFloat(" 300 "), 300.0f);
  EXPECT_EQ(parseFloat("1e300"), std::nullopt); // finite as a double, not as a float
  EXPECT_EQ(parseInteger("12"), 12);
  EXPECT_EQ(parseInteger("+12"), 12);
  EXPECT_EQ(parseInteger("1.5"), std::nullopt);
  EXPECT_EQ(parseInteger("3000000000"), std::nullopt);
}

TEST(EntityKeys, KeysMatchExactlyFirstThenIgnoringCaseAndSurroundingSpaces) {
  const KeyValues keys{{"Light", "100"}, {"_surface_radiosity ", "1"}, {"light", "200"}, {" \t_color", "1 0 0"}};
  auto valueOf = [&](std::string_view key) {
    const std::string* value = findKey(keys, key);
    return value ? *value : std::string("(absent)");
  };
  EXPECT_EQ(valueOf("light"), "200");
  EXPECT_EQ(valueOf("LIGHT"), "100");
  EXPECT_EQ(valueOf("_surface_radiosity"), "1");
  EXPECT_EQ(valueOf("_color"), "1 0 0");
  EXPECT_EQ(findKey(keys, "_surface"), nullptr);
}

TEST(EntityKeys, TypedGettersWarnAboutMalformedValuesNamingFileLineAndKey) {
  Entity entity;
  entity.line = 12;
  entity.keys = {{"classname", "light"}, {"wait", "2x"}, {"style", "1e30"}, {"_color", "255 128 0"}, {"origin", "1 2"}};
  Diagnostics diagnostics;
  const EntityKeys keys(entity, "maps/x.map", &diagnostics);
  EXPECT_EQ(keys.number("wait", 1.0f), 1.0f);
  EXPECT_EQ(keys.integer("style", 0), 1000000);
  EXPECT_EQ(keys.colour("_color"), glm::vec3(1.0f, 128.0f / 255.0f, 0.0f));
  EXPECT_EQ(keys.colour("_mincolor", glm::vec3(0.5f)), glm::vec3(0.5f));
  EXPECT_EQ(keys.vec3("origin"), std::nullopt);
  EXPECT_EQ(keys.string("classname"), "light");
  ASSERT_EQ(diagnostics.size(), 2u);
  EXPECT_EQ(diagnostics[0].file, "maps/x.map");
  EXPECT_EQ(diagnostics[0].line, 12);
  EXPECT_EQ(diagnostics[0].message, "light: key \"wait\" has value \"2x\", expected a number; using 1");
  EXPECT_EQ(diagnostics[1].message, "light: key \"origin\" has value \"1 2\", expected three numbers; ignored");
}

// What a mapper sees: a light written with tabs, a '+' and a padded key lights the level as the
// same light written plainly, and one with trailing garbage is the default light with a warning.
TEST(EntityKeys, LightEntitiesReadByTheRuleGiveTheSameLights) {
  auto lightsOf = [](std::vector<std::pair<std::string, std::string>> keys, Diagnostics& diagnostics) {
    Scene scene;
    scene.sourcePath = "x.map";
    scene.entities.push_back({1, {{"classname", "worldspawn"}}});
    keys.insert(keys.begin(), {"classname", "light"});
    scene.entities.push_back({2, std::move(keys)});
    return collectLights(scene, LightOptions{}, diagnostics).lights;
  };
  Diagnostics plainWarnings, tabbedWarnings, garbageWarnings;
  const auto plain = lightsOf({{"origin", "0 0 64"}, {"light", "200"}, {"_color", "255 0 0"}, {"wait", "2"}}, plainWarnings);
  const auto tabbed = lightsOf({{"origin", "0\t0\t+64"}, {"light ", "+200"}, {" _color", "255\t0 0"}, {"WAIT", "2"}}, tabbedWarnings);
  const auto garbage = lightsOf({{"origin", "0 0 64"}, {"light", "200x"}, {"wait", "2"}}, garbageWarnings);
  ASSERT_EQ(plain.size(), 1u);
  ASSERT_EQ(tabbed.size(), 1u);
  EXPECT_TRUE(plainWarnings.empty());
  EXPECT_TRUE(tabbedWarnings.empty());
  EXPECT_EQ(tabbed[0].origin, plain[0].origin);
  EXPECT_EQ(tabbed[0].value, plain[0].value);
  EXPECT_EQ(tabbed[0].color, plain[0].color);
  EXPECT_EQ(tabbed[0].atten, plain[0].atten);
  EXPECT_EQ(plain[0].value, 200.0f);
  EXPECT_EQ(plain[0].color, glm::vec3(1, 0, 0));
  ASSERT_EQ(garbage.size(), 1u);
  EXPECT_EQ(garbage[0].value, 300.0f);
  ASSERT_EQ(garbageWarnings.size(), 1u);
  EXPECT_NE(garbageWarnings[0].message.find("\"200x\""), std::string::npos);
}

} // namespace
} // namespace bt::quake
