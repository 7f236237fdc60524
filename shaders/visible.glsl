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
// flags in their buffer (renderer/gl/gl_lighting.h liquidCsgTable), offsets counted from F:
//   [0, F]:  per face f, where its entries begin; face f's are [table[f], table[f + 1]), none
//            where no other liquid brush reaches its brush;
//   entries: uvec2 per brush: its faces' first, then their count << 1 | same kind; a face's
//            own brush first, then the liquid brushes that reach it.
// In float on the face planes the tracer hits, where the CPU's is in the Scene's double planes:
// the same answers but within float rounding of the tolerances.
#include "liquid_csg_constants.glsl" // one pair of tolerances with the CPU's rule
const float CSG_ON_PLANE = BT_LIQUID_CSG_ON_PLANE;
const float CSG_NORMAL = BT_LIQUID_CSG_NORMAL;
const uint CSG_NO = 0u, CSG_TOUCHING = 1u, CSG_INSIDE = 2u;

uint csgTable(uint i) { return faceFlags[uint(faces.length()) + i]; }
uvec2 csgEntries(uint face) { return uvec2(csgTable(face), csgTable(face + 1u)); } // [begin, end)
float csgDistance(uint face, vec3 p) { return dot(faces[face].plane.xyz, p) - faces[face].plane.w; }
bool csgSamePlane(vec4 a, vec4 b) { return dot(a.xyz, b.xyz) > 1.0 - CSG_NORMAL && abs(a.w - b.w) <= CSG_ON_PLANE; }

// LiquidCsg's holds(): where `p`, on plane `plane` of another brush, lies against the brush of
// faces [first, first + count).
uint csgHolds(uint first, uint count, vec4 plane, vec3 p) {
  bool touching = false;
  for (uint k = first; k < first + count; ++k) {
    vec4 side = faces[k].plane;
    if (csgSamePlane(side, plane)) return CSG_NO;
    if (csgSamePlane(side, -plane)) {
      touching = true;
      continue;
    }
    if (csgDistance(k, p) > CSG_ON_PLANE) return CSG_NO;
  }
  return touching ? CSG_TOUCHING : CSG_INSIDE;
}

// LiquidCsg::drawn(): whether a hit on `face` at `p`, entering its brush or `leaving` it, is
// drawn. Only for faces with entries.
bool csgDrawn(uint face, vec3 p, bool leaving) {
  vec4 plane = faces[face].plane;
  uvec2 range = csgEntries(face);
  bool inOtherKind = false;
  for (uint i = range.x + 2u; i < range.y; i += 2u) { // past the face's own brush
    uint word = csgTable(i + 1u);
    uint h = csgHolds(csgTable(i), word >> 1, plane, p);
    if (h == CSG_NO) continue;
    if ((word & 1u) != 0u) return false; // merged into one volume: no face here
    inOtherKind = inOtherKind || h == CSG_INSIDE;
  }
  return !leaving || inOtherKind;
}

// LiquidCsg::keptFaceAt(): for an entering hit that csgDrawn() removes, the face qbsp keeps at
// `p` that a ray along `dir` enters there, of the hit's brush or those that reach it (the later
// in the file, as the tracer's tie rule picks); NO_FACE in the middle of a removed face.
uint csgKeptFaceAt(uint face, vec3 p, vec3 dir) {
  uint kept = NO_FACE;
  uvec2 range = csgEntries(face);
  for (uint i = range.x; i < range.y; i += 2u) {
    uint first = csgTable(i), count = csgTable(i + 1u) >> 1;
    bool onBrush = true;
    for (uint k = first; k < first + count; ++k) onBrush = onBrush && !(csgDistance(k, p) > CSG_ON_PLANE);
    if (!onBrush) continue;
    for (uint k = first; k < first + count; ++k) {
      if (k == face || (faceFlags[k] & FACE_HIDDEN) != 0u || abs(csgDistance(k, p)) > CSG_ON_PLANE ||
          dot(faces[k].plane.xyz, dir) >= 0.0)
        continue;
      uvec2 own = csgEntries(k);
      if ((kept == NO_FACE || k > kept) && (own.x == own.y || csgDrawn(k, p, false))) kept = k;
    }
  }
  return kept;
}

// A surface ray's hit on `face` (not hidden) at `p` under the rule, as the CPU's traceVisible
// applies it: `shown` as the tracer found it (false for the far side of a brush, `inside`) in,
// whether it is drawn out; `face` becomes the face drawn in its place, if another.
void liquidCsgHit(inout uint face, inout bool shown, bool inside, vec3 p, vec3 dir) {
  uvec2 range = csgEntries(face);
  if (range.x == range.y) return;
  if (inside) {
    shown = csgDrawn(face, p, true);
  } else if (shown && !csgDrawn(face, p, false)) {
    uint kept = csgKeptFaceAt(face, p, dir);
    shown = kept != NO_FACE;
    if (shown) face = kept;
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
