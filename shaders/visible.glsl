// The integrator's ray queries (renderer/cpu/integrator.cpp traceVisible, occluded,
// reachesSky): closest hits that skip what is never drawn or never blocks light.
// Needs scene_buffers.glsl and trace.glsl.

const int MAX_SKIPS = 64;        // hidden faces / inside hits skipped along one ray
const float SKIP_STEP = 1e-3;    // past a skipped hit, as the CPU reference
const float SURFACE_OFFSET = 0.03; // rays leave surfaces this far along the normal

struct SurfaceHit {
  bool found;
  float t;
  uint face;
  vec3 position;
  vec3 normal; // the face plane's
};

vec3 offsetPoint(vec3 p, vec3 n) { return p + n * SURFACE_OFFSET; }

SurfaceHit traceVisible(vec3 origin, vec3 dir) {
  float tMin = 0.0;
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceClosest(origin, dir, tMin, 3.0e38);
    if (hit.face == NO_FACE) break;
    if (!hit.inside && (faces[hit.face].flags & FACE_HIDDEN) == 0u)
      return SurfaceHit(true, hit.t, hit.face, origin + dir * hit.t, faces[hit.face].normal);
    tMin = hit.t + SKIP_STEP;
  }
  return SurfaceHit(false, 0.0, NO_FACE, vec3(0.0), vec3(0.0));
}

bool blocksLight(uint faceFlags, bool physical) {
  if ((faceFlags & (FACE_HIDDEN | FACE_LIQUID)) != 0u) return false;
  if (!physical && (faceFlags & FACE_NO_SHADOW) != 0u) return false;
  return true;
}

bool occluded(vec3 origin, vec3 dir, float tMax, bool physical) {
  float tMin = 0.0;
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceClosest(origin, dir, tMin, tMax);
    if (hit.face == NO_FACE) return false;
    if (!hit.inside && blocksLight(faces[hit.face].flags, physical)) return true;
    tMin = hit.t + SKIP_STEP;
  }
  return true;
}

bool reachesSky(vec3 origin, vec3 dir, bool physical) {
  float tMin = 0.0;
  for (int i = 0; i < MAX_SKIPS; ++i) {
    Hit hit = traceClosest(origin, dir, tMin, 3.0e38);
    if (hit.face == NO_FACE) return true; // left the level: nothing stops the sun
    uint flags = faces[hit.face].flags;
    if (!hit.inside && (flags & FACE_SKY) != 0u) return true;
    if (!hit.inside && blocksLight(flags, physical)) return false;
    tMin = hit.t + SKIP_STEP;
  }
  return false;
}
