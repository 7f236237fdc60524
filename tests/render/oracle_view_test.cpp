// Faithful mode as a user sees it, against the reference compiler: every level under
// ../shared/oracle/lit/ (ericw-tools `light`, default settings) is rendered from its source .map
// from three cameras, in colour, and each pixel's light is compared with the compiled lightmap
// that this test samples itself at the point the pixel sees, bilinearly over the face's luxels as
// GLQuake and QuakeSpasm filter them. The same lightmaps are also compared luxel by luxel.
//
// What a pixel shows of the light: the renderer's faithful display is srgbToLinear(texture ×
// stored / 128) (lighting/README.md), so stored = 128 × linearToSrgb(beauty) / texture per
// channel, where texture is the base colour at the hit of the pixel's own (jittered) ray.
#include "importers/bsp/bsp_file.h"
#include "importers/import.h"
#include "scene/color.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/lightmap_bake.h"
#include "renderer/view_lightmaps.h"
#include "tests/render/lightmap_oracle.h"
#include "tests/render/oracle_levels.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>

namespace bt {
namespace {

// Below this stored value a relative error says nothing (1 unit of 8 is 12 %): relative to 8.
constexpr double kErrorFloor = 8.0;
// A channel of the texture darker than this tells too little of the light under it.
constexpr float kMinTexture = 24.0f / 255.0f;
constexpr int kWidth = 128, kHeight = 96;
constexpr size_t kMinLitPixels = 200;
constexpr size_t kWholeLevelLuxels = 270000; // e1m1 (260 000) whole, lqdm5 (290 000) by camera

using test::CompiledFace;
using CompiledLightmaps = test::LightmapOracle;

// Pixels (or luxels) where the compiled light is at least kErrorFloor are "lit": the median and
// the share within 5 % are theirs, so that a view mostly in darkness cannot pass on its black
// pixels alone. Darker ones count towards `darkWithin5` when off by at most one step of the byte
// the compiler writes (5 % of them is less than the byte's own rounding).
struct ViewResult {
  size_t compared = 0, within5 = 0, dark = 0, darkWithin5 = 0, skyOrUnlit = 0, noCompiledFace = 0;
  double median = 0.0;
  std::vector<double> errors;

