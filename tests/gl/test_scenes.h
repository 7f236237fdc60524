// Hand-built scenes for the GL tests: boxes and a wedge with known planes and textures, plus a
// double-precision brute-force ray caster as the reference the GPU images are compared with.
#pragma once

#include "renderer/gl/gl_tracer.h"
#include "scene/scene.h"
#include "tests/support/scene_builder.h"

namespace bt::test {

// The brush of the given outward planes with the given bounds (tests/support/scene_builder.h),
// every face of `material`; a box's faces +X, -X, +Y, -Y, +Z, -Z.
void addBrush(Scene& scene, const std::vector<Plane>& planes, const Bounds& bounds, uint32_t material);
void addBox(Scene& scene, dvec3 min, dvec3 max, uint32_t material);

// A room (floor, ceiling, four walls) 512 x 512 x 256 around the origin, a pillar, a wedge
// with sloped faces, and three materials: a 4x4 texel checker of distinct colours (size 64),
// a 2x1 two-colour texture (size 32x16) and one without texture.
Scene makeTestRoom();
gl::CameraBasis testCamera(int width, int height);

// A wall of 24 boxes side by side facing -X, each textured with its own image size (4 to 32 texels wide, 4 to
// 20 tall: more sizes than the texture-array path has arrays, kMaxTextureArrays), every texel a
// different colour and each texture repeating across its face. manyTextureSizesCamera looks at
// it from -X, the boxes filling most of a 3:2 view.
Scene makeManyTextureSizesWall();
gl::CameraBasis manyTextureSizesCamera(int width, int height);

// The texture path the GL tests render with: $BT_GL_TEXTURES (bindless, arrays or auto),
// auto when unset. scripts/gpu-check.sh forces bindless on the GPU and arrays after it.
gl::TextureMode textureModeUnderTest();

// One headless context for the whole test program, made on first use: a context per test
// would spend the GPU driver's start-up (seconds on NVIDIA) again and again.
gl::GlContext& sharedGlContext();

// The reference: each pixel's ray (the CameraBasis formula in double) against every brush.
gl::AovImages referenceAovs(const Scene& scene, const gl::CameraBasis& camera, int width, int height);

} // namespace bt::test
