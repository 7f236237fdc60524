// AOV images of the GL tracer against a double-precision brute-force reference.
#include "renderer/gl/gl_context.h"
#include "renderer/gl/gl_error.h"
#include "renderer/gl/gl_scene.h"
#include "renderer/gl/gl_tracer.h"
#include "tests/gl/test_scenes.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <utility>
#include <vector>

namespace bt::gl {
namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 64;

// Pixels whose ray grazes an edge between two faces may pick either in float; allow 0.5 %.
constexpr double kMaxFaceMismatch = 0.005;

void expectAovsMatch(const AovImages& gpu, const AovImages& ref, double albedoTolerance = 3e-5) {
  ASSERT_EQ(gpu.width, ref.width);
  ASSERT_EQ(gpu.height, ref.height);
  size_t mismatched = 0, hits = 0;
  for (size_t i = 0; i < ref.face.size(); ++i) {
    if (gpu.face[i] != ref.face[i]) {
      ++mismatched;
      continue;
    }
    if (ref.face[i] == AovImages::kNothingHit) continue;
    ++hits;
    EXPECT_NEAR(gpu.depth[i], ref.depth[i], 1e-4 * ref.depth[i] + 1e-3) << "pixel " << i;
    EXPECT_LT(glm::length(gpu.normal[i] - ref.normal[i]), 1e-5f) << "pixel " << i;
    // The float hit point is a few ulps off the double one; on the checker's steepest texel
    // gradient that moves the filtered colour by up to ~1e-5.
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(gpu.albedo[i][c], ref.albedo[i][c], albedoTolerance) << "pixel " << i << " channel " << c;
  }
  EXPECT_LE(mismatched, kMaxFaceMismatch * ref.face.size()) << mismatched << " pixels see another face";
  EXPECT_GT(hits, ref.face.size() / 2);
}

TEST(GlAov, TestRoomEqualsBruteForceReference) {
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeTestRoom();
  const int debugErrorsBefore = context->debugErrorCount();
  GlTracer tracer(*context, scene, test::textureModeUnderTest());
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  const AovImages gpu = tracer.renderAovs(camera, kWidth, kHeight);
  expectAovsMatch(gpu, test::referenceAovs(scene, camera, kWidth, kHeight));
  EXPECT_EQ(context->debugErrorCount(), debugErrorsBefore);
}

TEST(GlAov, EveryBrushAndMaterialIsSeen) {
  // Guards the test above against a camera that misses what it is meant to check.
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeTestRoom();
  GlTracer tracer(*context, scene, TextureMode::Arrays);
  const AovImages gpu = tracer.renderAovs(test::testCamera(kWidth, kHeight), kWidth, kHeight);
  std::vector<bool> materialSeen(scene.materials.size());
  bool slopedSeen = false;
  for (uint32_t f : gpu.face) {
    if (f == AovImages::kNothingHit) continue;
    materialSeen[scene.faces[f - 1].material] = true;
    const dvec3 n = scene.faces[f - 1].plane.normal;
    slopedSeen |= std::abs(n.x) > 0.1 && std::abs(n.z) > 0.1;
  }
  for (size_t m = 0; m < materialSeen.size(); ++m) EXPECT_TRUE(materialSeen[m]) << scene.materials[m].name;
  EXPECT_TRUE(slopedSeen) << "the wedge's sloped face is out of view";
}

TEST(GlAov, ArraysAndBindlessGiveTheSameImage) {
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeTestRoom();
  if (!context->info().bindlessTextures) {
    ASSERT_NE(test::textureModeUnderTest(), TextureMode::Bindless) << "BT_GL_TEXTURES=bindless on a context without it";
    EXPECT_THROW(GlTracer(*context, scene, TextureMode::Bindless), GlError);
    GTEST_SKIP() << context->info().renderer << " has no GL_ARB_bindless_texture; compared on the GPU (scripts/gpu-check.sh)";
  }
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  GlTracer arrays(*context, scene, TextureMode::Arrays);
  const AovImages a = arrays.renderAovs(camera, kWidth, kHeight);
  GlTracer bindless(*context, scene, TextureMode::Bindless);
  ASSERT_EQ(bindless.textureMode(), TextureMode::Bindless);
  const AovImages b = bindless.renderAovs(camera, kWidth, kHeight);
  EXPECT_EQ(a.face, b.face);
  EXPECT_EQ(a.depth, b.depth);
  for (size_t i = 0; i < a.albedo.size(); ++i) EXPECT_EQ(a.albedo[i], b.albedo[i]) << "pixel " << i;

  // Path-traced beauty: the same texels through either path, so the same samples; the two
  // shader variants may still be compiled into differently ordered float arithmetic.
  GlLighting lighting;
  lighting.lights = {GpuLight{.origin = {0, 0, 200}}};
  const BeautySettings settings{.width = kWidth, .height = kHeight, .spp = 4, .physical = true, .bounces = 3};
  const BeautyImage beautyArrays = GlTracer(*context, scene, TextureMode::Arrays, lighting).renderBeauty(camera, settings);
  const BeautyImage beautyBindless = GlTracer(*context, scene, TextureMode::Bindless, lighting).renderBeauty(camera, settings);
  for (size_t i = 0; i < beautyArrays.beauty.size(); ++i)
    EXPECT_LE(glm::length(beautyArrays.beauty[i] - beautyBindless.beauty[i]), 1e-5f * (1.0f + glm::length(beautyArrays.beauty[i])))
        << "pixel " << i;
}

// More texture sizes than sampler arrays (llvmpipe has no bindless, so this is the only GL path
// there): the arrays path merges size classes and pads layers, and still draws what the
// reference and the bindless path draw, texel for texel.
TEST(GlAov, MoreTextureSizesThanArraysEqualTheReference) {
  GlContext* context = &test::sharedGlContext();
  const Scene scene = test::makeManyTextureSizesWall();
  std::set<std::pair<int, int>> sizes;
  for (const Material& m : scene.materials) sizes.insert({m.baseColor.width, m.baseColor.height});
  ASSERT_GT(sizes.size(), size_t(kMaxTextureArrays));

  constexpr int width = 192, height = 128;
  const CameraBasis camera = test::manyTextureSizesCamera(width, height);
  const int debugErrorsBefore = context->debugErrorCount();
  GlTracer arrays(*context, scene, TextureMode::Arrays);
  const AovImages gpu = arrays.renderAovs(camera, width, height);
  EXPECT_EQ(context->debugErrorCount(), debugErrorsBefore);
  // Denser texels than the test room's (up to 32 over a 48-unit face), neighbours up to the full
  // range apart: the float hit point's few ulps move the filtered colour by up to ~4e-5 here. A
  // texel read from the wrong place (a map wrapped at its padded layer's size) is off by ~0.1.
  expectAovsMatch(gpu, test::referenceAovs(scene, camera, width, height), 1e-4);
  std::set<uint32_t> materialsSeen;
  for (uint32_t f : gpu.face)
    if (f != AovImages::kNothingHit) materialsSeen.insert(scene.faces[f - 1].material);
  EXPECT_EQ(materialsSeen.size(), scene.materials.size()) << "every texture size in view";

  if (!context->info().bindlessTextures) return; // compared on the GPU (scripts/gpu-check.sh)
  GlTracer bindless(*context, scene, TextureMode::Bindless);
  const AovImages b = bindless.renderAovs(camera, width, height);
  EXPECT_EQ(gpu.face, b.face);
  for (size_t i = 0; i < gpu.albedo.size(); ++i) EXPECT_EQ(gpu.albedo[i], b.albedo[i]) << "pixel " << i;
}

// The sampler state the textures carry (gl_textures.h): the driver's anisotropy up to 16x
// (llvmpipe offers 16x). No shader samples through it today (the tracer fetches level-0 texels
// itself, so the AOVs above equal the CPU reference); this checks only that a sampler lookup
// would get the filter gl_textures.h documents.
TEST(GlTextures, AnisotropicFilteringAtTheDriversMaximumUpTo16) {
  GlContext& context = test::sharedGlContext();
  if (!context.info().anisotropicFiltering) GTEST_SKIP() << context.info().renderer << " has no anisotropic filtering";
  GLfloat driverMax = 0.0f;
  glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &driverMax);
  const Scene scene = test::makeTestRoom();
  GlTextures textures(scene, TextureMode::Arrays, context.info());
  EXPECT_EQ(textures.anisotropy(), std::min(driverMax, 16.0f));
  EXPECT_GT(textures.anisotropy(), 1.0f);
  textures.bind();
  GLint array = 0;
  glActiveTexture(GL_TEXTURE0);
  glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &array);
  ASSERT_NE(array, 0);
  GLfloat set = 0.0f;
  glGetTextureParameterfv(static_cast<GLuint>(array), GL_TEXTURE_MAX_ANISOTROPY, &set);
  EXPECT_EQ(set, textures.anisotropy());
}