  void add(double error, double compiledPeak) {
    if (compiledPeak < kErrorFloor) {
      ++dark;
      darkWithin5 += error * kErrorFloor <= 1.0; // error is |ours - compiled| / kErrorFloor here
      return;
    }
    errors.push_back(error);
    within5 += error <= 0.05;
  }
  void finish() {
    compared = errors.size();
    if (errors.empty()) return;
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    median = errors[errors.size() / 2];
  }
};

// With BT_ORACLE_VIEW_DIR set, each view is written there as a PPM: ours | the compiler's | the
// error (green within 5 %, red beyond, blue where nothing is compared), to see where they differ.
void writeDebugImage(const std::string& name, const std::vector<glm::vec3>& ours, const std::vector<glm::vec3>& compiled,
                     const std::vector<float>& error) {
  const char* dir = std::getenv("BT_ORACLE_VIEW_DIR");
  if (!dir) return;
  std::ofstream out(std::filesystem::path(dir) / (name + ".ppm"), std::ios::binary);
  out << "P6\n" << 3 * kWidth << " " << kHeight << "\n255\n";
  for (int y = 0; y < kHeight; ++y)
    for (int part = 0; part < 3; ++part)
      for (int x = 0; x < kWidth; ++x) {
        const size_t i = size_t(y) * kWidth + x;
        glm::vec3 c = part == 0 ? ours[i] / 255.0f
            : part == 1         ? compiled[i] / 255.0f
            : error[i] < 0.0f   ? glm::vec3(0, 0, 0.5f)
            : error[i] <= 0.05f ? glm::vec3(0, 0.6f, 0)
                                : glm::vec3(1, 0, 0);
        c = glm::clamp(c, 0.0f, 1.0f);
        out.put(char(c.x * 255.0f)).put(char(c.y * 255.0f)).put(char(c.z * 255.0f));
      }
}

// The pixels of `image` (1 spp, seed 0, from `camera`) against the compiled lightmaps.
ViewResult compareImage(const RenderScene& rs, const CompiledLightmaps& oracle, const Camera& camera, const RenderImage& image,
                        const std::string& name) {
  const uint32_t seed = 0;
  ViewResult r;
  std::vector<glm::vec3> oursImage(size_t(kWidth) * kHeight, glm::vec3(0.0f)), compiledImage = oursImage;
  std::vector<float> errorImage(oursImage.size(), -1.0f);
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      // The pixel's one sample: the renderer's own jittered ray (cpu_renderer.cpp).
      Rng rng = pixelRng(uint32_t(x), uint32_t(y), 0, seed);
      const glm::vec2 jitter = rng.next2();
      const SurfaceHit hit = traceVisible(rs, camera.ray(float(x) + jitter.x, float(y) + jitter.y));
      if (!hit.found) continue;
      const uint32_t flags = rs.faceFlags[hit.face];
      const glm::vec3 texture = glm::vec3(baseColorAt(rs, hit.face, hit.position));
      const glm::vec3 emissive = emissiveAt(rs, hit.face, hit.position);
      if ((flags & kFaceSky) || ((flags & kFaceLiquid) && !rs.world.litwater) || emissive != glm::vec3(0.0f)) {
        ++r.skyOrUnlit;
        continue;
      }
      const std::optional<glm::dvec3> compiled = oracle.at(glm::dvec3(hit.position), glm::dvec3(hit.normal));
      if (!compiled) {
        ++r.noCompiledFace;
        continue;
      }
      const glm::vec3 shown = linearToSrgb(image.beauty[size_t(y) * kWidth + x]);
      double error = 0.0;
      bool any = false;
      for (int c = 0; c < 3; ++c) {
        if (texture[c] < kMinTexture) continue;
        const double ours = 128.0 * shown[c] / texture[c];
        error = std::max(error, std::abs(ours - (*compiled)[c]) / std::max((*compiled)[c], kErrorFloor));
        any = true;
      }
      if (!any) continue;
      const size_t i = size_t(y) * kWidth + x;
      oursImage[i] = 128.0f * shown / glm::max(texture, glm::vec3(kMinTexture));
      compiledImage[i] = glm::vec3(*compiled);
      errorImage[i] = float(error);
      r.add(error, std::max({(*compiled).x, (*compiled).y, (*compiled).z}));
    }
  writeDebugImage(name, oursImage, compiledImage, errorImage);
  r.finish();
  return r;
}

// What the user sees from `pose`: the faithful image (1 spp; the baked luxels make it exact).
RenderImage renderView(const RenderScene& rs, const CameraPose& pose) {
  RenderSettings settings;
  settings.width = kWidth, settings.height = kHeight, settings.spp = 1, settings.seed = 0;
  return renderCpu(rs, Camera(pose, kWidth, kHeight), settings);
}

// Every luxel of every lit compiled face against what we show at its centre: our luxel at the
// same place of the texture's grid (bilinear weights 0 there), from the face the point lies on.
ViewResult compareLuxels(const RenderScene& rs, const CompiledLightmaps& oracle) {
  ViewResult r;
  for (const CompiledFace& f : oracle.faces())
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const glm::dvec3 p = oracle.luxelPoint(f, x, y);
        const glm::vec3 n(f.normal);
        const SurfaceHit hit = traceVisible(rs, Ray{glm::vec3(p) + n * 0.5f, 0.0f, -n, 1.0f});
        if (!hit.found || glm::dot(hit.normal, n) < 0.999f || !rs.lightmaps.baked(hit.face)) {
          ++r.noCompiledFace; // the centre lies off the face (an edge luxel) or on nothing we bake
          continue;
        }
        const std::optional<glm::vec3> ours =
            lightmapValue(rs.lightmaps, hit.face, textureCoordinates(gpuFace(rs, hit.face), glm::vec3(p)));
        const glm::dvec3 compiled = oracle.luxel(f, x, y);
        double error = 0.0;
        for (int c = 0; c < 3; ++c) error = std::max(error, std::abs((*ours)[c] - compiled[c]) / std::max(compiled[c], kErrorFloor));
        r.add(error, std::max({compiled.x, compiled.y, compiled.z}));
      }
  r.finish();
  return r;
}

