// Faithful mode against the reference compiler: ../shared/oracle/lit/*.bsp were lit by
// ericw-tools `light` (default settings, no bounce) from the .map sources in ../shared/maps.
// We import the source .map, evaluate faithful direct light at every luxel centre of every
// lit world face of the compiled .bsp, and compare with the stored style-0 lightmap.
//
// Luxels as the compiler places them: the face's texture-space extents, floor/ceil to 16
// texels, one luxel every 16 texels from the floor, (extent / 16 + 1) per axis; the stored
// byte is (light sum x _range) clamped to 255, the brightest of r, g, b for coloured light.
#include "importers/bsp/bsp_file.h"
#include "importers/import.h"
#include "renderer/cpu/faithful.h"
#include "renderer/cpu/integrator.h"
#include "tests/test_data.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>

namespace bt {
namespace {

struct OracleResult {
  size_t luxels = 0;
  size_t faces = 0;
  double medianError = 0.0;    // |ours - compiler| / max(compiler, kErrorFloor)
  double meanAbsError = 0.0;   // in lightmap units (0..255)
  double meanSignedError = 0.0; // ours - compiler: > 0 too bright
  size_t within5 = 0;          // luxels within 5 %
};

// Below this stored value a relative error says nothing (1 unit of 8 is 12 %): relative to 8.
constexpr double kErrorFloor = 8.0;
// Soft lights (penumbra, domes, deviance) are averaged over this many samples per luxel.
constexpr int kSamplesPerLuxel = 4;

OracleResult compareWithCompiler(const std::filesystem::path& bspPath, const std::filesystem::path& mapPath) {
  const bsp::BspFile bsp = bsp::readBspFile(bspPath);
  ImportOptions options;
  options.textures.load = false; // light values do not depend on texture pixels
  const Scene scene = importScene(mapPath.string(), options);
  RenderSceneOptions renderOptions;
  renderOptions.lights.styleZeroOnly = true;
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, renderOptions, diags);

