#version 450
#extension GL_GOOGLE_include_directive : require
#ifdef BT_TEXTURES_BINDLESS
#extension GL_ARB_bindless_texture : require
#endif
// The wavefront path tracer's trace kernel (wavefront.glsl): each live pixel's ray to its hit,
// the one call of the traversal in this program. No lighting mode: the ray carries its
// pass flags, so one program serves faithful and physical shade kernels, and every level: it has
// the rule from inside (trace.glsl blocksFromInside), which the pass word keeps to faithful rays
// and the brushes' pad words to the levels that have it. Not a switch: the kernel is started
// before the level is known (TracerPrograms::startTraceKernel) and draws only while the
// megakernel compiles, where a pad-word read per exit hit costs nothing one can see.
#define BT_BLOCKS_FROM_INSIDE
#include "scene_buffers.glsl"
#include "textures.glsl" // the alpha test of trace.glsl
#include "trace.glsl"
#include "camera.glsl"
#include "wavefront.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  int slot = wavefrontSlot(dispatchPixel());
  if (slot < 0) return;
  WavefrontRay ray = wavefrontRays[slot];
  if (ray.live == 0u) return;
  Hit hit = traceRay(makeTraceRay(ray.origin, ray.dir, ray.tMin, ray.tMax), ray.anyHit != 0u, ray.passFlags);
  wavefrontHits[slot] = WavefrontHit(hit.t, hit.face, hit.inside, closestHitMasked(hit, ray.anyHit != 0u, ray.origin, ray.dir));
}
