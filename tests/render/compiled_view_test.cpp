// `--lighting compiled` as a user sees it: every lit oracle level (../shared/oracle/lit/, Quake 1,
// `.lit` files among them) and every level of ../shared/oracle/lit-games/ (Half-Life, Quake 2) is
// imported from its .bsp and rendered from the cameras of the faithful-mode view test; each
// pixel must show, within 1/255 in every channel after the display, the compiled lightmap that
// this test samples itself (lightmap_oracle.h, bilinear over the compiled face's luxels) at the
// point the pixel sees, through the engine's rule written out here again:
//   Quake     luxel = min(255, Σ stored × style >> 8), style 'm' = 264; shown = texture × luxel × 2 / 255
//   Half-Life t = min(1023, Σ stored × style × 338 >> 14), luxel = lightgammatable[t] >> 2 (GoldSrc's
//             light gamma at its defaults, gamma 2.5, lightgamma 2.5, brightness 0); × 1 / 255
//   Quake 2   luxel = Σ stored × style ('m' = 1), its hue kept below 255; shown = texture × luxel / 255
// Pixels on sky, unlit liquids, Quake 2's glass (SURF_TRANS33/66 without SURF_WARP: ref_gl draws it
// without its lightmap, game_rules.h engineGlassAlpha), fullbright texels and faces without a compiled lightmap (the
// world's only: brush entities' faces are not sampled) are left out and counted.
#include "importers/bsp/bsp_file.h"
#include "importers/bsp/pk3.h"
#include "importers/import.h"
#include "scene/color.h"
#include "lighting/compiled_lightmaps.h"
#include "renderer/cpu/cpu_renderer.h"
#include "tests/render/goldsrc_display.h"
#include "tests/render/lightmap_oracle.h"
#include "tests/render/oracle_levels.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <cstdio>
#include <functional>
#include <limits>
#include <string_view>

namespace bt {
namespace {

constexpr int kWidth = 96, kHeight = 72;
constexpr double kTolerance = 1.0 / 255.0 + 1e-4; // one step of the 8-bit display, and float noise
// Pixels at least this bright (display 0..1) show a 2 % error as more than a step of 1/255.
constexpr double kBright = 0.3;
constexpr size_t kMinBrightPixels = 50;
// Pixels that see a wall through Quake 2's glass, at least, for its test to judge by.
constexpr size_t kMinGlassPixels = 200;

enum class Engine { Quake, HalfLife, Quake2 };

// The worldspawn style strings' first letters (Quake's world.qc, the same in Half-Life and Quake 2).
constexpr std::string_view kStylesAtLoad = "mmammjnmmama";

// Each style's letter at load: the worldspawn strings, and the switchable styles (32..62) of the
// level's lights, 'a' for one that starts off (spawnflags 1), else 'm'. Empty: not set.
struct StyleTable {
  Engine engine = Engine::Quake;
  std::array<char, 256> letters{};

