// `--lighting compiled` as a user sees it: every lit oracle level (../shared/oracle/lit/, Quake 1,
// `.lit` files among them) and every level of ../shared/oracle/lit-games/ (Half-Life, Quake 2) is
// imported from its .bsp and rendered from the cameras of the faithful-mode view test; each
// pixel must show, within 1/255 in every channel after the display, the compiled lightmap that
// this test samples itself (lightmap_oracle.h, bilinear over the compiled face's luxels) at the
// point the pixel sees, through the engine's rule written out here again:
//   Quake     luxel = min(255, Σ stored × style >> 8), style 'm' = 264; shown = texture × luxel × 2 / 255
//   Half-Life the same luxel (its light gamma is the identity at its defaults, to a step), × 1 / 255
//   Quake 2   luxel = Σ stored × style ('m' = 1), its hue kept below 255; shown = texture × luxel / 255
// Pixels on sky, unlit liquids, fullbright texels and faces without a compiled lightmap (the
// world's only: brush entities' faces are not sampled) are left out and counted.
#include "importers/import.h"
#include "renderer/cpu/color.h"
#include "renderer/cpu/compiled_lightmaps.h"
#include "renderer/cpu/cpu_renderer.h"
#include "tests/render/lightmap_oracle.h"
#include "tests/render/oracle_levels.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <cstdio>
#include <string_view>

namespace bt {
namespace {

constexpr int kWidth = 96, kHeight = 72;
constexpr double kTolerance = 1.0 / 255.0 + 1e-4; // one step of the 8-bit display, and float noise
// Pixels at least this bright (display 0..1) show a 2 % error as more than a step of 1/255.
constexpr double kBright = 0.3;
constexpr size_t kMinBrightPixels = 50;

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
  return glm::min(glm::floor(sum / 256.0), glm::dvec3(255.0));
}

double displayScale(Engine engine) { return engine == Engine::Quake ? 2.0 / 255.0 : 1.0 / 255.0; }

struct Comparison {
  size_t compared = 0, bright = 0, off = 0, excluded = 0;
  double worst = 0.0;
  std::string describe() const {
    return fmt::format("{} pixels compared ({} bright), {} off by more than 1/255 (worst {:.4f}), {} left out", compared, bright, off,
                       worst, excluded);
  }
};

// The pixels of `image` (1 spp, seed 0) against the compiled lightmaps, shown scaled by `gain`.
Comparison compare(const RenderScene& rs, const test::LightmapOracle& oracle, const StyleTable& styles, const Camera& camera,
                   const RenderImage& image, double gain = 1.0) {
  Comparison r;
  const auto value = [&](const test::CompiledFace& f, int x, int y) { return engineLuxel(styles, oracle, f, x, y); };
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      // The pixel's one sample: the renderer's own jittered ray (cpu_renderer.cpp).
      Rng rng = pixelRng(uint32_t(x), uint32_t(y), 0, 0);
      const glm::vec2 jitter = rng.next2();
      const SurfaceHit hit = traceVisible(rs, camera.ray(float(x) + jitter.x, float(y) + jitter.y));
      if (!hit.found) continue;
      const uint32_t flags = rs.faceFlags[hit.face];
      const glm::dvec3 texture(baseColorAt(rs, hit.face, hit.position));
      if ((flags & kFaceSky) || ((flags & kFaceLiquid) && !rs.world.litwater) ||
          emissiveAt(rs, hit.face, hit.position) != glm::vec3(0.0f)) {
        ++r.excluded;
        continue;
      }
      const std::vector<glm::dvec3> expected = oracle.allAt(glm::dvec3(hit.position), glm::dvec3(hit.normal), value);
      if (expected.empty()) {
        ++r.excluded;
        continue;
      }
      const glm::dvec3 shown = glm::clamp(glm::dvec3(linearToSrgb(image.beauty[size_t(y) * kWidth + x])) * gain, 0.0, 1.0);
      double error = 1e30;
      for (const glm::dvec3& luxel : expected) { // a seam between two compiled faces: either
        const glm::dvec3 want = glm::clamp(texture * luxel * displayScale(styles.engine), 0.0, 1.0);
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

RenderImage renderView(const RenderScene& rs, const CameraPose& pose) {
  RenderSettings settings;
  settings.width = kWidth, settings.height = kHeight, settings.spp = 1, settings.seed = 0;
  return renderCpu(rs, Camera(pose, kWidth, kHeight), settings);
}

Engine engineOf(const Scene& scene) {
  return scene.format == "bsp30" ? Engine::HalfLife : scene.format == "ibsp38" ? Engine::Quake2 : Engine::Quake;
}

// One level: every camera's every pixel; returns how many views had lit pixels to judge by.
int checkLevel(const std::filesystem::path& bsp) {
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

} // namespace
} // namespace bt
