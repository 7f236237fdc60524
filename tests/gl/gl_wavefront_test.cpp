// The wavefront form of the path tracer (shaders/wavefront.glsl) against the megakernel
// (shaders/pathtrace.comp): the same advance() on the same random streams, so the same image
// for the same seed and sample count, in every lighting mode. Equal within float tolerance, not
// bit for bit: the driver compiles the traversal and the shading in separate programs, and may
// contract or reorder their arithmetic differently (measured: bit-exact on llvmpipe).
#include "renderer/cpu/integrator.h"
#include "lighting/light_grid.h"
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <glm/common.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace bt::gl {
namespace {

// Not multiples of the 8 x 8 work groups: the last groups' spare invocations have no slot.
constexpr int kWidth = 61;
constexpr int kHeight = 35;

// One set of programs for the suite: llvmpipe compiles each for seconds, and the trace kernel
// serves every lighting mode.
std::shared_ptr<TracerPrograms> sharedPrograms() {
  static const auto programs = std::make_shared<TracerPrograms>(test::sharedGlContext(), test::textureModeUnderTest());
  return programs;
}

float largestOf(glm::vec3 v) {
  return std::max(v.x, std::max(v.y, v.z));
}

// Renders `settings` with both forms and compares them pixel by pixel.
void expectSameImage(const Scene& scene, const GlLighting& lighting, BeautySettings settings) {
  GlTracer tracer(test::sharedGlContext(), scene, TraceScene::build(scene), sharedPrograms(), lighting);
  const CameraBasis camera = test::testCamera(settings.width, settings.height);
  settings.form = PathTracerForm::Megakernel;
  const BeautyImage mega = tracer.renderBeauty(camera, settings);
  settings.form = PathTracerForm::Wavefront;
  const BeautyImage wave = tracer.renderBeauty(camera, settings);
  ASSERT_EQ(mega.samples, settings.spp);
  ASSERT_EQ(wave.samples, settings.spp);
  EXPECT_EQ(mega.wavefrontSamples, 0);
  EXPECT_EQ(wave.wavefrontSamples, settings.spp);
  ASSERT_EQ(mega.beauty.size(), wave.beauty.size());
  size_t lit = 0, exact = 0, differing = 0;
  float largest = 0.0f;
  for (size_t i = 0; i < mega.beauty.size(); ++i) {
    const glm::vec3 a = mega.beauty[i], b = wave.beauty[i];
    lit += a != glm::vec3(0.0f);
    exact += a == b;
    const float error = largestOf(glm::abs(a - b));
    largest = std::max(largest, error);
    // Float rounding, or at most one sample of a pixel sent another way (a shadow ray grazing an edge).
    if (error > 1e-4f * std::max(1.0f, largestOf(a))) ++differing;
  }
  EXPECT_GT(lit, mega.beauty.size() / 2) << "the test should see a lit room";
  EXPECT_LE(differing, mega.beauty.size() / 200) << "largest difference " << largest;
  std::printf("wavefront vs megakernel: %zu of %zu pixels bit-exact, %zu beyond float tolerance, largest difference %g\n", exact,
              mega.beauty.size(), differing, largest);
}

GpuLight pointLight(glm::vec3 origin, float value) {
  GpuLight light;
  light.origin = origin;
  light.value = value;
  return light;
}

TEST(GlWavefront, FaithfulWithBounceEqualsTheMegakernel) {
  GlLighting lighting;
  lighting.lights = {pointLight({-100, 0, 200}, 300.0f), pointLight({150, 100, 60}, 200.0f)};
  lighting.lights[1].deviance = 8.0f; // jittered copies draw random numbers in the light loop
  lighting.faithfulBounces = 1;
  lighting.minlight = glm::vec3(5.0f);
  expectSameImage(test::makeTestRoom(), lighting, {.width = kWidth, .height = kHeight, .spp = 2, .seed = 3});
}

// A level with more bounce lights than the draw's rays gets the faithful program with the draw
// (BT_FAITHFUL_BOUNCE_DRAW), whose state lives in the path between the wavefront's dispatches.
// The room's floor and walls as 40 bounce lights facing into it: every cell lists more than 16.
TEST(GlWavefront, FaithfulBounceDrawEqualsTheMegakernel) {
  GlLighting lighting;
  lighting.lights = {pointLight({-100, 0, 200}, 300.0f)};
  for (int i = 0; i < 40; ++i) {
    GpuLight bounce = pointLight({-240.0f + 12.0f * float(i), 200.0f - 10.0f * float(i % 7), 1.0f}, 40000.0f + 1000.0f * float(i));
    bounce.formula = uint32_t(LightFormula::Bounce);
    bounce.direction = {0.0f, 0.0f, 1.0f}; // towards what it lights
    bounce.color = {0.9f, 0.6f + 0.01f * float(i % 10), 0.4f};
    if (i % 4 == 3) bounce.origin = {-255.0f, bounce.origin.y, 60.0f}, bounce.direction = {1.0f, 0.0f, 0.0f};
    lighting.lights.push_back(bounce);
  }
  lighting.faithfulBounces = 1;
  ASSERT_TRUE(faithfulFeatures(lighting.dirt, lighting.lights).bounceDraw);
  const Scene room = test::makeTestRoom();
  lighting.lightGrid = buildLightGrid(lighting.lights, TraceScene::build(room).bounds(), lighting.scaledist);
  ASSERT_GT(trailingBounceLights(lighting.lights, lighting.lightGrid.cellLights({100.0f, 60.0f, 40.0f})), kBounceShadowRays)
      << "the cell the camera looks at must draw among its bounce lights";
  expectSameImage(room, lighting, {.width = kWidth, .height = kHeight, .spp = 2, .seed = 5});
}

TEST(GlWavefront, PhysicalEqualsTheMegakernel) {
  GlLighting lighting;
  lighting.lights = {pointLight({-100, 0, 200}, 300.0f), pointLight({150, 100, 60}, 200.0f)};
  expectSameImage(test::makeTestRoom(), lighting,
                  {.width = kWidth, .height = kHeight, .spp = 2, .seed = 5, .physical = true, .bounces = 3});
}

// Physical mode's firefly clamp (BeautySettings::clampIndirect) in both forms: at 512 units it
// dims every point light's light at the surfaces after the camera's, which both must do alike;
// the clamped image must differ from the unclamped one, or the comparison would prove nothing.
TEST(GlWavefront, PhysicalWithTheFireflyClampEqualsTheMegakernel) {
  GlLighting lighting;
  lighting.lights = {pointLight({-100, 0, 200}, 300.0f), pointLight({150, 100, 60}, 200.0f)};
  const Scene room = test::makeTestRoom();
  const BeautySettings clamped{
      .width = kWidth, .height = kHeight, .spp = 2, .seed = 5, .physical = true, .bounces = 3, .clampIndirect = 512.0f};
  expectSameImage(room, lighting, clamped);

  GlTracer tracer(test::sharedGlContext(), room, TraceScene::build(room), sharedPrograms(), lighting);
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  BeautySettings unclamped = clamped;
  unclamped.clampIndirect = 0.0f;
  const BeautyImage a = tracer.renderBeauty(camera, clamped), b = tracer.renderBeauty(camera, unclamped);
  size_t changed = 0;
  for (size_t i = 0; i < a.beauty.size(); ++i) changed += largestOf(glm::abs(a.beauty[i] - b.beauty[i])) > 1e-3f * largestOf(b.beauty[i]);
  EXPECT_GT(changed, a.beauty.size() / 4) << "the clamp should change the light of most pixels";
}

TEST(GlWavefront, FaithfulDirtEqualsTheMegakernel) {
  GlLighting lighting;
  lighting.lights = {pointLight({-100, 0, 200}, 300.0f)};
  lighting.lights[0].flags = kLightFlagDirt;
  lighting.dirt.enabled = true;
  lighting.dirt.depth = 64.0f;
  lighting.dirt.minlight = true;
  lighting.minlight = glm::vec3(20.0f);
  expectSameImage(test::makeTestRoom(), lighting, {.width = kWidth, .height = kHeight, .spp = 1, .seed = 1});
}

TEST(GlWavefront, AutoDrawsWithTheMegakernelOnceItIsBuilt) {
  GlLighting lighting;
  lighting.lights = {pointLight({-100, 0, 200}, 300.0f)};
  const Scene scene = test::makeTestRoom();
  GlTracer tracer(test::sharedGlContext(), scene, TraceScene::build(scene), sharedPrograms(), lighting);
  tracer.buildPathTracer(kWidth, kHeight, false); // the size of the first test's: llvmpipe compiles a variant per image shape
  EXPECT_FALSE(tracer.programs().wavefrontWhileCompiling(false));
  const BeautyImage image = tracer.renderBeauty(test::testCamera(kWidth, kHeight), {.width = kWidth, .height = kHeight, .spp = 2});
  EXPECT_EQ(image.samples, 2);
  EXPECT_EQ(image.wavefrontSamples, 0);
}

} // namespace
} // namespace bt::gl