  StyleTable(Engine e, const Scene& scene) : engine(e) {
    for (size_t s = 0; s < kStylesAtLoad.size(); ++s) letters[s] = kStylesAtLoad[s];
    letters[63] = 'a';
    for (const Entity& entity : scene.entities) {
      const std::string* style = entity.find("style");
      if (!style || !entity.classname().starts_with("light")) continue;
      const int n = std::stoi(*style);
      if (n >= 32 && n < 63) letters[size_t(n)] = (std::stoi(std::string(entity.value("spawnflags", "0"))) & 1) ? 'a' : 'm';
    }
  }
  // The engine's weight: Quake and Half-Life (c - 'a') 22, 256 unset; Quake 2 (c - 'a') / 12, 1 unset.
  double weight(uint8_t style) const {
    const char c = letters[style];
    if (engine == Engine::Quake2) return c ? (c - 'a') / 12.0 : 1.0;
    return c ? (c - 'a') * 22.0 : 256.0;
  }
};

// What the engine uploads for luxel (x, y) of `f`.
glm::dvec3 engineLuxel(const StyleTable& styles, const test::LightmapOracle& oracle, const test::CompiledFace& f, int x, int y) {
  glm::dvec3 sum(0.0);
  for (int s = 0; s < 4 && f.styles[s] != 255; ++s) sum += oracle.luxel(f, x, y, s) * styles.weight(f.styles[s]);
  if (styles.engine == Engine::Quake2) {
    glm::dvec3 v = glm::floor(sum);
    const double peak = std::max({v.x, v.y, v.z});
    if (peak > 255.0) v = glm::floor(v * (255.0 / peak));
    return v;
  }
  if (styles.engine == Engine::HalfLife) return {test::goldSrcLuxel(sum.x), test::goldSrcLuxel(sum.y), test::goldSrcLuxel(sum.z)};
  return glm::min(glm::floor(sum / 256.0), glm::dvec3(255.0));
}

double displayScale(Engine engine) {
  return engine == Engine::Quake ? 2.0 / 255.0 : 1.0 / 255.0;
}

struct Comparison {
  size_t compared = 0, bright = 0, off = 0, excluded = 0;
  double worst = 0.0;
  std::string describe() const {
    return fmt::format("{} pixels compared ({} bright), {} off by more than 1/255 (worst {:.4f}), {} left out", compared, bright, off,
                       worst, excluded);
  }
};

// Where a point of the level shows which engine luxel values (several along a seam between two
// compiled faces; none where no compiled face with a lightmap lies).
using ExpectedAt = std::function<std::vector<glm::dvec3>(const glm::dvec3& p, const glm::dvec3& n)>;

// The pixels of `image` (1 spp, seed 0) against texture × luxel × scale, shown scaled by `gain`.
Comparison compareWith(const RenderScene& rs, const ExpectedAt& expectedAt, double scale, const Camera& camera, const RenderImage& image,
                       double gain = 1.0) {
  Comparison r;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      // The pixel's one sample: the renderer's own jittered ray (cpu_renderer.cpp).
      Rng rng = pixelRng(uint32_t(x), uint32_t(y), 0, 0);
      const glm::vec2 jitter = rng.next2();
      const SurfaceHit hit = traceVisible(rs, camera.ray(float(x) + jitter.x, float(y) + jitter.y));
      if (!hit.found) continue;
      const glm::dvec3 texture(baseColorAt(rs, hit.face, hit.position));
      // Mesh triangles (Quake 3 curves) have no compiled lightmap in the view yet: lit at each point.
      if (engineDrawsUnlit(rs, hit.face) || rs.scene->faces[hit.face].brush == kNoBrush ||
          emissiveAt(rs, hit.face, hit.position) != glm::vec3(0.0f)) {
        ++r.excluded;
        continue;
      }
      const std::vector<glm::dvec3> expected = expectedAt(glm::dvec3(hit.position), glm::dvec3(hit.normal));
      if (expected.empty()) {
        ++r.excluded;
        continue;
      }
      const glm::dvec3 shown = glm::clamp(glm::dvec3(linearToSrgb(image.beauty[size_t(y) * kWidth + x])) * gain, 0.0, 1.0);
      double error = 1e30;
      for (const glm::dvec3& luxel : expected) { // a seam between two compiled faces: either
        const glm::dvec3 want = glm::clamp(texture * luxel * scale, 0.0, 1.0);
        const glm::dvec3 d = glm::abs(shown - want);
        error = std::min(error, std::max({d.x, d.y, d.z}));
      }
      ++r.compared;
      r.bright += std::max({shown.x, shown.y, shown.z}) >= kBright;
      r.off += error > kTolerance;
      r.worst = std::max(r.worst, error);
    }
  return r;
}

Comparison compare(const RenderScene& rs, const test::LightmapOracle& oracle, const StyleTable& styles, const Camera& camera,
                   const RenderImage& image, double gain = 1.0) {
  const auto value = [&](const test::CompiledFace& f, int x, int y) { return engineLuxel(styles, oracle, f, x, y); };
  const auto at = [&](const glm::dvec3& p, const glm::dvec3& n) { return oracle.allAt(p, n, value); };
  return compareWith(rs, at, displayScale(styles.engine), camera, image, gain);
}

RenderImage renderView(const RenderScene& rs, const CameraPose& pose) {
  RenderSettings settings;
  settings.width = kWidth, settings.height = kHeight, settings.spp = 1, settings.seed = 0;
  return renderCpu(rs, Camera(pose, kWidth, kHeight), settings);
}

Engine engineOf(const Scene& scene) {
  return scene.format == "bsp30" ? Engine::HalfLife : scene.format == "ibsp38" ? Engine::Quake2 : Engine::Quake;
}

// One level: every camera's every pixel; returns how many views had lit pixels to judge by, and
// adds the pixels compared to `compared`.
int checkLevel(const std::filesystem::path& bsp, size_t* compared = nullptr) {
  SCOPED_TRACE(bsp.filename().string());
  const test::LightmapOracle oracle(bsp, /*styleZeroOnly=*/false);
  const Scene scene = importScene(bsp.string(), ImportOptions{});
  const Engine engine = engineOf(scene);
  Diagnostics diags;
  RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diags);
  const std::string why = showCompiledLightmaps(scene, rs, "");
  if (oracle.faces().empty()) return 0; // nothing lit: the warning path (ShowsFaithfulWithoutLightmaps)
  EXPECT_EQ(why, "");
  const StyleTable styles(engine, scene);
  int judged = 0;
  for (const CameraPose& pose : test::oracleCameras(scene, rs, oracle)) {
    const Camera camera(pose, kWidth, kHeight);
    const RenderImage image = renderView(rs, pose);
    const Comparison r = compare(rs, oracle, styles, camera, image);
    if (compared) *compared += r.compared;
    std::printf("%s", fmt::format("compiled view {} {}: {}\n", bsp.stem().string(), formatCameraPose(pose), r.describe()).c_str());
    EXPECT_EQ(r.off, 0u) << formatCameraPose(pose) << ": " << r.describe();
    if (r.bright < kMinBrightPixels) continue;
    // The comparison can fail: 2 % brighter is off by more than a step in the bright pixels.
    const Comparison brighter = compare(rs, oracle, styles, camera, image, 1.02);
    EXPECT_GT(brighter.off, r.bright / 2) << "2 % too bright still passes from " << formatCameraPose(pose);
    ++judged;
  }
  return judged;
}