TEST(GlAov, EmptySceneSeesNothing) {
  GlContext* context = &test::sharedGlContext();
  Scene scene;
  GlTracer tracer(*context, scene, TextureMode::Arrays);
  const AovImages gpu = tracer.renderAovs(test::testCamera(16, 8), 16, 8);
  for (uint32_t f : gpu.face) EXPECT_EQ(f, AovImages::kNothingHit);
  for (float d : gpu.depth) EXPECT_TRUE(std::isinf(d));
}

void expectLayoutFacesEqualClosestHit(const Scene& scene, const TraceScene& traceScene, const CameraBasis& camera, int width, int height,
                                      TraceLayout layout) {
  GlContext& context = test::sharedGlContext();
  GlTracer tracer(context, scene, traceScene, std::make_shared<TracerPrograms>(context, TextureMode::Arrays, layout));
  const AovImages gpu = tracer.renderAovs(camera, width, height);
  size_t mismatched = 0, hits = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      // camera.glsl's ray, in float like the shader.
      const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / glm::vec2(width, height) * 2.0f - 1.0f;
      const glm::vec3 dir = glm::normalize(camera.forward + ndc.x * camera.right - ndc.y * camera.up);
      const std::optional<Hit> hit = traceScene.closestHit(Ray{camera.origin, 0.0f, dir});
      const size_t i = static_cast<size_t>(y) * width + x;
      const uint32_t expected = hit ? hit->face + 1 : AovImages::kNothingHit;
      if (gpu.face[i] != expected) {
        ++mismatched;
        continue;
      }
      if (!hit) continue;
      ++hits;
      EXPECT_NEAR(gpu.depth[i], hit->t, 1e-5f * hit->t) << "pixel " << i;
    }
  // The GPU's normalize and division may round differently in the last bit: allow a pixel or two.
  EXPECT_LE(mismatched, 2u);
  EXPECT_GT(hits, 0u);
}

