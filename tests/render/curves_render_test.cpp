// Quake 3 curves as a camera sees them: Unvanquished's plat23.map (patchDef2) and two OpenArena
// levels (IBSP 46 patches) rendered from cameras that look at curves. Where the curves, tessellated
// far finer than the engine does, show, the engine's tessellation shows no hole (no ray escapes
// the level there) and the albedo AOV is the same within the chords' deviation.
#include "importers/import.h"
#include "renderer/cpu/cpu_renderer.h"
#include "lighting/render_scene.h"
#include "tests/test_data.h"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

namespace bt {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 128, kHeight = 96;
constexpr double kReferenceError = 0.25; // units; the engine's is 4 (r_subdivisions)

RenderScene prepare(const Scene& scene) {
  Diagnostics diagnostics;
  RenderSceneOptions options;
  options.bounceLights = false;
  return buildRenderScene(scene, options, diagnostics);
}

bool onMesh(const Scene& scene, uint32_t pixelFace) {
  return pixelFace > 0 && scene.faces[pixelFace - 1].brush == kNoBrush;
}

// The mesh a pixel's face (face AOV: index + 1) belongs to; both tessellations have the same meshes.
size_t meshOf(const Scene& scene, uint32_t pixelFace) {
  const auto it =
      std::upper_bound(scene.meshes.begin(), scene.meshes.end(), pixelFace - 1, [](uint32_t f, const Mesh& m) { return f < m.firstFace; });
  return size_t(it - scene.meshes.begin()) - 1;
}

CameraPose lookAt(const glm::vec3& eye, const glm::vec3& target) {
  const glm::vec3 f = glm::normalize(target - eye);
  return CameraPose{eye, -glm::degrees(std::asin(std::clamp(f.z, -1.0f, 1.0f))), glm::degrees(std::atan2(f.y, f.x)), 0.0f, "test"};
}

// Whether nothing lies within 16 units of p along the axes: a camera there sees the level, not
// a wall against its eye (whose tessellations would differ most).
bool clearAround(const RenderScene& rs, const glm::vec3& p) {
  for (int a = 0; a < 3; ++a)
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 d(0.0f);
      d[a] = sign;
      if (rs.tracer.occluded(Ray{p, 0.0f, d, 16.0f})) return false;
    }
  return true;
}

// Cameras 160 units in front of (or behind) the middle triangle of the largest curves, out of
// every brush and clear of walls, that see that curve's middle first.
std::vector<CameraPose> camerasSeeingCurves(const Scene& scene, const RenderScene& rs, size_t count) {
  std::vector<uint32_t> order(scene.meshes.size());
  std::iota(order.begin(), order.end(), 0u);
  auto area = [&](uint32_t m) { return scene.meshes[m].bounds.surfaceArea(); };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return area(a) > area(b); });
  std::vector<CameraPose> poses;
  for (uint32_t m : order) {
    const Mesh& mesh = scene.meshes[m];
    if (mesh.kind != MeshKind::Curve || (rs.faceFlags[mesh.firstFace] & kFaceHidden)) continue;
    const Face& middle = scene.faces[mesh.firstFace + (mesh.faceCount / 4) * 2];
    const glm::vec3 centre((middle.winding[0] + middle.winding[1] + middle.winding[2]) / 3.0);
    for (float side : {1.0f, -1.0f}) {
      const glm::vec3 eye = centre + glm::vec3(middle.plane.normal) * (160.0f * side);
      if (rs.tracer.inside(
              eye, [](uint32_t) { return true; }, true))
        continue;
      const std::optional<Hit> hit = rs.tracer.closestHit(Ray{eye, 0.0f, centre - eye, 1.01f});
      if (!hit || hit->t < 0.95f || hit->face < mesh.firstFace || hit->face >= mesh.firstFace + mesh.faceCount) continue;
      if (!clearAround(rs, eye)) continue;
      poses.push_back(lookAt(eye, centre));
      break;
    }
    if (poses.size() == count) break;
  }
  return poses;
}