class CompiledView : public ::testing::TestWithParam<const char*> {};

TEST_P(CompiledView, QuakePixelsShowTheCompiledLightmaps) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path bsp = shared / "oracle" / "lit" / (std::string("maps_") + GetParam() + ".bsp");
  checkLevel(bsp);
}

INSTANTIATE_TEST_SUITE_P(Lit, CompiledView, ::testing::ValuesIn(test::kLitLevels), [](const auto& info) {
  std::string n = info.param;
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
});

// Half-Life's display: hl_basic's lightmaps peak at 48, which GoldSrc brightens through its
// light gamma table (about × 1.36 at the defaults). Every pixel against the lightmap this test
// samples through its own copy of the table.
TEST(CompiledView, HalfLifeShowsItsLightmapsThroughGoldSrcsLightGamma) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path bsp = shared / "oracle" / "lit-games" / "maps_ericw-tools_testmaps_hl_basic.bsp";
  const test::LightmapOracle oracle(bsp, /*styleZeroOnly=*/false);
  double peak = 0.0;
  for (const test::CompiledFace& f : oracle.faces())
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const glm::dvec3 v = oracle.luxel(f, x, y, 0);
        peak = std::max({peak, v.x, v.y, v.z});
      }
  std::printf("hl_basic: lightmap peak %.0f stored, %.0f shown\n", peak, test::goldSrcLuxel(peak * 264.0));
  EXPECT_GT(test::goldSrcLuxel(peak * 264.0), peak * 1.3) << "GoldSrc brightens the lightmaps";
  // Its light is dim (no pixel above 0.3 of white), so no view is judged by the 2 % brighter
  // check; a light gamma of 2.2 instead of 2.5 moves its pixels by several steps of 1/255.
  size_t compared = 0;
  checkLevel(bsp, &compared);
  EXPECT_GT(compared, 10000u) << "the views of hl_basic show too little of its lightmaps";
}

// Half-Life and Quake 2, every lit level of oracle/lit-games/ (their RGB lighting lumps).
TEST(CompiledView, HalfLifeAndQuake2PixelsShowTheCompiledLightmaps) {
  BT_REQUIRE_SHARED(shared);
  int levels = 0, judged = 0;
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "oracle" / "lit-games"))
    if (entry.path().extension() == ".bsp") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const std::filesystem::path& bsp : files) {
    judged += checkLevel(bsp);
    ++levels;
  }
  std::printf("%s", fmt::format("{} Half-Life and Quake 2 levels, {} views with lit pixels judged\n", levels, judged).c_str());
  EXPECT_GT(judged, 0);
}