  std::vector<double> errors;
  double absSum = 0.0, signedSum = 0.0;
  OracleResult result;
  if (bsp.models.empty()) return result;
  const bsp::Model& world = bsp.models[0];
  for (int32_t fi = world.firstFace; fi < world.firstFace + world.faceCount; ++fi) {
    const bsp::Face& face = bsp.faces[size_t(fi)];
    if (face.lightOffset < 0 || face.styles[0] != 0) continue; // unlit (sky, liquids) or styled only
    const bsp::TexInfo& tex = bsp.texinfo[size_t(face.texinfo)];
    const std::vector<glm::dvec3> verts = bsp.faceVertices(size_t(fi));
    double mins[2] = {1e30, 1e30}, maxs[2] = {-1e30, -1e30};
    for (const glm::dvec3& v : verts)
      for (int a = 0; a < 2; ++a) {
        const double st = v.x * tex.vecs[a][0] + v.y * tex.vecs[a][1] + v.z * tex.vecs[a][2] + tex.vecs[a][3];
        mins[a] = std::min(mins[a], st);
        maxs[a] = std::max(maxs[a], st);
      }
    int lo[2], size[2];
    for (int a = 0; a < 2; ++a) {
      lo[a] = int(std::floor(mins[a] / 16.0));
      size[a] = int(std::ceil(maxs[a] / 16.0)) - lo[a] + 1;
    }
    const size_t count = size_t(size[0]) * size_t(size[1]);
    // Every lit face's luxels must lie in the lighting lump; none is skipped silently.
    EXPECT_LE(size_t(face.lightOffset) + count, bsp.lighting.size()) << bspPath << " face " << fi;
    if (size_t(face.lightOffset) + count > bsp.lighting.size()) continue;

    const bsp::BspPlane& plane = bsp.planes[size_t(face.plane)];
    glm::dvec3 normal = glm::dvec3(plane.normal);
    double dist = plane.dist;
    if (face.side) normal = -normal, dist = -dist;
    // Luxel (s, t) -> the point on the face plane with those texture coordinates.
    const glm::dmat3 m = glm::transpose(glm::dmat3(glm::dvec3(tex.vecs[0][0], tex.vecs[0][1], tex.vecs[0][2]),
                                                   glm::dvec3(tex.vecs[1][0], tex.vecs[1][1], tex.vecs[1][2]), normal));
    const glm::dmat3 inv = glm::inverse(m);
    // A face whose texture carries a radiosity _surface template is lit at least at its value.
    glm::vec3 faceMinlight(0.0f);
    if (auto material = scene.findMaterial(tex.texture); material && *material < rs.surfaceLights.size())
      faceMinlight = faithful::surfaceFaceMinlight(rs.surfaceLights[*material]);
    // A lit liquid face takes light from both sides, as the renderer lights kFaceLiquid faces.
    const bool twoSided = classifyTexture(tex.texture, std::nullopt) & kFaceLiquid;
    ++result.faces;
    for (int t = 0; t < size[1]; ++t)
      for (int s = 0; s < size[0]; ++s) {
        const glm::dvec3 rhs((lo[0] + s) * 16.0 - tex.vecs[0][3], (lo[1] + t) * 16.0 - tex.vecs[1][3], dist);
        const glm::vec3 p = glm::vec3(inv * rhs);
        glm::vec3 sum(0.0f);
        for (int k = 0; k < kSamplesPerLuxel; ++k) {
          Rng rng = pixelRng(uint32_t(fi), uint32_t(t * size[0] + s), uint32_t(k), 1);
          sum += faithfulLightAt(rs, p, glm::vec3(normal), rng, twoSided);
        }
        glm::vec3 stored = glm::max(sum / float(kSamplesPerLuxel), faceMinlight) * rs.world.range;
        const float peak = std::max({stored.x, stored.y, stored.z});
        if (peak > 255.0f) stored *= 255.0f / peak;
        // The mono lightmap holds the brightest channel of the coloured one (.lit files agree).
        // ... written to a byte by C's float-to-integer conversion, which truncates (WriteSingleLightmap).
        const double ours = std::floor(std::clamp(double(std::max({stored.x, stored.y, stored.z})), 0.0, 255.0));
        const double compiler = bsp.lighting[size_t(face.lightOffset) + size_t(t) * size[0] + size_t(s)];
        const double error = std::abs(ours - compiler) / std::max(compiler, kErrorFloor);
        errors.push_back(error);
        absSum += std::abs(ours - compiler);
        signedSum += ours - compiler;
        result.within5 += error <= 0.05;
      }
  }
  result.luxels = errors.size();
  if (!errors.empty()) {
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    result.medianError = errors[errors.size() / 2];
    result.meanAbsError = absSum / double(errors.size());
    result.meanSignedError = signedSum / double(errors.size());
  }
  return result;
}

// The .map each lit .bsp was compiled from (oracle/manifest.json).
std::filesystem::path sourceMap(const std::filesystem::path& shared, const std::string& bspName) {
  std::ifstream in(shared / "oracle" / "manifest.json");
  const nlohmann::json manifest = nlohmann::json::parse(in);
  for (const auto& entry : manifest)
    if (entry.value("bsp", "") == bspName) return shared / entry.value("map", "");
  return {};
}

// The lit oracle level maps_<name>.bsp against faithful mode on its source .map, with the figures
// printed to the test log (they are what the closing note reports); nullopt, with the failure
// recorded, when the level or its manifest entry is missing.
std::optional<OracleResult> compareLitLevel(const std::filesystem::path& shared, const std::string& name) {
  const std::string bspName = "maps_" + name + ".bsp";
  const std::filesystem::path bspPath = shared / "oracle" / "lit" / bspName;
  if (!std::filesystem::exists(bspPath)) {
    ADD_FAILURE() << bspPath << " does not exist";
    return std::nullopt;
  }
  const std::filesystem::path map = sourceMap(shared, bspName);
  if (map.empty()) {
    ADD_FAILURE() << "no manifest entry for " << bspName;
    return std::nullopt;
  }
  const OracleResult r = compareWithCompiler(bspPath, map);
  std::printf("%s", fmt::format("oracle {}: {} faces, {} luxels, median error {:.2f} %, within 5 %: {:.1f} %, mean |diff| {:.2f}/255, mean diff {:+.2f}\n",
                                name, r.faces, r.luxels, 100.0 * r.medianError, 100.0 * double(r.within5) / double(std::max<size_t>(r.luxels, 1)),
                                r.meanAbsError, r.meanSignedError).c_str());
  return r;
}

class OracleLightmaps : public ::testing::TestWithParam<const char*> {};

TEST_P(OracleLightmaps, FaithfulDirectLightMatchesCompiler) {
  BT_REQUIRE_SHARED(shared);
  const std::optional<OracleResult> result = compareLitLevel(shared, GetParam());
  ASSERT_TRUE(result);
  const OracleResult& r = *result;
  ASSERT_GT(r.luxels, 0u);
  EXPECT_LE(r.medianError, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Lit, OracleLightmaps,
                         // Not here: deprecated_nobounce and deprecated_bouncecolorscaletest set worldspawn
                         // _bounce 1 (the compiler bounced, this compares direct light; the latter's lightmap
                         // offsets also do not fit the lump as this test sizes faces, so no face is compared);
                         // q1_light_invalid_delay compiled with no lit face; deprecated_dirttest2 needs dirt
                         // (ambient occlusion, not modelled: median 5.5 %); lqdm5: too slow for the suite.
                         // testsurfacelight (last) has the thinnest margin: 4.8 % (its _surface lights
                         // stand on faces split as qbsp's tree would split them, not on the compiler's
                         // own faces; with those its median is 0.00 %).
                         ::testing::Values("ericw-tools_testmaps_deprecated_falloff",
                                           "ericw-tools_testmaps_deprecated_light_near_wall",
                                           "ericw-tools_testmaps_deprecated_suntest",
                                           "ericw-tools_testmaps_deprecated_testminlight",
                                           "ericw-tools_testmaps_deprecated_testlightonface",
                                           "ericw-tools_testmaps_q1_surflight_minlight",
                                           "ericw-tools_testmaps_q1_light_bounce_litwater",
                                           "ericw-tools_testmaps_q1_light_bounce_noshadow",
                                           "ericw-tools_testmaps_deprecated_dirttest",
                                           "ericw-tools_testmaps_q1_light_hlform",
                                           "ericw-tools_testmaps_q1_light_skip_shadow",
                                           "ericw-tools_testmaps_q1_light_suntexture",
                                           "ericw-tools_testmaps_q1_light_surflight_group",
                                           "ericw-tools_testmaps_q1_light_switchableshadow_selfshadows",
                                           "ericw-tools_testmaps_q1_litwater_opt_in",
                                           "ericw-tools_testmaps_q1_light_black",
                                           "ericw-tools_testmaps_q1_lightignore",
                                           "ericw-tools_testmaps_q1_light_switchableshadow_target",
                                           "ericw-tools_testmaps_q1_sunlight",
                                           "ericw-tools_testmaps_q1_litwater",
                                           "ericw-tools_testmaps_q1_minlight_nobounce",
                                           "quake_map_source_e1m1",
                                           "ericw-tools_testmaps_deprecated_testsurfacelight"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

} // namespace
} // namespace bt