// How far a pixel's albedo is from the reference's around it (5x5 pixels): the engine's chords
// lie up to 4 units off the curve and its st are interpolated along them, so a texel lands a
// pixel or two from where the finer tessellation puts it (at 160 units a pixel is 2.5 units).
float albedoDistance(const RenderImage& got, const RenderImage& want, int x, int y) {
  float best = 1e30f;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) {
      const int nx = std::clamp(x + dx, 0, kWidth - 1), ny = std::clamp(y + dy, 0, kHeight - 1);
      const glm::vec3 d = glm::abs(got.albedo[size_t(y * kWidth + x)] - want.albedo[size_t(ny * kWidth + nx)]);
      best = std::min(best, std::max({d.r, d.g, d.b}));
    }
  return best;
}

// The level as the engine tessellates it against a much finer tessellation, from two cameras.
void expectCurvesAsTheReference(const std::string& level, ImportOptions options) {
  const Scene coarse = importScene(level, options);
  options.curveMaxError = kReferenceError;
  const Scene fine = importScene(level, options);
  ASSERT_FALSE(coarse.meshes.empty()) << level;
  size_t coarseTriangles = 0, fineTriangles = 0;
  for (const Mesh& m : coarse.meshes) coarseTriangles += m.faceCount / 2;
  for (const Mesh& m : fine.meshes) fineTriangles += m.faceCount / 2;
  EXPECT_GT(fineTriangles, coarseTriangles) << level;
  const RenderScene coarseRs = prepare(coarse), fineRs = prepare(fine);
  const std::vector<CameraPose> poses = camerasSeeingCurves(fine, fineRs, 2);
  ASSERT_EQ(poses.size(), 2u) << level << ": no camera sees its curves";
  for (const CameraPose& pose : poses) {
    const Camera camera(pose, kWidth, kHeight);
    const RenderImage got = renderAovsCpu(coarseRs, camera, kWidth, kHeight);
    const RenderImage want = renderAovsCpu(fineRs, camera, kWidth, kHeight);
    size_t curvePixels = 0, escaped = 0, shownAsCurve = 0, offColour = 0;
    double difference = 0.0;
    for (size_t i = 0; i < want.face.size(); ++i) {
      if (!onMesh(fine, want.face[i])) continue;
      ++curvePixels;
      escaped += got.face[i] == 0;
      // The same curve, where the finer one is: the chords lie within 4 units of it.
      shownAsCurve += onMesh(coarse, got.face[i]) && meshOf(coarse, got.face[i]) == meshOf(fine, want.face[i]) &&
          std::abs(got.depth[i] - want.depth[i]) < 8.0f;
      const float distance = albedoDistance(got, want, int(i % kWidth), int(i / kWidth));
      difference += distance;
      offColour += distance > 0.1f;
    }
    const std::string where =
        level + " from " + std::to_string(pose.origin.x) + " " + std::to_string(pose.origin.y) + " " + std::to_string(pose.origin.z);
    ASSERT_GT(curvePixels, size_t(kWidth * kHeight / 25)) << where;
    EXPECT_EQ(escaped, 0u) << where;
    // At the silhouettes the chords cut inside the curve: pixels there show what is behind.
    EXPECT_GT(shownAsCurve, curvePixels * 90 / 100) << where;
    EXPECT_LT(offColour, curvePixels * 3 / 100) << where;
    EXPECT_LT(difference / double(curvePixels), 0.02) << where;
  }
}

TEST(Curves, Plat23MapMatchesAFinerTessellation) {
  BT_REQUIRE_SHARED(shared);
  expectCurvesAsTheReference((shared / "maps/unvanquished-plat23/maps/plat23.map").string(), {});
}

class OpenArenaCurves : public testing::TestWithParam<std::string> {};

TEST_P(OpenArenaCurves, MatchesAFinerTessellation) {
  const fs::path game = "/usr/share/games/openarena/baseoa";
  if (!fs::exists(game / "pak1-maps.pk3"))
    GTEST_SKIP() << game << " has no levels: install Debian's openarena-085-data (scripts/install-deps.sh --with-test-data)";
  expectCurvesAsTheReference((game / GetParam()).string(), {});
}

INSTANTIATE_TEST_SUITE_P(Levels, OpenArenaCurves, testing::Values("pak1-maps.pk3:maps/oa_ctf2.bsp", "pak1-maps.pk3:maps/oa_dm5.bsp"),
                         [](const auto& info) { return fs::path(info.param).stem().string(); });

} // namespace
} // namespace bt
