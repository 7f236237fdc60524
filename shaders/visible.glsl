// The ray queries of lighting/visibility.h (traceVisible, occluded, reachesSky): closest hits that skip what is never drawn or never blocks light.
// Needs scene_buffers.glsl and trace.glsl.

#include "ray_offsets.glsl" // one rule with the CPU tracer (bvh/trace_scene.h)
const int MAX_SKIPS = BT_MAX_SKIPS;
const float SKIP_STEP = BT_SKIP_STEP;
const float SURFACE_OFFSET = BT_SURFACE_OFFSET;

struct SurfaceHit {
  bool found;
  float t;
  uint face;
  vec3 position;
  vec3 normal; // the face plane's, facing the ray (flipped for a liquid face seen from inside: BT_LIQUID_CSG)
};

vec3 offsetPoint(vec3 p, vec3 n) { return p + n * SURFACE_OFFSET; }
vec3 faceNormal(uint face) { return faces[face].plane.xyz; }

#ifdef BT_LIQUID_CSG
#include "liquid_csg.glsl" // liquidCsgHit
#endif

SurfaceHit traceVisibleFrom(vec3 origin, vec3 dir, float tMin) {
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceRay(makeTraceRay(origin, dir, tMin, INFINITY), false, 0u);
    if (hit.face == NO_FACE) break;
#ifdef BT_LIQUID_CSG
    vec3 position = origin + dir * hit.t;
    bool hidden = (faceFlags[hit.face] & FACE_HIDDEN) != 0u;
    bool shown = !hit.inside && !maskedOut(hit.face, position) && !hidden;
    uint face = hit.face;
    if (!hidden) liquidCsgHit(face, shown, hit.inside, position, dir);
    // A liquid face seen from inside is its mirrored face, facing the ray.
    if (shown) return SurfaceHit(true, hit.t, face, position, hit.inside ? -faceNormal(face) : faceNormal(face));
#else
    if (!hit.inside && !maskedOut(hit.face, origin + dir * hit.t) && (faceFlags[hit.face] & FACE_HIDDEN) == 0u)
      return SurfaceHit(true, hit.t, hit.face, origin + dir * hit.t, faceNormal(hit.face));
#endif
    tMin = hit.t + SKIP_STEP;
  }
  return SurfaceHit(false, 0.0, NO_FACE, vec3(0.0), vec3(0.0));
}
SurfaceHit traceVisible(vec3 origin, vec3 dir) { return traceVisibleFrom(origin, dir, 0.0); }

// The pass word (trace.glsl blocksRay) of a ray on lighting channels `channels` (lighting
// blocksLight): light passes hidden faces and liquids, in faithful mode brush entities without
// _shadow and faces on none of the ray's channels; physical mode knows no channels.
uint shadowPassFlags(bool physical, uint channels) {
  uint classes = FACE_HIDDEN | FACE_LIQUID | (physical ? 0u : FACE_NO_SHADOW);
  return classes | (physical ? FACE_ANY_CHANNEL : (channels << FACE_CHANNEL_SHIFT) & FACE_CHANNEL_BITS);
}
// ... of the rays of suns, domes, dirt and every light on the default channel.
uint lightPassFlags(bool physical) { return shadowPassFlags(physical, DEFAULT_CHANNELS); }
bool blocksLight(uint flags, bool physical) { return blocksRay(flags, lightPassFlags(physical)); }
// The channels a face is on (its object mask; RenderScene::faceChannels).
uint faceChannels(uint face) { return (faceFlags[face] & FACE_CHANNEL_BITS) >> FACE_CHANNEL_SHIFT; }

// Any blocker on the segment: one any-hit traversal, stopping at the first.
bool occluded(vec3 origin, vec3 dir, float tMax, bool physical) {
  return traceRay(makeTraceRay(origin, dir, 0.0, tMax), true, lightPassFlags(physical)).face != NO_FACE;
}

bool reachesSky(vec3 origin, vec3 dir, bool physical) {
  float tMin = 0.0;
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceRay(makeTraceRay(origin, dir, tMin, INFINITY), false, 0u);
    if (hit.face == NO_FACE) return true; // left the level: nothing stops the sun
    uint flags = faceFlags[hit.face];
    bool through = hit.inside || maskedOut(hit.face, origin + dir * hit.t);
    if (!through && (flags & FACE_SKY) != 0u) return true;
    if (!through && blocksLight(flags, physical)) return false;
    tMin = hit.t + SKIP_STEP;
  }
  return false;
}
