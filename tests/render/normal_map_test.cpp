// Normal maps in physical mode (renderer/cpu shadingNormal): a `_norm` companion texture turns the
// shading normal in the face's texture frame (DarkPlaces' convention: red along +s, green up in
// the image), which brightens a wall where it turns the wall towards the light; faithful mode
// and the normal AOV keep the face normal.
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/cpu/integrator.h"
#include "tests/render/normal_map_room.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace bt {
namespace {

using test::NormalMapRoom;
using test::NormalMapRoomOptions;
using test::uniformRgb;

// Tangent-space normals as 8-bit texels ((n + 1) / 2 * 255): flat, and 30 degrees towards +s,
// -s, up in the image and down in the image.
const test::RgbImage kFlat = uniformRgb(8, 8, 128, 128, 255);
const test::RgbImage kTowardsS = uniformRgb(8, 8, 191, 128, 238);
const test::RgbImage kAgainstS = uniformRgb(8, 8, 64, 128, 238);
const test::RgbImage kUp = uniformRgb(8, 8, 128, 191, 238);
const test::RgbImage kDown = uniformRgb(8, 8, 128, 64, 238);

// Lights 120 units to either side of the wall's middle and 32 in front of it (75 degrees off its
// normal there), and above it. The camera's right is -y: the unmirrored texture's +s.
constexpr glm::vec3 kLightRight{96.0f, -120.0f, 128.0f};
constexpr glm::vec3 kLightLeft{96.0f, 120.0f, 128.0f};
constexpr glm::vec3 kLightAbove{64.0f, 0.0f, 240.0f};

RenderSettings settings(LightingMode mode) {
  RenderSettings s;
  s.width = 48;
  s.height = 32;
  s.spp = 8;
  s.seed = 7;
  s.integrator.mode = mode;
  s.integrator.bounces = 1;
  return s;
}

RenderImage render(const NormalMapRoom& room, LightingMode mode = LightingMode::Physical) {
  const RenderSettings s = settings(mode);
  return renderCpu(room.render(), Camera(room.pose(), s.width, s.height), s);
}

// The mean brightness (r + g + b) of the pixels that see the bumpy wall.
double wallBrightness(const NormalMapRoom& room, const RenderImage& image) {
  double sum = 0.0;
  size_t pixels = 0;
  for (size_t i = 0; i < image.beauty.size(); ++i)
    if (image.face[i] == room.wallFace() + 1) {
      sum += image.beauty[i].x + image.beauty[i].y + image.beauty[i].z;
      ++pixels;
    }
  EXPECT_GT(pixels, image.beauty.size() / 2) << "the wall should fill most of the view";
  return pixels ? sum / double(pixels) : 0.0;
}

double wallBrightness(const NormalMapRoomOptions& options) {
  const NormalMapRoom room(options);
  return wallBrightness(room, render(room));
}

// The share of the bumpy wall's pixels at least `factor` times as bright in b as in a. A point
// light near a wall lights the spot in front of it head-on, where any tilt darkens the wall, and
// that spot outshines the rest (inverse square): pixel counts say what the wall does, not means.
double shareBrighter(const NormalMapRoomOptions& a, const NormalMapRoomOptions& b, double factor) {
  const NormalMapRoom roomA(a), roomB(b);
  const RenderImage imageA = render(roomA), imageB = render(roomB);
  size_t wall = 0, brighter = 0;
  for (size_t i = 0; i < imageA.beauty.size(); ++i) {
    if (imageA.face[i] != roomA.wallFace() + 1) continue;
    ++wall;
    const glm::vec3 pa = imageA.beauty[i], pb = imageB.beauty[i];
    brighter += pb.x + pb.y + pb.z >= factor * (pa.x + pa.y + pa.z);
  }
  EXPECT_GT(wall, imageA.beauty.size() / 2) << "the wall should fill most of the view";
  return wall ? double(brighter) / double(wall) : 0.0;
}

TEST(NormalMap, TheImporterAttachesTheCompanionMap) {
  const NormalMapRoom room({kTowardsS, false, kLightRight});
  const Material& m = room.scene().materials[room.scene().faces[room.wallFace()].material];
  ASSERT_FALSE(m.normal.empty());
  EXPECT_EQ(m.normal.width, 8);
  EXPECT_EQ(m.normal.texel(3, 3)[0], 191);
}

// The shading normal on the wall (face normal -x, +s towards -y, up in the image +z) for a hit
// seen head-on: the decoded texel in that frame. Mirrored, +s points to +y.
TEST(NormalMap, ShadingNormalFollowsTheTextureFrame) {
  struct Case {
    test::RgbImage map;
    bool mirrored;
    glm::vec3 expected;
  };
  const Case cases[] = {
      {kTowardsS, false, {-0.866f, -0.5f, 0.0f}}, {kAgainstS, false, {-0.866f, 0.5f, 0.0f}}, {kTowardsS, true, {-0.866f, 0.5f, 0.0f}},
      {kUp, false, {-0.866f, 0.0f, 0.5f}},        {kDown, true, {-0.866f, 0.0f, -0.5f}},     {kFlat, false, {-1.0f, 0.0f, 0.0f}},
  };
  for (const Case& c : cases) {
    const NormalMapRoom room({c.map, c.mirrored, kLightRight});
    SurfaceHit hit;
    hit.found = true;
    hit.face = room.wallFace();
    hit.position = {128.0f, 20.0f, 100.0f};
    hit.normal = {-1.0f, 0.0f, 0.0f};
    const glm::vec3 n = shadingNormal(room.render(), hit, {-1.0f, 0.0f, 0.0f});
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    // 8-bit texels: 191 decodes to 0.498, 128 to 0.004 (not 0), 238 to 0.867.
    EXPECT_LT(glm::length(n - c.expected), 0.01f) << "texel " << int(c.map.rgb[0]) << " " << int(c.map.rgb[1])
                                                  << (c.mirrored ? " mirrored" : "") << ": got " << n.x << " " << n.y << " " << n.z;
  }
}

TEST(NormalMap, NoMapKeepsTheFaceNormalExactly) {
  const NormalMapRoom room({{}, false, kLightRight});
  SurfaceHit hit;
  hit.found = true;
  hit.face = room.wallFace();
  hit.position = {128.0f, 20.0f, 100.0f};
  hit.normal = {-1.0f, 0.0f, 0.0f};
  EXPECT_EQ(shadingNormal(room.render(), hit, glm::normalize(glm::vec3(-0.1f, 1.0f, 0.0f))), hit.normal);
}

// A map tilted 70 degrees towards +s (-y). Seen from far off to the other side (+y, 84 degrees
// off the face normal), wo would lie behind the tilted normal; seen head-on, wo's mirror direction
// would point into the wall. The guard bends the normal so that it faces wo, stays in front of
// the face and reflects wo out of it, still leaning the way the map leans.
TEST(NormalMap, SteepTiltsAreBentToFaceTheViewer) {
  const NormalMapRoom room({uniformRgb(8, 8, 247, 128, 171), false, kLightRight});
  SurfaceHit hit;
  hit.found = true;
  hit.face = room.wallFace();
  hit.position = {128.0f, 20.0f, 100.0f};
  hit.normal = {-1.0f, 0.0f, 0.0f};
  for (const glm::vec3 wo : {glm::normalize(glm::vec3(-0.1f, 1.0f, 0.0f)), glm::vec3(-1.0f, 0.0f, 0.0f)}) {
    const glm::vec3 n = shadingNormal(room.render(), hit, wo);
    EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
    EXPECT_GT(glm::dot(n, wo), 0.0f);
    EXPECT_GT(glm::dot(n, hit.normal), 0.0f);
    const glm::vec3 mirror = 2.0f * glm::dot(n, wo) * n - wo;
    EXPECT_GT(glm::dot(mirror, hit.normal), 0.005f);
  }
  // Head-on the bent normal still leans the way the map does (behind it, it turns to the viewer).
  EXPECT_LT(shadingNormal(room.render(), hit, {-1.0f, 0.0f, 0.0f}).y, -0.5f);
}

// One light from the camera's right. A map that turns the wall towards it brightens the wall, one
// that turns it away darkens it, except near the spot the light shines on head-on.
TEST(NormalMap, TiltTowardsTheLightBrightensTheWall) {
  const NormalMapRoomOptions none{{}, false, kLightRight}, flat{kFlat, false, kLightRight};
  const NormalMapRoomOptions towards{kTowardsS, false, kLightRight}, away{kAgainstS, false, kLightRight};
  EXPECT_GT(wallBrightness(none), 0.0);
  EXPECT_GE(shareBrighter(none, towards, 1.2), 0.8);
  EXPECT_GE(shareBrighter(flat, towards, 1.2), 0.8);
  EXPECT_GE(shareBrighter(away, none, 1.2), 0.8);
}

// The flat map against no map, pixel by pixel: the same random numbers, and a shading normal
// 0.3 degrees off the face's, as 8-bit 128 decodes to 0.004, not 0. Where the light grazes the
// wall (on the left, 88 degrees off the normal) that tilt still moves cos by a few percent.
TEST(NormalMap, FlatMapGivesTheImageOfNoMap) {
  const NormalMapRoom none({{}, false, kLightRight});
  const NormalMapRoom flat({kFlat, false, kLightRight});
  const RenderImage a = render(none), b = render(flat);
  ASSERT_EQ(a.beauty.size(), b.beauty.size());
  size_t close = 0;
  glm::dvec3 sumA(0.0), sumB(0.0);
  for (size_t i = 0; i < a.beauty.size(); ++i) {
    close += glm::length(a.beauty[i] - b.beauty[i]) <= 0.05f * glm::length(a.beauty[i]) + 1e-4f;
    sumA += glm::dvec3(a.beauty[i]);
    sumB += glm::dvec3(b.beauty[i]);
  }
  EXPECT_GE(close, a.beauty.size() * 97 / 100) << close << " of " << a.beauty.size() << " pixels agree";
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sumB[c], sumA[c], 0.01 * sumA[c]) << "channel " << c;
}