// The bar: median error at most 2 %, at least 90 % of pixels (or luxels) within 5 %.
struct Bar {
  double median = 0.02;
  double within5 = 0.90;
};
// Judged on the lit pixels; a view with none (all its light below the floor) only needs some dark
// ones to compare. The dark pixels' agreement is reported, not judged: a byte's rounding there is
// more than 5 %, and the bar is about the light a user sees.
bool meets(const ViewResult& r, const Bar& bar) {
  if (r.compared == 0) return r.dark > 0;
  return r.median <= bar.median && double(r.within5) >= bar.within5 * double(r.compared);
}

// Levels below the bar today, each held at what it reaches so that it cannot get worse unseen;
// the faithful-mode issue (14) stays open until this table is empty.
//   testsurfacelight: its _surface points stand on faces split as a tree grown on that surface
//     alone would split them, not on the compiler's own faces (lighting/README.md): qbsp's tree
//     is grown over the whole level, so planes of brushes far from a surface cut it too.
//   lqdm5: its sun's penumbra. The compiler's 64 directions are not noise: light.cc SetupSun
//     takes the sun's own direction, then 63 jittered by glibc rand() from its default seed (no
//     srand; nothing draws before it here), azimuth and elevation each uniform in ±penumbra, its
//     rejection test comparing radians² with degrees² and so never rejecting. Those directions
//     in the luxel passes (tried on the CPU alone) give luxels 90.1 % and views 89.6 / 87.0 /
//     97.9 % within 5 % (from 84.8 / 82.3 / 85.9 / 94.9): the GL bake needs the same table
//     (GlBake checks both agree on a penumbra), and the rest of the gap is still unexplained.
const std::map<std::string, Bar>& knownGaps() {
  static const std::map<std::string, Bar> gaps = {
      {"ericw-tools_testmaps_deprecated_testsurfacelight", {0.13, 0.16}},
      {"librequake_lq1_maps_src_dm_lqdm5", {0.02, 0.82}},
  };
  return gaps;
}

std::string describe(const ViewResult& r) {
  return fmt::format("{} lit, median {:.2f} %, within 5 %: {:.1f} %; {} dark, within: {:.1f} % ({} sky/unlit, {} on no compiled face)",
                     r.compared, 100.0 * r.median, 100.0 * double(r.within5) / double(std::max<size_t>(r.compared, 1)), r.dark,
                     100.0 * double(r.darkWithin5) / double(std::max<size_t>(r.dark, 1)), r.skyOrUnlit, r.noCompiledFace);
}

using test::oracleCameras;

class OracleView : public ::testing::TestWithParam<const char*> {};