// Quake 2's glass as ref_gl draws it (gl_rsurf.c R_DrawAlphaSurfaces): its texture alone, without
// the lightmap the compiler gave it, blended in the framebuffer at alpha 0.33 (SURF_TRANS33) or
// 0.66 (SURF_TRANS66) over what was drawn behind it, here a wall shown with its compiled lightmap:
//   shown = alpha × glass texture + (1 - alpha) × min(1, wall texture × luxel / 255).
// Every pixel whose ray crosses one glass face (its flags read here from its own texinfo) and then
// meets a world face with a compiled lightmap, from the level's cameras.
TEST(CompiledView, Quake2GlassShowsItsTextureBlendedOverTheLightmapBehind) {
  BT_REQUIRE_SHARED(shared);
  const std::filesystem::path bsp = shared / "oracle" / "lit-games" / "maps_ericw-tools_testmaps_light_q2_translucent_shadow.bsp";
  const test::LightmapOracle oracle(bsp, /*styleZeroOnly=*/false);
  const Scene scene = importScene(bsp.string(), ImportOptions{});
  Diagnostics diags;
  RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diags);
  ASSERT_EQ(showCompiledLightmaps(scene, rs, ""), "");
  const StyleTable styles(Engine::Quake2, scene);
  const auto value = [&](const test::CompiledFace& f, int x, int y) { return engineLuxel(styles, oracle, f, x, y); };
  const auto alphaOf = [&](uint32_t face) {
    using namespace quake::q2;
    const Face& f = scene.faces[face];
    if (!f.surface || (f.surface->flags & SURF_WARP)) return 1.0;
    return (f.surface->flags & SURF_TRANS33) ? 0.33 : (f.surface->flags & SURF_TRANS66) ? 0.66 : 1.0;
  };
  // The glass's own compiled lightmap (255 here: the spotlight aims at it) is halved: the engine
  // never shows it, so no pixel may change, where glass drawn lit would show half its texture.
  for (size_t fi = 0; fi < rs.lightmaps.fragments.size(); ++fi) {
    if (alphaOf(rs.lightmaps.fragmentFace[fi]) == 1.0) continue;
    const GpuLightmapFragment& g = rs.lightmaps.fragments[fi];
    for (uint32_t i = 0; i < g.width * g.height; ++i) {
      uint32_t& luxel = rs.lightmaps.luxels[g.firstLuxel + i];
      luxel = packLuxel(unpackLuxel(luxel) * 0.5f);
    }
  }
  size_t compared33 = 0, compared66 = 0, off = 0;
  double worst = 0.0;
  // The level's cameras, and two that look through both panes (x = -40 .. -7, SURF_TRANS33 at
  // y = -512 .. -447, SURF_TRANS66 at y = -576 .. -511): one beside the light, one from beyond.
  std::vector<CameraPose> cameras = test::oracleCameras(scene, rs, oracle);
  cameras.push_back(CameraPose{.origin = {-200.0f, -500.0f, 80.0f}, .pitch = 10.0f, .yaw = 0.0f, .source = "through the glass"});
  cameras.push_back(CameraPose{.origin = {150.0f, -500.0f, 80.0f}, .pitch = 10.0f, .yaw = 180.0f, .source = "through the glass"});
  for (const CameraPose& pose : cameras) {
    const Camera camera(pose, kWidth, kHeight);
    const RenderImage image = renderView(rs, pose);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        // The pixel's one sample: the renderer's own jittered ray (cpu_renderer.cpp).
        Rng rng = pixelRng(uint32_t(x), uint32_t(y), 0, 0);
        const glm::vec2 jitter = rng.next2();
        const Ray ray = camera.ray(float(x) + jitter.x, float(y) + jitter.y);
        const SurfaceHit glass = traceVisible(rs, ray);
        if (!glass.found || alphaOf(glass.face) == 1.0) continue;
        const double alpha = alphaOf(glass.face);
        const glm::vec3 toGlass = glass.position - ray.origin;
        const float t = glm::length(toGlass);
        const SurfaceHit wall = traceVisible(rs, Ray{ray.origin, continueRayAfter(t), toGlass / t, std::numeric_limits<float>::infinity()});
        if (!wall.found || alphaOf(wall.face) != 1.0 || (rs.faceFlags[wall.face] & (kFaceSky | kFaceLiquid)) ||
            scene.faces[wall.face].brush == kNoBrush || emissiveAt(rs, wall.face, wall.position) != glm::vec3(0.0f))
          continue;
        const std::vector<glm::dvec3> luxels = oracle.allAt(glm::dvec3(wall.position), glm::dvec3(wall.normal), value);
        if (luxels.empty()) continue;
        const glm::dvec3 glassTexture(baseColorAt(rs, glass.face, glass.position));
        const glm::dvec3 wallTexture(baseColorAt(rs, wall.face, wall.position));
        const glm::dvec3 shown = glm::clamp(glm::dvec3(linearToSrgb(image.beauty[size_t(y) * kWidth + x])), 0.0, 1.0);
        double error = 1e30;
        for (const glm::dvec3& luxel : luxels) { // a seam between two compiled faces: either
          const glm::dvec3 behind = glm::clamp(wallTexture * luxel / 255.0, 0.0, 1.0);
          const glm::dvec3 d = glm::abs(shown - (alpha * glassTexture + (1.0 - alpha) * behind));
          error = std::min(error, std::max({d.x, d.y, d.z}));
        }
        (alpha < 0.5 ? compared33 : compared66) += 1;
        off += error > kTolerance;
        worst = std::max(worst, error);
      }
  }
  std::printf("%s",
              fmt::format("glass: {} pixels through SURF_TRANS33, {} through SURF_TRANS66, {} off by more than 1/255 (worst {:.4f})\n",
                          compared33, compared66, off, worst)
                  .c_str());
  EXPECT_GT(compared33 + compared66, kMinGlassPixels) << "the cameras see too little through the glass";
  EXPECT_EQ(off, 0u) << "worst " << worst;
}

