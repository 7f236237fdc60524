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
// qbsp's CSG of overlapping liquids as a rule on hits (lighting/liquid_csg.h, LiquidCsg), for
// the levels that have them (FaithfulFeatures::liquidCsg). The rule's table follows the F face
// flags in their buffer (renderer/gl/gl_lighting.h liquidCsgTable, which spells out its
// layout); what does not depend on the hit point is answered there, so only the point's tests
// are here. The distances are in float on the face planes the tracer hits, where the CPU's are
// in the Scene's double planes: the same answers but within float rounding of the tolerance.
#include "liquid_csg_constants.glsl" // one tolerance with the CPU's rule
const float CSG_ON_PLANE = BT_LIQUID_CSG_ON_PLANE;

uint csgTable(uint i) { return faceFlags[uint(faces.length()) + i]; }
bool csgReaches(uint face) { return csgTable(face) != csgTable(face + 1u); }
bool csgOutside(uint side, vec3 p) { return dot(faces[side].plane.xyz, p) - faces[side].plane.w > CSG_ON_PLANE; }

// LiquidCsg::drawn(): whether a hit on `face` at `p`, entering its brush or `leaving` it, is
// drawn. Only for faces that csgReaches().
bool csgDrawn(uint face, vec3 p, bool leaving) {
  uint i = csgTable(face), end = csgTable(face + 1u);
  i += 1u + 2u * csgTable(i); // past the brush ranges
  bool inOtherKind = false;
  while (i < end) {
    uint head = csgTable(i), stop = i + 1u + (head >> 2);
    bool held = true;
    for (++i; i < stop && held; ++i) held = !csgOutside(csgTable(i), p);
    i = stop;
    if (!held) continue;
    if ((head & 1u) != 0u) return false; // merged into one volume: no face here
    inOtherKind = inOtherKind || (head & 2u) == 0u;
  }
  return !leaving || inOtherKind;
}

// The latest face below `bound`, other than `face`, of the hit's brush or of those that reach
// it, that holds `p` on its plane, is not hidden, and that a ray along `dir` enters: where
// LiquidCsg::keptFaceAt() looks for the face qbsp keeps at an edge. NO_FACE if none.
uint csgKeptCandidate(uint face, vec3 p, vec3 dir, uint bound) {
  uint base = csgTable(face), brushes = csgTable(base), best = NO_FACE;
  for (uint b = 0u; b < brushes; ++b) {
    uint first = csgTable(base + 1u + 2u * b), end = first + csgTable(base + 2u + 2u * b);
    bool onBrush = true;
    for (uint k = first; k < end && onBrush; ++k) onBrush = !csgOutside(k, p);
    if (!onBrush) continue;
    for (uint k = first; k < end; ++k) {
      if (k == face || k >= bound || (best != NO_FACE && k <= best) || (faceFlags[k] & FACE_HIDDEN) != 0u) continue;
      vec4 plane = faces[k].plane;
      if (abs(dot(plane.xyz, p) - plane.w) <= CSG_ON_PLANE && dot(plane.xyz, dir) < 0.0) best = k;
    }
  }
  return best;
}

// A surface ray's hit on `face` (not hidden) at `p` under the rule, as the CPU's traceVisible
// applies it: `shown` as the tracer found it (false for the far side of a brush, `inside`) in,
// whether it is drawn out; `face` becomes the face drawn in its place, if another. An entering
// hit that is not drawn tries the faces kept at its point from the latest down (keptFaceAt's
// choice, the latest that is drawn), so that drawn() has one call site: each copy of it cost
// the megakernel registers.
void liquidCsgHit(inout uint face, inout bool shown, bool inside, vec3 p, vec3 dir) {
  if (!csgReaches(face) || (!inside && !shown)) return;
  uint candidate = face;
  for (;;) { // candidates fall strictly: the loop ends
    bool drawn = !csgReaches(candidate) || csgDrawn(candidate, p, inside && candidate == face);
    if (drawn || (inside && candidate == face)) {
      shown = drawn;
      face = candidate;
      return;
    }
    candidate = csgKeptCandidate(face, p, dir, candidate == face ? NO_FACE : candidate);
    if (candidate == NO_FACE) {
      shown = false;
      return;
    }
  }
}
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