TEST_P(OracleView, FaithfulPixelsMatchTheCompiledLightmaps) {
  BT_REQUIRE_SHARED(shared);
  const std::string bspName = std::string("maps_") + GetParam() + ".bsp";
  const std::filesystem::path map = test::oracleSourceMap(shared, bspName);
  ASSERT_FALSE(map.empty()) << "no manifest entry for " << bspName;
  const CompiledLightmaps oracle(shared / "oracle" / "lit" / bspName);
  const Scene scene = importScene(map.string(), ImportOptions{});
  RenderSceneOptions options;
  options.lights.styleZeroOnly = true;
  Diagnostics diags;
  RenderScene rs = buildRenderScene(scene, options, diags);
  const std::vector<CameraPose> cameras = oracleCameras(scene, rs, oracle);
  int judged = 0;
  // Every face of a level of up to kWholeLevelLuxels luxels; on a larger one (lqdm5) the faces
  // the cameras see, as `render` bakes them.
  rs.lightmaps = layoutLightmaps(rs);
  if (rs.lightmaps.luxels.size() > kWholeLevelLuxels) {
    std::vector<uint32_t> seen;
    for (const CameraPose& pose : cameras)
      for (uint32_t f : facesSeen(rs, Camera(pose, kWidth, kHeight), kWidth, kHeight)) seen.push_back(f);
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    rs.lightmaps = layoutLightmaps(rs, seen);
  }
  bakeLightmaps(rs, rs.lightmaps);
  ASSERT_FALSE(rs.lightmaps.empty());

  if (oracle.faces().empty()) {
    // The compiler lit nothing (q1_light_invalid_delay: its one light has an unknown delay):
    // neither do we, in any luxel or pixel.
    for (uint32_t luxel : rs.lightmaps.luxels) EXPECT_EQ(unpackLuxel(luxel), glm::vec3(0.0f));
    for (const glm::vec3& b : renderView(rs, cameras.front()).beauty) EXPECT_EQ(b, glm::vec3(0.0f));
    return;
  }

  const auto gap = knownGaps().find(GetParam());
  const Bar bar = gap == knownGaps().end() ? Bar{} : gap->second;
  const ViewResult luxels = compareLuxels(rs, oracle);
  std::printf("%s", fmt::format("oracle luxels {}: {}\n", GetParam(), describe(luxels)).c_str());
  EXPECT_TRUE(meets(luxels, bar)) << describe(luxels);

  for (size_t c = 0; c < cameras.size(); ++c) {
    const CameraPose& pose = cameras[c];
    const RenderImage image = renderView(rs, pose);
    const Camera camera(pose, kWidth, kHeight);
    const ViewResult r = compareImage(rs, oracle, camera, image, fmt::format("{}-{}", GetParam(), c));
    std::printf("%s", fmt::format("oracle view {} {}: {}\n", GetParam(), formatCameraPose(pose), describe(r)).c_str());
    EXPECT_TRUE(meets(r, bar)) << formatCameraPose(pose) << ": " << describe(r);
    // The test can fail: the same pixels with our light 5 % brighter miss the bar wherever the
    // view has lit pixels to judge by.
    if (gap != knownGaps().end() || r.compared < kMinLitPixels) continue;
    RenderImage brighter = image;
    for (glm::vec3& b : brighter.beauty) b = srgbToLinear(linearToSrgb(b) * 1.05f);
    const ViewResult off = compareImage(rs, oracle, camera, brighter, fmt::format("{}-{}-brighter", GetParam(), c));
    EXPECT_FALSE(meets(off, bar)) << "5 % too bright still passes from " << formatCameraPose(pose) << ": " << describe(off);
    ++judged;
  }
  // A level whose compiled light is all dark has no lit pixel to judge a 5 % error by.
  if (gap == knownGaps().end() && luxels.compared > 0) EXPECT_GT(judged, 0) << "no view of a lit face";
}

// No level under oracle/lit/ is left out of kLitLevels unseen.
TEST(OracleView, EveryLitOracleLevelIsListed) {
  BT_REQUIRE_SHARED(shared);
  for (const auto& entry : std::filesystem::directory_iterator(shared / "oracle" / "lit")) {
    const std::string file = entry.path().filename().string();
    if (entry.path().extension() != ".bsp" || !file.starts_with("maps_")) continue;
    const std::string name = file.substr(5, file.size() - 9);
    EXPECT_TRUE(std::find(std::begin(test::kLitLevels), std::end(test::kLitLevels), name) != std::end(test::kLitLevels)) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Lit, OracleView, ::testing::ValuesIn(test::kLitLevels), [](const auto& info) {
  std::string n = info.param;
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
});

} // namespace
} // namespace bt