// Every pixel's face is the one TraceScene::closestHit finds for the same ray, ties between
// neighbouring brushes included: the shaders traverse a layout made from TraceScene's tree
// (renderer/gl/gl_structs.h GlBvhNode) by trace_scene.cpp's rules. Both trace layouts are held
// to it on whatever runs the tests: llvmpipe's (BT_TRACE_SOFTWARE) and the GPUs'.
void expectFacesEqualClosestHit(const Scene& scene, const TraceScene& traceScene,
                                const CameraBasis& camera = test::testCamera(kWidth, kHeight), int width = kWidth, int height = kHeight) {
  for (const TraceLayout layout : {TraceLayout::Software, TraceLayout::Hardware}) {
    SCOPED_TRACE(layout == TraceLayout::Software ? "software trace layout" : "hardware trace layout");
    expectLayoutFacesEqualClosestHit(scene, traceScene, camera, width, height, layout);
  }
}

// A row of 40 boxes makes the tree deep enough to exercise the stack; one brush per leaf.
TEST(GlAov, FacesEqualTraceSceneClosestHit) {
  Scene scene = test::makeTestRoom();
  for (int i = 0; i < 40; ++i) test::addBox(scene, {-250.0 + i * 12.0, 100, 0}, {-242.0 + i * 12.0, 108, 8.0 + i}, i % 3);
  expectFacesEqualClosestHit(scene, TraceScene::build(scene, {.leafSize = 1}));
  expectFacesEqualClosestHit(scene, TraceScene::build(scene, {.leafSize = 8}));
}

// How deep trace.glsl's stack gets for `ray`: its walk over the GlBvhNodes (nearer child first,
// the farther one pushed), in float, with TraceScene's brush hits cutting it short as the best
// t shrinks.
size_t deepestStack(const TraceScene& scene, const std::vector<GlBvhNode>& nodes, const Ray& ray) {
  float best = std::numeric_limits<float>::infinity();
  auto overlaps = [&](const float(&min)[3], const float(&max)[3], float& entry) {
    float near = 0.0f, far = best;
    for (int a = 0; a < 3; ++a) {
      const float t0 = (min[a] - ray.origin[a]) / ray.direction[a], t1 = (max[a] - ray.origin[a]) / ray.direction[a];
      near = std::max(near, std::min(t0, t1));
      far = std::min(far, std::max(t0, t1));
    }
    entry = near;
    return near <= far;
  };
  std::vector<uint32_t> stack;
  size_t deepest = 0;
  uint32_t current = 0;
  auto pop = [&] {
    if (stack.empty()) return kGlLeafRef; // an empty leaf: done
    const uint32_t top = stack.back();
    stack.pop_back();
    return top;
  };
  while (true) {
    while ((current & kGlLeafRef) == 0) {
      const GlBvhNode& n = nodes[current];
      float entryA = 0, entryB = 0;
      uint32_t a = n.left, b = n.right;
      const bool hitA = a != kGlNoChild && overlaps(n.leftMin, n.leftMax, entryA);
      const bool hitB = b != kGlNoChild && overlaps(n.rightMin, n.rightMax, entryB);
      if (hitA && hitB) {
        if (entryB < entryA) std::swap(a, b);
        stack.push_back(b);
        deepest = std::max(deepest, stack.size());
        current = a;
      } else {
        current = hitA ? a : hitB ? b : pop();
      }
    }
    const uint32_t first = current & 0xffffffu, count = (current >> 24) & 0x7fu;
    for (uint32_t i = first; i < first + count; ++i)
      if (const std::optional<Hit> hit = scene.intersectBrush(ray, i)) best = std::min(best, hit->t);
    if (stack.empty()) return deepest;
    current = pop();
  }
}

