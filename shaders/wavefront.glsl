// The wavefront form of the path tracer: the megakernel's loop (pathtrace.comp: trace a ray,
// advance() the path) cut at the traversal into two programs, so that the driver compiles two
// small programs in parallel instead of one large one, in about a third of its time on NVIDIA:
//   pathtrace.comp with BT_WAVEFRONT_SHADE: the camera ray, advance() and the accumulation;
//   wavefront_trace.comp: the traversal, one ray per pixel to one hit per pixel.
// renderer/gl/gl_tracer.cpp dispatches shade, then trace and shade by turns until no path is
// live, and draws with them while the megakernel still compiles. One slot per pixel, index
// y * width + x; the path's own state (Path, Rng) is in pathtrace.comp's WavefrontPaths.

// The ray a pixel's path waits for, as the megakernel passes it to traceRay.
#include "gl_bindings.glsl"
struct WavefrontRay {
  vec3 origin;
  float tMin;
  vec3 dir;
  float tMax;
  uint anyHit;    // 1: a shadow ray (any hit)
  uint passFlags; // the traversal's pass word (visible.glsl shadowPassFlags)
  uint live;      // 0: the path has ended (or the pixel has none): nothing to trace or shade
};

layout(std430, binding = BT_BINDING_WAVEFRONT_RAYS) buffer WavefrontRays { WavefrontRay wavefrontRays[]; };
// The trace kernel's Hit, and its alpha test (trace.glsl closestHitMasked) done there.
struct WavefrontHit {
  float t;
  uint face;
  bool inside;
  bool masked;
};
layout(std430, binding = BT_BINDING_WAVEFRONT_HITS) buffer WavefrontHits { WavefrontHit wavefrontHits[]; };
// Paths ended in this sample: the host clears it at the start and stops when all have ended.
// (One atomic per path, not one per live path and round.)
layout(std430, binding = BT_BINDING_WAVEFRONT_ENDED_COUNT) buffer WavefrontEndedCount { uint wavefrontEnded; };

// The pixel's slot, or -1 outside the image (the dispatch covers whole 8 x 8 groups).
int wavefrontSlot(ivec2 pixel) {
  if (any(greaterThanEqual(pixel, camera.imageSize))) return -1;
  return pixel.y * camera.imageSize.x + pixel.x;
}