// Green is up in the image (-t, here +z): with the light above the wall, a map tilted up
// brightens it and one tilted down darkens it. A reader that took green along +t would swap them.
TEST(NormalMap, GreenTiltsUpInTheImage) {
  const NormalMapRoomOptions none{{}, false, kLightAbove}, up{kUp, false, kLightAbove}, down{kDown, false, kLightAbove};
  EXPECT_GE(shareBrighter(none, up, 1.2), 0.8);
  EXPECT_GE(shareBrighter(down, none, 1.2), 0.8);
}

// A mirrored texture (scale -1 along s) mirrors its normal map: the map that turned the wall
// towards a light on the right now turns it to the left. The room is symmetric, so the mirrored
// wall lit from the left looks like the unmirrored one lit from the right.
TEST(NormalMap, MirroredTextureMirrorsTheEffect) {
  const NormalMapRoomOptions noneRight{{}, true, kLightRight}, noneLeft{{}, true, kLightLeft};
  const NormalMapRoomOptions mirroredRight{kTowardsS, true, kLightRight}, mirroredLeft{kTowardsS, true, kLightLeft};
  EXPECT_GE(shareBrighter(mirroredRight, noneRight, 1.2), 0.8);
  EXPECT_GE(shareBrighter(noneLeft, mirroredLeft, 1.2), 0.8);
  const double unmirroredRight = wallBrightness({kTowardsS, false, kLightRight});
  EXPECT_NEAR(wallBrightness(mirroredLeft), unmirroredRight, 0.03 * unmirroredRight);
}