// 4096 small boxes along the camera's central ray, alternately just above and just below it, one
// brush per leaf: that ray and its neighbours miss them all but pass through every node box on
// the way, so the traversal keeps more nodes on its stack than trace.glsl holds in registers
// (8) and the entries below go to shared memory and back.
TEST(GlAov, DeepStackEqualsTraceSceneClosestHit) {
  Scene scene = test::makeTestRoom();
  const CameraBasis camera = test::testCamera(kWidth, kHeight);
  for (int i = 0; i < 4096; ++i) {
    const dvec3 onRay = dvec3(camera.origin) + dvec3(camera.forward) * (60.0 + 0.05 * i);
    const dvec3 offset{0, 0, i % 2 == 0 ? 2.0 : -2.0};
    test::addBox(scene, onRay + offset - dvec3(0.5), onRay + offset + dvec3(0.5), i % 3);
  }
  const TraceScene traceScene = TraceScene::build(scene, {.leafSize = 1});
  const std::vector<GlBvhNode> nodes = bvhForGl(traceScene.nodes());
  size_t deepest = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / glm::vec2(kWidth, kHeight) * 2.0f - 1.0f;
      const glm::vec3 dir = glm::normalize(camera.forward + ndc.x * camera.right - ndc.y * camera.up);
      deepest = std::max(deepest, deepestStack(traceScene, nodes, Ray{camera.origin, 0.0f, dir}));
    }
  ASSERT_GT(deepest, 10u);
  expectFacesEqualClosestHit(scene, traceScene);
}

// A camera looking down +X with an odd image size: the middle row's and column's rays have
// zero direction components, which the box tests handle apart ("inside that slab or miss").
// From z = 40 the middle row runs exactly along the top of the box of height 40 (boundaries
// count as inside) and into the taller ones behind it.
TEST(GlAov, AxisAlignedRaysEqualTraceSceneClosestHit) {
  Scene scene = test::makeTestRoom();
  for (int i = 0; i < 40; ++i) test::addBox(scene, {-250.0 + i * 12.0, 100, 0}, {-242.0 + i * 12.0, 108, 8.0 + i}, i % 3);
  CameraBasis camera;
  camera.origin = {-252, 104, 40};
  camera.forward = {1, 0, 0};
  camera.right = {0, -1, 0};
  camera.up = {0, 0, 0.5f};
  const int width = 63, height = 31;
  ASSERT_EQ((glm::vec2(31, 15) + 0.5f) / glm::vec2(width, height) * 2.0f - 1.0f, glm::vec2(0.0f));
  expectFacesEqualClosestHit(scene, TraceScene::build(scene, {.leafSize = 1}), camera, width, height);
  expectFacesEqualClosestHit(scene, TraceScene::build(scene), camera, width, height);
  camera.origin = {-200, 50, 20};
  expectFacesEqualClosestHit(scene, TraceScene::build(scene), camera, width, height);
}

// A tree that is a single leaf has no interior node: the GL root holds it as its only child.
TEST(GlAov, OneBrushSceneEqualsTraceSceneClosestHit) {
  Scene scene;
  scene.materials = test::makeTestRoom().materials;
  test::addBox(scene, {-40, -60, 0}, {104, 4, 200}, 1);
  const TraceScene traceScene = TraceScene::build(scene);
  ASSERT_EQ(traceScene.nodes().size(), 1u);
  expectFacesEqualClosestHit(scene, traceScene);
}

} // namespace
} // namespace bt::gl
