// Whole-frame rendering: camera conventions, determinism across threads and runs, exact AOVs,
// and the image files.
#include "renderer/cpu/cpu_renderer.h"
#include "renderer/denoise.h"
#include "renderer/image_output.h"
#include "tests/render/box_scene.h"
#include "scene/color.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>

namespace bt {
namespace {

TEST(Camera, QuakeViewAngles) {
  auto forward = [](float pitch, float yaw) {
    CameraPose p;
    p.pitch = pitch;
    p.yaw = yaw;
    return Camera(p, 4, 4).forward();
  };
  EXPECT_NEAR(glm::distance(forward(0, 0), glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(forward(0, 90), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(forward(90, 0), glm::vec3(0, 0, -1)), 0.0f, 1e-6f); // +pitch looks down
  // Right of the image is the camera's right: looking along +X, that is -Y.
  CameraPose p;
  const Camera c(p, 100, 50);
  EXPECT_LT(c.ray(99.5f, 25.0f).direction.y, 0.0f);
  EXPECT_GT(c.ray(50.0f, 0.5f).direction.z, 0.0f); // top row looks up
  // 90 degree horizontal field of view: the right edge is 45 degrees off axis.
  EXPECT_NEAR(c.ray(100.0f, 25.0f).direction.x, std::sqrt(0.5f), 1e-5f);
}

// The viewer's markers are drawn where project() puts them: the pixel whose ray passes there.
TEST(Camera, ProjectIsTheInverseOfRay) {
  CameraPose p;
  p.origin = glm::vec3(10, -20, 30);
  p.pitch = 20, p.yaw = 135, p.roll = 5;
  const Camera c(p, 320, 180);
  for (const glm::vec2 pixel : {glm::vec2(0.5f, 0.5f), glm::vec2(160, 90), glm::vec2(300.25f, 17.75f), glm::vec2(12, 170)}) {
    const Ray r = c.ray(pixel.x, pixel.y);
    const auto projected = c.project(r.origin + r.direction * 250.0f);
    ASSERT_TRUE(projected.has_value());
    EXPECT_NEAR(projected->x, pixel.x, 1e-3f);
    EXPECT_NEAR(projected->y, pixel.y, 1e-3f);
    EXPECT_NEAR(projected->z, 250.0f * glm::dot(r.direction, c.forward()), 1e-2f);
  }
  EXPECT_FALSE(c.project(p.origin - c.forward() * 10.0f).has_value()) << "a point behind the camera has no pixel";
}

TEST(Camera, ParseFormatAndDefaults) {
  auto pose = parseCameraPose("(1 -2.5 3) 10 20 30");
  ASSERT_TRUE(pose);
  EXPECT_EQ(pose->origin, glm::vec3(1, -2.5f, 3));
  EXPECT_EQ(formatCameraPose(*pose), "(1 -2.5 3) 10 20 30");
  EXPECT_FALSE(parseCameraPose("1 2 3 10 20 30"));
  EXPECT_FALSE(parseCameraPose("(1 2 x) 10 20 30"));
  // Quake's and Source's console lines, and every form without roll.
  for (const char* text : {"setpos 1 -2.5 3 10 20 30", "setpos 1 -2.5 3;setang 10 20 30", " setpos 1 -2.5 3 ; setang 10 20 30 "}) {
    const auto setpos = parseCameraPose(text);
    ASSERT_TRUE(setpos) << text;
    EXPECT_EQ(formatCameraPose(*setpos), "(1 -2.5 3) 10 20 30") << text;
  }
  for (const char* text : {"(1 -2.5 3) 10 20", "setpos 1 -2.5 3 10 20", "setpos 1 -2.5 3;setang 10 20"}) {
    const auto noRoll = parseCameraPose(text);
    ASSERT_TRUE(noRoll) << text;
    EXPECT_EQ(formatCameraPose(*noRoll), "(1 -2.5 3) 10 20 0") << text;
  }
  for (const char* text : {"setpos 1 2 3", "setpos 1 2 3 4", "setpos 1 2 3 4 5 6 7", "setpos 1 2;setang 3 4 5", "setpos 1 2 3;setang 4",
                           "setposx 1 2 3 4 5", "(1 2 3) 4", "(1 2 3) 4 5 6 7", "setpos 1 2 3;setang 4 5 x", ""})
    EXPECT_FALSE(parseCameraPose(text)) << text;

  test::BoxSceneBuilder b;
  b.material("white", 255, 255, 255);
  b.room({-64, -64, 0}, {64, 64, 128}, "white"); // a view that sees walls keeps the entity's angles
  b.entity({{"classname", "info_player_start"}, {"origin", "10 20 24"}, {"angle", "90"}});
  CameraPose d = defaultCameraPose(b.build());
  EXPECT_EQ(d.source, "info_player_start");
  EXPECT_EQ(d.origin, glm::vec3(10, 20, 46)); // 22 units eye height
  EXPECT_FLOAT_EQ(d.yaw, 90.0f);
  b.entity({{"classname", "info_intermission"}, {"origin", "0 0 100"}, {"mangle", "15 180 0"}});
  d = defaultCameraPose(b.build());
  EXPECT_EQ(d.source, "info_intermission");
  EXPECT_FLOAT_EQ(d.pitch, 15.0f);
  EXPECT_FLOAT_EQ(d.yaw, 180.0f);
}

// A lit room with a pillar, seen from inside.
Scene litRoom() {
  test::BoxSceneBuilder b;
  b.material("white", 230, 230, 230);
  b.material("red", 200, 30, 30);
  b.room({-128, -128, 0}, {128, 128, 128}, "white");
  b.box({20, -20, 0}, {60, 20, 100}, "red");
  b.entity({{"classname", "light"}, {"origin", "-60 40 100"}, {"light", "250"}, {"_deviance", "8"}});
  return b.build();
}

RenderImage renderRoom(LightingMode mode, int threads, uint32_t seed, int spp = 2) {
  static const Scene scene = litRoom();
  Diagnostics diags;
  static const RenderScene rs = buildRenderScene(scene, {}, diags);
  CameraPose pose;
  pose.origin = {-110, -100, 64};
  pose.yaw = 40;
  pose.pitch = 10;
  RenderSettings s;
  s.width = 32;
  s.height = 24;
  s.spp = spp;
  s.threads = threads;
  s.seed = seed;
  s.integrator.mode = mode;
  return renderCpu(rs, Camera(pose, s.width, s.height), s);
}

TEST(Render, DeterministicAcrossThreadCountsAndRuns) {
  for (LightingMode mode : {LightingMode::Faithful, LightingMode::Physical}) {
    const RenderImage a = renderRoom(mode, 1, 3);
    const RenderImage b = renderRoom(mode, 2, 3);
    const RenderImage c = renderRoom(mode, 2, 3);
    EXPECT_EQ(a.beauty, b.beauty);
    EXPECT_EQ(b.beauty, c.beauty);
    // A different seed draws different random numbers (soft shadows, bounces): not the same image.
    const RenderImage d = renderRoom(mode, 2, 4);
    EXPECT_NE(a.beauty, d.beauty);
    // Nothing is black everywhere: the light reaches the walls.
    float total = 0.0f;
    for (const glm::vec3& v : a.beauty) total += v.x + v.y + v.z;
    EXPECT_GT(total, 1.0f);
  }
}

TEST(Render, AovsAreExactAtKnownPixels) {
  const RenderImage img = renderRoom(LightingMode::Faithful, 2, 0, 1);
  // Recompute the centre pixel's ray by hand: camera at (-110 -100 64) looking yaw 40 pitch 10.
  const size_t centre = size_t(12) * 32 + 16;
  ASSERT_NE(img.face[centre], 0u);
  const Scene scene = litRoom();
  Diagnostics diags;
  const RenderScene rs = buildRenderScene(scene, {}, diags);
  CameraPose pose;
  pose.origin = {-110, -100, 64};
  pose.yaw = 40;
  pose.pitch = 10;
  const Ray ray = Camera(pose, 32, 24).ray(16.5f, 12.5f);
  const SurfaceHit hit = traceVisible(rs, ray);
  EXPECT_EQ(img.face[centre], hit.face + 1);
  EXPECT_EQ(img.depth[centre], hit.t);
  EXPECT_EQ(img.normal[centre], hit.normal);
  // The centre looks at the red pillar: albedo is the red texture's linear colour.
  EXPECT_EQ(scene.faces[hit.face].texture, "red");
  EXPECT_NEAR(img.albedo[centre].x, srgbToLinear(200.0f / 255.0f), 1e-6f);
  // And the AOVs do not depend on the seed or sample count.
  const RenderImage other = renderRoom(LightingMode::Physical, 1, 9, 3);
  EXPECT_EQ(img.face, other.face);
  EXPECT_EQ(img.depth, other.depth);
  EXPECT_EQ(img.albedo, other.albedo);
}

TEST(ImageOutput, PngRoundTripAndExrLayers) {
  const RenderImage img = renderRoom(LightingMode::Faithful, 2, 0, 1);
  const auto dir = std::filesystem::temp_directory_path() / ("bt_render_test_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string png = (dir / "out.png").string();
  writeImage(png, img, {});
  auto in = OIIO::ImageInput::open(png);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().width, 32);
  EXPECT_EQ(in->spec().nchannels, 3);
  std::vector<uint8_t> pixels(32 * 24 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
  in->close();
  EXPECT_EQ(pixels, displayPixels(img, {}));

  const std::string exr = (dir / "out.exr").string();
  writeImage(exr, img, {});
  auto ex = OIIO::ImageInput::open(exr);
  ASSERT_TRUE(ex);
  const auto& names = ex->spec().channelnames;
  for (const char* n : {"R", "G", "B", "albedo.R", "normal.X", "depth.Z"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  ex->close();

  // Only the two finished files: no temporary left behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 2);
  EXPECT_THROW(writeImage((dir / "out.bmp").string(), img, {}), std::runtime_error);
  EXPECT_THROW(writeImage((dir / "missing" / "out.png").string(), img, {}), std::runtime_error);
  std::filesystem::remove_all(dir);
}

// A physical image written as an EXR and read back denoises to the same picture as the image the
// tracer gave: the second moment and the sample count travel with the beauty and its AOVs, so
// the denoiser lab (issue 18) can filter stored images again. The exposure written is taken out.
TEST(ImageOutput, AnExrReadBackDenoisesAsTheTracersImage) {
  const RenderImage img = renderRoom(LightingMode::Physical, 2, 0, 8);
  const auto dir = std::filesystem::temp_directory_path() / ("bt_render_test_moment_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string exr = (dir / "physical.exr").string();
  writeImage(exr, img, {.exposureEv = 1.5f});
  const RenderImage back = readExrImage(exr);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(back.samples, 8);
  ASSERT_EQ(back.luminanceMoment2.size(), img.luminanceMoment2.size());
  const std::vector<glm::vec3> expected = denoise(img), got = denoise(back);
  float worst = 0.0f;
  for (size_t i = 0; i < expected.size(); ++i)
    worst = std::max(worst, glm::length(got[i] - expected[i]) / (glm::length(expected[i]) + 1e-3f));
  EXPECT_LT(worst, 1e-4f) << "the denoised image read back differs from the tracer's";
}

TEST(ImageOutput, TonemapsAndExposure) {
  EXPECT_NEAR(tonemapAces(glm::vec3(0.0f)).x, 0.0f, 1e-6f);
  EXPECT_LT(tonemapAces(glm::vec3(100.0f)).x, 1.0001f);
  const glm::vec3 mid = tonemapAgx(glm::vec3(0.18f));
  EXPECT_GT(mid.x, 0.05f);
  EXPECT_LT(mid.x, 0.5f);
  RenderImage img;
  img.width = 1;
  img.height = 1;
  img.beauty = {glm::vec3(0.25f)};
  img.albedo = {glm::vec3(0.0f)};
  img.normal = {glm::vec3(0.0f)};
  img.depth = {1.0f};
  img.face = {0};
  OutputSettings out;
  out.tonemap = Tonemap::Linear;
  EXPECT_EQ(displayPixels(img, out)[0], uint8_t(std::lround(linearToSrgb(0.25f) * 255.0f)));
  out.exposureEv = 1.0f; // twice as bright
  EXPECT_EQ(displayPixels(img, out)[0], uint8_t(std::lround(linearToSrgb(0.5f) * 255.0f)));
}

} // namespace
} // namespace bt
