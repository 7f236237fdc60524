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
#include "liquid_csg.glsl" // liquidCsgHit, for WAVEFRONT_CSG rays
#include "lightmaps.glsl"  // lightmapValue, for WAVEFRONT_LUXELS rays
#include "camera.glsl"
#include "wavefront.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  int slot = wavefrontSlot(dispatchPixel());
  if (slot < 0) return;
  WavefrontRay ray = wavefrontRays[slot];
  if (ray.live == 0u) return;
  bool anyHit = (ray.query & WAVEFRONT_ANY_HIT) != 0u;
  Hit hit = traceRay(makeTraceRay(ray.origin, ray.dir, ray.tMin, ray.tMax), anyHit, ray.passFlags);
  bool masked = closestHitMasked(hit, anyHit, ray.origin, ray.dir);
  // What the megakernel does with a surface ray's hit in advance() and faithfulSurface(), here
  // for the shade kernel (wavefront.glsl WAVEFRONT_*): this kernel is linked well before it.
  vec3 position = ray.origin + ray.dir * hit.t;
  uint face = hit.face;
  if ((ray.query & WAVEFRONT_CSG) != 0u && face != NO_FACE && (faceFlags[face] & FACE_HIDDEN) == 0u) {
    bool shown = !hit.inside && !masked;
    liquidCsgHit(face, shown, hit.inside, position, ray.dir);
    masked = !shown;
  }
  vec3 luxels = vec3(0.0);
  bool baked = false;
  if ((ray.query & WAVEFRONT_LUXELS) != 0u && face != NO_FACE && !masked) {
    uvec2 range = lightmapRange(face);
    if (range.y > 0u) {
      GpuFace f = faces[face];
      vec3 d = position - f.origin;
      luxels = lightmapValue(range, vec2(dot(d, f.tangent), dot(d, f.bitangent)));
      baked = true;
    }
  }
  wavefrontHits[slot] = WavefrontHit(hit.t, face, hit.inside, masked, luxels, baked);
}
