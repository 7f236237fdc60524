// How rays leave surfaces, one rule for both tracers: bvh/trace_scene.h includes this file as C++
// and shaders/visible.glsl as GLSL. Hence only #defines of integer and float literals (with the f suffix),
// which both languages read alike (GLSL since 1.30).
#ifndef BT_RAY_OFFSETS
#define BT_RAY_OFFSETS

// A secondary ray starts this far from its surface along the face's normal. A hit point's
// rounding error is a few float ulps of its largest coordinate: 0.03 is about 8 ulps at 32768,
// the largest coordinate a BSP2 or Quake 3 level reaches, and far under a texel anywhere.
#define BT_SURFACE_OFFSET 0.03f

// A ray that skips a hit (a face never drawn, a hole, a liquid for shadows) goes on from this far
// past it, so that the face it skipped is not met again.
#define BT_SKIP_STEP 1e-3f

// A ray gives up after skipping this many hits (hidden faces, far sides of brushes it starts in,
// holes): a bound on the walk, far above what a level needs.
#define BT_MAX_SKIPS 64

#endif
