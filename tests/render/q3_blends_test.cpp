// Quake 3 shader blends as the engine draws them (lighting/liquids.h), on maps/q3blend/
// (generate.py there): three panels, additive, filter and alpha blend, before a lit wall, against
// blends_behind.map, the same room without them. tests/gl holds the GL tracer to the same rules.
#include "importers/bsp/q3_shaders.h"
#include "importers/import.h"
#include "lighting/liquids.h"
#include "lighting/render_scene.h"
#include "renderer/cpu/cpu_renderer.h"
#include "scene/color.h"
#include "tests/render/liquid_ranges.h"
#include "tests/render/test_level.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>

#include <functional>
#include <memory>

namespace bt {
namespace {

using test::expectNear;

constexpr int kWidth = 96;
constexpr int kHeight = 64;

// generate.py's images (sRGB bytes); the blend image's alpha is 128.
const glm::vec3 kAddSrgb = glm::vec3(40, 30, 60) / 255.0f;
const glm::vec3 kFilterSrgb = glm::vec3(180, 220, 120) / 255.0f;
const glm::vec3 kBlendSrgb = glm::vec3(50, 200, 90) / 255.0f;
constexpr float kBlendAlpha = 128.0f / 255.0f;

using test::Level;

std::unique_ptr<Level> load(const std::string& name) {
  return test::loadLevel(test::mapsDir() / "q3blend" / "maps" / name);
}

RenderImage render(const Level& level, LightingMode mode, int spp) {
  return test::renderFromDefaultCamera(level, mode, spp, kWidth, kHeight);
}

// Pixels whose ray and its four neighbours' meet faces of `texture`: jitter stays on the panel.
std::vector<size_t> panelPixels(const Scene& scene, const RenderImage& image, const std::string& texture) {
  auto on = [&](int x, int y) {
    const uint32_t f = image.face[size_t(y) * kWidth + x];
    return f != 0 && scene.faces[f - 1].texture == texture;
  };
  std::vector<size_t> pixels;
  for (int y = 1; y + 1 < kHeight; ++y)
    for (int x = 1; x + 1 < kWidth; ++x)
      if (on(x, y) && on(x - 1, y) && on(x + 1, y) && on(x, y - 1) && on(x, y + 1)) pixels.push_back(size_t(y) * kWidth + x);
  return pixels;
}

// The engine's framebuffer blends (gamma space) of a panel over what lies behind it (linear).
using Rule = std::function<glm::vec3(const glm::vec3& behindLinear)>;
const Rule kAdd = [](const glm::vec3& b) { return srgbToLinear(kAddSrgb + linearToSrgb(b)); };
const Rule kFilter = [](const glm::vec3& b) { return srgbToLinear(kFilterSrgb * linearToSrgb(b)); };
const Rule kBlend = [](const glm::vec3& b) { return test::engineBlend(kBlendAlpha, kBlendSrgb, b); };

TEST(Quake3Blends, TheFirstStagesBlendFuncAsTheEngineReadsIt) {
  const auto blends = bsp::parseShaderBlends(R"(
a { { map a.tga
 blendFunc add } }
b { { map b.tga
 blendfunc GL_ONE GL_ONE } }
c { { map c.tga
 blendFunc filter } }
d { { map d.tga
 blendFunc GL_ZERO GL_SRC_COLOR } }
e { { map e.tga
 blendFunc GL_DST_COLOR GL_ZERO } }
f { { map f.tga
 blendFunc blend } }
g { { map g.tga
 blendFunc GL_SRC_ALPHA GL_ONE_MINUS_SRC_ALPHA } }
h { { map $lightmap } { map h.tga
 blendFunc filter } }
i { { map i.tga } }
j { surfaceparm trans { map j.tga
 blendFunc GL_ONE GL_ZERO } }
)");
  using enum ShaderBlend;
  const std::map<std::string, ShaderBlend> want = {{"a", Add},   {"b", Add},   {"c", Filter}, {"d", Filter}, {"e", Filter},
                                                   {"f", Blend}, {"g", Blend}, {"h", Opaque}, {"i", Opaque}, {"j", Opaque}};
  EXPECT_EQ(blends, want);
}

// One sample a pixel in both maps, so that each pixel is one ray: every pixel of each panel is
// the engine's blend of its image over blends_behind.map's pixel, in beauty and albedo.
TEST(Quake3Blends, FaithfulPanelsAreTheEnginesBlend) {
  const auto level = load("blends.map"), behind = load("blends_behind.map");
  const RenderImage seen = render(*level, LightingMode::Faithful, 1);
  const RenderImage wall = render(*behind, LightingMode::Faithful, 1);
  for (const auto& [texture, rule] : {std::pair{"blend/add", kAdd}, std::pair{"blend/filter", kFilter}, std::pair{"blend/blend", kBlend}}) {
    SCOPED_TRACE(texture);
    const std::vector<size_t> pixels = panelPixels(level->scene, seen, texture);
    ASSERT_GT(pixels.size(), size_t(100)) << "the camera should see the panel";
    for (size_t i : pixels) {
      // Lit, and below 1, where the engine's framebuffer would clamp what lies behind.
      ASSERT_GT(wall.beauty[i].x, 0.01f) << "the wall behind should be lit";
      ASSERT_LT(glm::max(wall.beauty[i].x, glm::max(wall.beauty[i].y, wall.beauty[i].z)), 1.0f) << "the wall behind is too bright";
      const bool ok = expectNear(seen.beauty[i], rule(wall.beauty[i]), 0.01f, i, "beauty") &&
          expectNear(seen.albedo[i], rule(wall.albedo[i]), 0.01f, i, "albedo");
      if (!ok) break; // one pixel tells
    }
  }
}

// Physical mode: an additive panel adds its image's linear colour to what lies behind it and a
// filter multiplies it by that colour; the means over each panel, 32 samples, within 5 %.
TEST(Quake3Blends, PhysicalAddAndFilterOnAverage) {
  const auto level = load("blends.map"), behind = load("blends_behind.map");
  const RenderImage seen = render(*level, LightingMode::Physical, 32);
  const RenderImage wall = render(*behind, LightingMode::Physical, 32);
  const auto mean = [](const RenderImage& image, const std::vector<size_t>& pixels) {
    glm::dvec3 sum(0.0);
    for (size_t i : pixels) sum += glm::dvec3(image.beauty[i]);
    return sum / double(pixels.size());
  };
  const std::vector<size_t> add = panelPixels(level->scene, seen, "blend/add");
  const std::vector<size_t> filter = panelPixels(level->scene, seen, "blend/filter");
  ASSERT_GT(add.size(), size_t(100));
  ASSERT_GT(filter.size(), size_t(100));
  const glm::dvec3 wantAdd = mean(wall, add) + glm::dvec3(srgbToLinear(kAddSrgb));
  const glm::dvec3 wantFilter = mean(wall, filter) * glm::dvec3(srgbToLinear(kFilterSrgb));
  const glm::dvec3 gotAdd = mean(seen, add), gotFilter = mean(seen, filter);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(gotAdd[c], wantAdd[c], 0.05 * wantAdd[c]) << "add, channel " << c;
    EXPECT_NEAR(gotFilter[c], wantFilter[c], 0.05 * wantFilter[c]) << "filter, channel " << c;
  }
  EXPECT_GT(mean(wall, filter).x, 0.01) << "a black wall proves nothing";
}

// The blended panels cast no shadow (q3map2 leaves `surfaceparm trans` out of its light
// trace) and are drawn unlit, as the engine draws a one-stage shader.
TEST(Quake3Blends, BlendedFacesAreLiquidsThatCastNoShadow) {
  const auto level = load("blends.map");
  size_t panels = 0;
  for (size_t f = 0; f < level->scene.faces.size(); ++f) {
    const std::string& texture = level->scene.faces[f].texture;
    if (!texture.starts_with("blend/") || texture == "blend/wall" || texture == "blend/floor") continue;
    EXPECT_TRUE(level->render.faceFlags[f] & kFaceLiquid) << texture;
    ++panels;
  }
  EXPECT_EQ(panels, size_t(3));
  const uint32_t blend = *level->scene.findMaterial("blend/blend");
  EXPECT_NEAR(level->render.materials[blend].opacity, kBlendAlpha, 1e-3);
  const uint32_t wall = *level->scene.findMaterial("blend/wall");
  EXPECT_FLOAT_EQ(level->render.materials[wall].opacity, 1.0f);
}

} // namespace
} // namespace bt
