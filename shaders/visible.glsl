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
  vec3 normal; // the face plane's
};

vec3 offsetPoint(vec3 p, vec3 n) { return p + n * SURFACE_OFFSET; }
vec3 faceNormal(uint face) { return faces[face].plane.xyz; }

SurfaceHit traceVisible(vec3 origin, vec3 dir) {
  float tMin = 0.0;
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceRay(makeTraceRay(origin, dir, tMin, INFINITY), false, 0u);
    if (hit.face == NO_FACE) break;
    if (!hit.inside && !maskedOut(hit.face, origin + dir * hit.t) && (faceFlags[hit.face] & FACE_HIDDEN) == 0u)
      return SurfaceHit(true, hit.t, hit.face, origin + dir * hit.t, faceNormal(hit.face));
    tMin = hit.t + SKIP_STEP;
  }
  return SurfaceHit(false, 0.0, NO_FACE, vec3(0.0), vec3(0.0));
}

// The face classes light passes through (lighting blocksLight): hidden faces and liquids,
// and in faithful mode brush entities without _shadow.
uint lightPassFlags(bool physical) { return FACE_HIDDEN | FACE_LIQUID | (physical ? 0u : FACE_NO_SHADOW); }
bool blocksLight(uint flags, bool physical) { return (flags & lightPassFlags(physical)) == 0u; }

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