// --- Quake 3 ---------------------------------------------------------------------------------
// OpenArena's levels (Debian's openarena-data): each planar draw surface's triangles, its
// vertices' lightmap coordinates interpolated at the point (barycentric), its page's block
// sampled bilinearly there, then ioquake3's display: each luxel doubled (r_mapOverBrightBits 2
// over r_overBrightBits 1) with its hue kept below 255, and the picture doubled by the gamma ramp.
const std::filesystem::path kOpenArenaMaps = "/usr/share/games/openarena/baseoa/pak1-maps.pk3";
constexpr size_t kOpenArenaLevels = 12;
constexpr int kPage = 128;

class Quake3Oracle {
public:
  explicit Quake3Oracle(bsp::BspFile file) : bsp_(std::move(file)) {}

  std::vector<glm::dvec3> allAt(const glm::dvec3& p, const glm::dvec3& n) const {
    std::vector<glm::dvec3> out;
    const bsp::Model& world = bsp_.models.at(0);
    for (int32_t i = world.firstFace; i < world.firstFace + world.faceCount; ++i) {
      const bsp::Surface& s = bsp_.surfaces[size_t(i)];
      if (s.type != bsp::SurfaceType::Planar || s.lightmap < 0) continue;
      const glm::dvec3 normal(s.lightmapVecs[2]);
      const glm::dvec3 v0(bsp_.drawVertices[size_t(s.firstVertex)].position);
      if (glm::dot(normal, n) < 0.999 || std::abs(glm::dot(normal, p - v0)) > 0.5) continue;
      for (int32_t k = 0; k + 2 < s.indexCount; k += 3) {
        const auto vertex = [&](int j) {
          return bsp_.drawVertices[size_t(s.firstVertex + bsp_.drawIndices[size_t(s.firstIndex + k + j)])];
        };
        const auto weights = barycentric(p, glm::dvec3(vertex(0).position), glm::dvec3(vertex(1).position), glm::dvec3(vertex(2).position));
        if (!weights) continue;
        const glm::dvec2 lm = glm::dvec2(vertex(0).lightmap) * (*weights)[0] + glm::dvec2(vertex(1).lightmap) * (*weights)[1] +
            glm::dvec2(vertex(2).lightmap) * (*weights)[2];
        out.push_back(sample(s, lm * double(kPage) - 0.5));
      }
    }
    return out;
  }

private:
  static std::optional<glm::dvec3> barycentric(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area = glm::dot(n, n);
    if (area < 1e-12) return std::nullopt;
    const double u = glm::dot(glm::cross(c - b, p - b), n) / area, v = glm::dot(glm::cross(a - c, p - c), n) / area;
    const double w = 1.0 - u - v;
    const double slack = 0.05 / std::sqrt(std::sqrt(area)); // about 0.05 units outside an edge
    if (u < -slack || v < -slack || w < -slack) return std::nullopt;
    return glm::dvec3(u, v, w);
  }

