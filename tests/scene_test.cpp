#include "scene/scene.h"

#include <gtest/gtest.h>

namespace bt {
namespace {

TEST(TextureFrame, TexelCoordinatesFollowTheFrame) {
  TextureFrame frame{{8.0, 0.0, 0.0}, {0.5, 0.0, 0.0}, {0.0, -2.0, 0.0}};
  EXPECT_DOUBLE_EQ(frame.s({10.0, 3.0, 7.0}), 1.0);
  EXPECT_DOUBLE_EQ(frame.t({10.0, 3.0, 7.0}), -6.0);
}

TEST(Bounds, GrowsAndMeasures) {
  Bounds b;
  EXPECT_TRUE(b.empty());
  EXPECT_EQ(b.surfaceArea(), 0.0);
  b.grow(dvec3{0, 0, 0});
  b.grow(dvec3{1, 2, 3});
  EXPECT_FALSE(b.empty());
  EXPECT_DOUBLE_EQ(b.surfaceArea(), 2.0 * (2 + 6 + 3));
}

TEST(Entity, KeepsDuplicateKeysAndFindsTheFirst) {
  Entity e;
  e.keys = {{"classname", "light"}, {"light", "200"}, {"light", "300"}};
  EXPECT_EQ(e.classname(), "light");
  ASSERT_NE(e.find("light"), nullptr);
  EXPECT_EQ(*e.find("light"), "200");
  EXPECT_EQ(e.value("missing", "x"), "x");
}

TEST(Scene, FindsMaterialsCaseInsensitively) {
  Scene s;
  s.materials.push_back(Material{.name = "*Water1"});
  EXPECT_EQ(s.findMaterial("*water1"), 0u);
  EXPECT_FALSE(s.findMaterial("lava").has_value());
}

TEST(Diagnostic, FormatsFileLineColumn) {
  EXPECT_EQ(format(Diagnostic{Severity::Error, "a.map", 3, 7, "bad number"}), "a.map:3:7: error: bad number");
  EXPECT_EQ(format(Diagnostic{Severity::Warning, "a.map", 0, 0, "x"}), "a.map: warning: x");
}

} // namespace
} // namespace bt