// Faithful mode is what ericw-tools' `light` bakes, and the compiler has no normal maps.
TEST(NormalMap, FaithfulModeIgnoresTheMap) {
  const NormalMapRoom none({{}, false, kLightRight});
  const NormalMapRoom towards({kTowardsS, false, kLightRight});
  const RenderImage a = render(none, LightingMode::Faithful), b = render(towards, LightingMode::Faithful);
  EXPECT_GT(wallBrightness(none, a), 0.0);
  EXPECT_EQ(a.beauty, b.beauty);
}

// The normal AOV is the face's geometric normal whatever the map says.
TEST(NormalMap, NormalAovStaysTheFaceNormal) {
  const NormalMapRoom room({kTowardsS, false, kLightRight});
  const RenderImage aovs = renderAovsCpu(room.render(), Camera(room.pose(), 48, 32), 48, 32);
  size_t wall = 0;
  for (size_t i = 0; i < aovs.normal.size(); ++i)
    if (aovs.face[i] == room.wallFace() + 1) {
      EXPECT_EQ(aovs.normal[i], glm::vec3(-1.0f, 0.0f, 0.0f)) << "pixel " << i;
      ++wall;
    }
  EXPECT_GT(wall, aovs.normal.size() / 2);
}

} // namespace
} // namespace bt