  // The engine's luxel at page texel (x, y), clamped to the page's edge as its texture is, then
  // bilinear between them.
  glm::dvec3 sample(const bsp::Surface& s, const glm::dvec2& texel) const {
    const auto luxel = [&](int x, int y) {
      x = std::clamp(x, 0, kPage - 1);
      y = std::clamp(y, 0, kPage - 1);
      const size_t at = ((size_t(s.lightmap) * kPage + size_t(y)) * kPage + size_t(x)) * 3;
      glm::ivec3 v(bsp_.lightmaps[at] * 2, bsp_.lightmaps[at + 1] * 2, bsp_.lightmaps[at + 2] * 2);
      const int peak = std::max({v.x, v.y, v.z});
      if (peak > 255) v = v * 255 / peak;
      return glm::dvec3(v);
    };
    const double fu = std::floor(texel.x), fv = std::floor(texel.y), wu = texel.x - fu, wv = texel.y - fv;
    const int x = int(fu), y = int(fv);
    return (luxel(x, y) * (1 - wu) + luxel(x + 1, y) * wu) * (1 - wv) + (luxel(x, y + 1) * (1 - wu) + luxel(x + 1, y + 1) * wu) * wv;
  }

  bsp::BspFile bsp_;
};

// Every pixel on a planar surface with a lightmap, from the default camera and two others.
TEST(CompiledView, OpenArenaPixelsShowTheCompiledLightmapPages) {
  if (!std::filesystem::exists(kOpenArenaMaps)) GTEST_SKIP() << kOpenArenaMaps << " not found: install Debian's openarena-data";
  bsp::Pk3Archive pk3(kOpenArenaMaps);
  std::vector<std::string> levels;
  for (const std::string& name : pk3.names())
    if (name.starts_with("maps/") && name.ends_with(".bsp")) levels.push_back(name);
  std::sort(levels.begin(), levels.end());
  levels.resize(std::min(levels.size(), kOpenArenaLevels));
  int judged = 0;
  for (const std::string& level : levels) {
    SCOPED_TRACE(level);
    const std::vector<uint8_t> bytes = *pk3.read(level);
    const Quake3Oracle oracle(bsp::readBspFile(bytes, level));
    ImportOptions options;
    options.textures.load = false; // placeholders: the comparison reads the same texture as the render
    const Scene scene = importScene(kOpenArenaMaps.string() + ":" + level, options);
    Diagnostics diags;
    RenderScene rs = buildRenderScene(scene, RenderSceneOptions{}, diags);
    ASSERT_EQ(showCompiledLightmaps(scene, rs, ""), "");
    const CameraPose start = defaultCameraPose(scene);
    std::vector<CameraPose> cameras{start};
    for (float yaw : {120.0f, 240.0f}) cameras.push_back(CameraPose{start.origin, 20.0f, start.yaw + yaw, 0.0f, "turned"});
    for (const CameraPose& pose : cameras) {
      const Camera camera(pose, kWidth, kHeight);
      const RenderImage image = renderView(rs, pose);
      const auto at = [&](const glm::dvec3& p, const glm::dvec3& n) { return oracle.allAt(p, n); };
      const Comparison r = compareWith(rs, at, 2.0 / 255.0, camera, image);
      std::printf("%s", fmt::format("compiled view {} {}: {}\n", level, formatCameraPose(pose), r.describe()).c_str());
      EXPECT_EQ(r.off, 0u) << formatCameraPose(pose) << ": " << r.describe();
      if (r.bright < kMinBrightPixels) continue;
      EXPECT_GT(compareWith(rs, at, 2.0 / 255.0, camera, image, 1.02).off, r.bright / 2) << "2 % too bright passes";
      ++judged;
    }
  }
  EXPECT_GT(judged, 0);
}

} // namespace
} // namespace bt
