// The same level imported from its .map and from the .bsp qbsp compiled from it gives the same
// picture: albedo and normal AOVs rendered by the CPU backend from the same camera agree on at
// least 99 % of the pixels that can be compared.
//
// Which pixels are compared. The compiler removes faces: sides buried in other brushes or facing
// the void, and the hidden classes (skip, hint, clip, ...). The .map render skips the hidden
// classes itself (renderer/cpu/README.md), so both renders already pass through them. Sides that
// qbsp removed for lying outside the level or against another brush come back from the .bsp
// with a generated hidden name (importers/bsp/brushes.h: "skip", "*waterskip", ..., and
// "e1u1/skip" for Quake 2); where the .map shows such a side, the .bsp cannot. So a pixel is
// excluded when the .bsp render with hidden faces drawn shows a generated hidden side first
// (for instance the outer walls of a level seen from a camera outside it), and when neither
// render sees anything. Every other pixel counts: it agrees when both see a face whose albedo,
// as the 8-bit sRGB value a PNG would hold, is within kAlbedoTolerance levels per channel and
// whose normal is within kNormalToleranceDegrees.
//
// Textures. qbsp -notex keeps only names, so the .bsp's textures are looked up exactly as the
// .map's are (its WADs and texture folders, relative to the .map): the oracle keeps the .bsp
// files in a folder of their own, not beside their sources as a mapper's would be.
#include "importers/bsp/bsp_import.h"
#include "importers/import.h"
#include "importers/textures/textures.h"
#include "renderer/cpu/color.h"
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/cpu/render_scene.h"
#include "tests/test_data.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace bt {
namespace {

constexpr int kWidth = 160;
constexpr int kHeight = 120;
// Texels are filtered bilinearly, and qbsp stores planes and texture axes in single precision:
// a hit seen at a grazing angle lands up to a tenth of a texel away from the .map's, which
// moves the colour at a texel edge by a few levels (deprecated/offgrid_after.map: 18 pixels of
// 19200 differ by more than 8).
constexpr float kAlbedoTolerance = 8.0f; // of 255, sRGB
constexpr float kNormalToleranceDegrees = 1.0f;
constexpr double kRequiredAgreement = 0.99;

// Levels whose pictures differ for a reason that is not the .bsp import's to fix. Each is still
// rendered and must still differ: when one agrees, it is taken off this list.
struct KnownDifference {
  std::string_view bsp;
  std::string_view reason;
};
constexpr KnownDifference kKnownDifferences[] = {
    {"maps_ericw-tools_testmaps_q2_chop_order_1.bsp",
     "coplanar faces of overlapping brushes, where _chop_order makes qbsp keep the earlier brush's "
     "face; the tracer's equal-t rule (bvh/trace_scene.h) keeps the later brush's, qbsp's default"},
    {"maps_ericw-tools_testmaps_q2_csg_water_water_current90.bsp",
     "two water brushes share a side; rays landing on the shared edge hit both at the same t and the "
     "tracer's equal-t rule picks by brush order"},
};

const KnownDifference* knownDifference(std::string_view bsp) {
  for (const KnownDifference& k : kKnownDifferences)
    if (k.bsp == bsp) return &k;
  return nullptr;
}

bool isGeneratedHiddenSide(std::string_view texture) {
  return texture == "skip" || texture == "*waterskip" || texture == "*slimeskip" || texture == "*lavaskip" ||
         texture == "skyskip" || texture == "e1u1/skip";
}

// The .bsp's scene with its textures found where its source .map's are.
Scene importBspBesideMap(const std::filesystem::path& bspPath, const std::filesystem::path& mapPath) {
  const bsp::BspFile file = bsp::readBspFile(bspPath);
  const TextureSearch search;
  return bsp::sceneFromBsp(file, [&](Scene& scene) {
    scene.sourcePath = mapPath.string(); // where loadMaterials resolves relative WADs and folders
    loadMaterials(scene, search);
    scene.sourcePath = bspPath.string();
  });
}

struct Agreement {
  size_t compared = 0, agreeing = 0, excluded = 0;
  size_t albedoOnly = 0, normalOnly = 0, coverage = 0; // kinds of disagreement
  double fraction() const { return compared ? double(agreeing) / double(compared) : 1.0; }
};

Agreement compareImages(const RenderImage& fromMap, const RenderImage& fromBsp, const RenderImage& bspWithHidden,
                        const Scene& bspScene) {
  const float minCos = std::cos(glm::radians(kNormalToleranceDegrees));
  Agreement a;
  for (size_t i = 0; i < fromMap.face.size(); ++i) {
    const uint32_t shown = bspWithHidden.face[i];
    if ((shown && isGeneratedHiddenSide(bspScene.faces[shown - 1].texture)) || (!fromMap.face[i] && !fromBsp.face[i])) {
      ++a.excluded;
      continue;
    }
    ++a.compared;
    if (!fromMap.face[i] || !fromBsp.face[i]) {
      ++a.coverage;
      continue;
    }
    const glm::vec3 d = glm::abs(linearToSrgb(fromMap.albedo[i]) - linearToSrgb(fromBsp.albedo[i])) * 255.0f;
    const bool albedo = std::max({d.x, d.y, d.z}) <= kAlbedoTolerance;
    const bool normal = glm::dot(fromMap.normal[i], fromBsp.normal[i]) >= minCos;
    if (albedo && normal) ++a.agreeing;
    else if (normal) ++a.albedoOnly;
    else if (albedo) ++a.normalOnly;
    else ++a.coverage;
  }
  return a;
}

RenderImage renderAovs(const Scene& scene, const CameraPose& pose, bool showHidden) {
  RenderSceneOptions options;
  options.showHidden = showHidden;
  Diagnostics diagnostics;
  const RenderScene rs = buildRenderScene(scene, options, diagnostics);
  return renderAovsCpu(rs, Camera(pose, kWidth, kHeight), kWidth, kHeight);
}

// Every oracle .bsp against its .map, from the .map's default camera (the .bsp has the same
// entities, so the same camera).
TEST(BspImage, MapAndBspRenderTheSameAlbedoAndNormals) {
  BT_REQUIRE_SHARED(shared);
  std::ifstream in(shared / "oracle" / "manifest.json");
  struct Result {
    std::string name;
    Agreement agreement;
  };
  std::vector<Result> results;
  for (const auto& entry : nlohmann::json::parse(in)) {
    const auto bspPath = shared / "oracle" / entry.at("bsp").get<std::string>();
    const auto mapPath = shared / entry.at("map").get<std::string>();
    SCOPED_TRACE(bspPath.string());
    const Scene fromMap = importScene(mapPath.string(), ImportOptions{});
    const Scene fromBsp = importBspBesideMap(bspPath, mapPath);
    const CameraPose pose = defaultCameraPose(fromMap);
    const Agreement a = compareImages(renderAovs(fromMap, pose, false), renderAovs(fromBsp, pose, false),
                                      renderAovs(fromBsp, pose, true), fromBsp);
    const std::string name = bspPath.filename().string();
    if (const KnownDifference* known = knownDifference(name))
      EXPECT_LT(a.fraction(), kRequiredAgreement) << "now agrees: take it off kKnownDifferences (" << known->reason << ")";
    else
      EXPECT_GE(a.fraction(), kRequiredAgreement)
          << a.agreeing << " of " << a.compared << " pixels agree; differing albedo " << a.albedoOnly << ", normal "
          << a.normalOnly << ", face or none " << a.coverage;
    results.push_back({name, a});
  }
  EXPECT_GE(results.size(), 229u);

  std::sort(results.begin(), results.end(),
            [](const Result& x, const Result& y) { return x.agreement.fraction() < y.agreement.fraction(); });
  size_t compared = 0, agreeing = 0, nothingToCompare = 0;
  for (const Result& r : results) {
    compared += r.agreement.compared;
    agreeing += r.agreement.agreeing;
    nothingToCompare += r.agreement.compared == 0;
  }
  // Every level, worst first: agreeing share of the compared pixels, how many were compared and
  // excluded, and what differed.
  for (const Result& r : results) {
    const Agreement& a = r.agreement;
    std::printf("  %6.2f %% of %5zu (excluded %5zu; albedo %4zu, normal %4zu, face or none %4zu)  %s%s\n",
                100.0 * a.fraction(), a.compared, a.excluded, a.albedoOnly, a.normalOnly, a.coverage, r.name.c_str(),
                knownDifference(r.name) ? " (known difference)" : "");
  }
  std::printf("%zu levels, %zu pixels compared, %.3f %% agree; %zu levels show nothing comparable from their "
              "camera\n",
              results.size(), compared, 100.0 * double(agreeing) / double(compared), nothingToCompare);
}

} // namespace
} // namespace bt
