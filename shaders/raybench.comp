#version 450
#extension GL_GOOGLE_include_directive : require
#include "gl_bindings.glsl"
#ifdef BT_TEXTURES_BINDLESS
#extension GL_ARB_bindless_texture : require
#endif
// Ray throughput for `brushtrace bench`: closest hits only, no shading.
//   mode 0: one primary ray through each pixel (coherent);
//   mode 1: from each pixel's primary hit, one cosine-distributed bounce ray (incoherent),
//           the kind the integrator spends most of its time on. Only the bounce rays are timed
//           apart: the primary hit is read from the image mode 0 wrote;
//   mode 2: the same bounce rays as shadow rays: any-hit queries of at most `shadowLength`,
//           passing what physical mode's light passes (visible.glsl lightPassFlags(true)).
// BT_RB_VARIANT (gl_bench's `variant`, with trace.glsl's BT_RB_* switches): a measurement of
// part of the walk. Its results go to bounceT only, in every mode, so that the hits image keeps
// the plain program's primary hits, where the bounce rays start. BT_RB_NO_WALK: the ray is made
// and a result written, no walk; BT_RB_GROUP_X / _Y: another work group shape.
#include "scene_buffers.glsl"
#include "trace.glsl"
#include "camera.glsl"
#include "sampling.glsl"
#include "ray_offsets.glsl"

#ifndef BT_RB_GROUP_X
layout(local_size_x = 8, local_size_y = 8) in;
#endif
// A point of its own (gl_buffer_bindings_test.cpp), named here only: GlTracer asks the program.
#define BT_BINDING_RAYBENCH_COUNTS 16
#ifdef BT_RB_COUNT
// Per mode 16 words: for each of trace.glsl's walkCounts and walkDeepest, the sum and the maximum.
layout(std430, binding = BT_BINDING_RAYBENCH_COUNTS) buffer RayBenchCounts { uint rayBenchCounts[]; };
#endif
layout(rgba32f, binding = BT_IMAGE_PRIMARY_HITS) uniform image2D hits; // xyz: primary hit point, w: face + 1 (0 = miss)
layout(r32f, binding = BT_IMAGE_BOUNCE_T) uniform writeonly image2D bounceT;

layout(location = 0) uniform uint mode;
layout(location = 1) uniform float shadowLength;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, camera.imageSize))) return;
  vec3 origin = camera.origin;
  vec3 dir = cameraRayDirection(vec2(pixel) + 0.5);
  if (mode != 0u) {
    vec4 primary = imageLoad(hits, pixel);
    if (primary.w == 0.0) return;
    vec3 n = faces[uint(primary.w) - 1u].plane.xyz;
    Rng rng = pixelRng(uint(pixel.x), uint(pixel.y), camera.frameIndex, camera.seed);
    origin = primary.xyz + n * BT_SURFACE_OFFSET;
    dir = sampleCosineHemisphere(n, rngNext2(rng));
  }
  // One call site of the traversal for every mode (trace.glsl says why).
  bool shadow = mode == 2u;
  uint passFlags = shadow ? FACE_HIDDEN | FACE_LIQUID | FACE_ANY_CHANNEL : 0u;
#ifdef BT_RB_NO_WALK
  TraceRay r = makeTraceRay(origin, dir, 0.0, shadow ? shadowLength : INFINITY);
  Hit hit = Hit(dot(r.invDir, r.origin) + r.tMax, passFlags, r.hasZero);
#else
  Hit hit = traceRay(makeTraceRay(origin, dir, 0.0, shadow ? shadowLength : INFINITY), shadow, passFlags);
#endif
#ifdef BT_RB_COUNT
  uint base = 16u * mode;
  uint counted[5] = uint[5](walkCounts.x, walkCounts.y, walkCounts.z, walkCounts.w, walkDeepest);
  for (uint i = 0u; i < 5u; ++i) {
    atomicAdd(rayBenchCounts[base + 2u * i], counted[i]);
    atomicMax(rayBenchCounts[base + 2u * i + 1u], counted[i]);
  }
#endif
#ifdef BT_RB_VARIANT
  imageStore(bounceT, pixel, vec4(hit.t + float(hit.face) + (hit.inside ? 1.0 : 0.0)));
  return;
#endif
  if (mode == 0u) imageStore(hits, pixel, vec4(origin + dir * hit.t, hit.face == NO_FACE ? 0.0 : float(hit.face + 1u)));
  else if (!shadow) imageStore(bounceT, pixel, vec4(hit.t));
  else if (hit.face != NO_FACE) imageStore(bounceT, pixel, vec4(-hit.t)); // kept, so the query is not optimised away
}
