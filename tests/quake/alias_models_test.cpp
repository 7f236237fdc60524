// quake/alias_models.h: the first frame and default skin of .mdl, .md2 and .md3 files written
// here, and that a truncated or lying file is an ImportError naming it.
#include "quake/alias_models.h"
#include "scene/diagnostics.h"
#include "tests/support/alias_model_writer.h"

#include <gtest/gtest.h>

namespace bt::quake {
namespace {

void expectCorner(const AliasCorner& c, glm::vec3 position, glm::vec2 st) {
  EXPECT_EQ(c.position, position);
  EXPECT_FLOAT_EQ(c.st.x, st.x);
  EXPECT_FLOAT_EQ(c.st.y, st.y);
}

TEST(AliasModels, MdlFirstFrameIsScaledAndMovedAndStIsHalfTexelCentred) {
  test::TestMdl m = test::squareMdl(4, 9);
  m.scale = glm::vec3(2.0f, 3.0f, 0.5f);
  m.origin = glm::vec3(-1.0f, 10.0f, 4.0f);
  const AliasModel model = readMdl(test::writeMdl(m), "sq.mdl");
  ASSERT_EQ(model.surfaces.size(), 1u);
  ASSERT_EQ(model.surfaces[0].corners.size(), 6u);
  EXPECT_EQ(model.skinWidth, 8);
  EXPECT_EQ(model.skinIndices, std::vector<uint8_t>(64, 9));
  // scale * v + scale_origin; st (s + 0.5) / skinwidth as gl_mesh.c BuildTris.
  expectCorner(model.surfaces[0].corners[0], {-1, 10, 4}, {0.5f / 8, 0.5f / 8});
  expectCorner(model.surfaces[0].corners[1], {7, 10, 4}, {7.5f / 8, 0.5f / 8});
  expectCorner(model.surfaces[0].corners[2], {7, 22, 4}, {7.5f / 8, 7.5f / 8});
  expectCorner(model.surfaces[0].corners[5], {-1, 22, 4}, {0.5f / 8, 7.5f / 8});
}

// A seam vertex of a triangle that faces away takes the back half of the skin: s + skinwidth / 2.
TEST(AliasModels, MdlOnseamVerticesOfBackFacingTrianglesMoveHalfASkin) {
  test::TestMdl m = test::squareMdl(4, 1);
  m.st[1].onseam = true;
  m.st[2].onseam = true;
  m.triangles[1].facesFront = false; // (0, 2, 3): vertex 2 on the seam
  const AliasModel model = readMdl(test::writeMdl(m), "seam.mdl");
  const std::vector<AliasCorner>& c = model.surfaces[0].corners;
  EXPECT_FLOAT_EQ(c[1].st.x, 7.5f / 8) << "front-facing: the seam changes nothing";
  EXPECT_FLOAT_EQ(c[2].st.x, 7.5f / 8);
  EXPECT_FLOAT_EQ(c[3].st.x, 0.5f / 8) << "not on the seam";
  EXPECT_FLOAT_EQ(c[4].st.x, (7.0f + 4.0f + 0.5f) / 8) << "back-facing, on the seam";
  EXPECT_FLOAT_EQ(c[5].st.x, 0.5f / 8);
}

TEST(AliasModels, MdlSkinIsTheOneAskedForElseTheFirst) {
  test::TestMdl m = test::squareMdl(4, 3);
  m.skins.push_back(std::vector<uint8_t>(64, 200));
  EXPECT_EQ(readMdl(test::writeMdl(m), "a.mdl", 1).skinIndices[0], 200);
  EXPECT_EQ(readMdl(test::writeMdl(m), "a.mdl", 0).skinIndices[0], 3);
  EXPECT_EQ(readMdl(test::writeMdl(m), "a.mdl", 7).skinIndices[0], 3);
}

TEST(AliasModels, Md2FirstFrameSkinAndSt) {
  test::TestMd2 m;
  m.skin = "models/items/thing/skin.pcx";
  m.positions = {{0, 0, 0}, {10, 0, 0}, {0, 20, 0}};
  m.scale = glm::vec3(0.5f);
  m.translate = glm::vec3(1, 2, 3);
  m.st = {{0, 0}, {8, 0}, {0, 4}};
  m.triangles = {{{0, 1, 2}, {0, 1, 2}}};
  const AliasModel model = readMd2(test::writeMd2(m), "tris.md2");
  ASSERT_EQ(model.surfaces.size(), 1u);
  EXPECT_EQ(model.surfaces[0].skin, m.skin);
  ASSERT_EQ(model.surfaces[0].corners.size(), 3u);
  expectCorner(model.surfaces[0].corners[1], {6, 2, 3}, {0.5f, 0.0f});
  expectCorner(model.surfaces[0].corners[2], {1, 12, 3}, {0.0f, 0.25f});
}

TEST(AliasModels, Md3SurfacesShadersAndPositionsInSixtyFourths) {
  test::TestMd3Surface a;
  a.shader = "models/powerups/thing.tga";
  a.positions = {{0, 0, 0}, {1.5f, 0, 0}, {0, -2.25f, 8}};
  a.st = {{0, 0}, {1, 0}, {0.25f, 0.75f}};
  a.triangles = {{0, 1, 2}};
  test::TestMd3Surface b = a;
  b.shader = "other";
  b.triangles = {{2, 1, 0}};
  const AliasModel model = readMd3(test::writeMd3({a, b}), "thing.md3");
  ASSERT_EQ(model.surfaces.size(), 2u);
  EXPECT_EQ(model.surfaces[0].skin, "models/powerups/thing.tga");
  EXPECT_EQ(model.surfaces[1].skin, "other");
  expectCorner(model.surfaces[0].corners[2], {0, -2.25f, 8}, {0.25f, 0.75f});
  expectCorner(model.surfaces[1].corners[0], {0, -2.25f, 8}, {0.25f, 0.75f});
}

// Every prefix of each file is refused with an error naming it, never read past its end.
TEST(AliasModels, TruncatedFilesAreErrorsNamingThem) {
  test::TestMd2 md2;
  md2.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  md2.st = {{0, 0}, {1, 0}, {0, 1}};
  md2.triangles = {{{0, 1, 2}, {0, 1, 2}}};
  test::TestMd3Surface s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.st = {{0, 0}, {1, 0}, {0, 1}};
  s.triangles = {{0, 1, 2}};
  for (const std::vector<uint8_t>& file : {test::writeMdl(test::squareMdl(4, 1)), test::writeMd2(md2), test::writeMd3({s})}) {
    EXPECT_NO_THROW(readAliasModel(file, "whole"));
    for (size_t size = 0; size < file.size(); ++size) {
      try {
        readAliasModel(std::span(file).first(size), "cut.mdl");
        ADD_FAILURE() << "a file cut to " << size << " of " << file.size() << " bytes was read";
      } catch (const ImportError& e) {
        EXPECT_EQ(e.diagnostic().file, "cut.mdl");
      }
    }
  }
}

TEST(AliasModels, LyingCountsAndIndicesAreErrors) {
  test::TestMdl m = test::squareMdl(4, 1);
  m.triangles[1].vertex[2] = 4; // one past the last vertex
  EXPECT_THROW(readMdl(test::writeMdl(m), "bad.mdl"), ImportError);
  std::vector<uint8_t> huge = test::writeMdl(test::squareMdl(4, 1));
  huge[60] = 0xff, huge[61] = 0xff, huge[62] = 0xff, huge[63] = 0x7f; // numverts 2^31 - 1
  try {
    readMdl(huge, "huge.mdl");
    ADD_FAILURE() << "read";
  } catch (const ImportError& e) {
    EXPECT_NE(std::string(e.what()).find("huge.mdl"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  test::TestMd3Surface s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.st = {{0, 0}, {1, 0}, {0, 1}};
  s.triangles = {{0, 1, 3}};
  EXPECT_THROW(readMd3(test::writeMd3({s}), "bad.md3"), ImportError);
  EXPECT_THROW(readAliasModel(std::vector<uint8_t>{'I', 'D', 'S', 'T', 10, 0, 0, 0}, "studio.mdl"), ImportError);
}

} // namespace
} // namespace bt::quake
