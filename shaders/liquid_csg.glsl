// qbsp's CSG of overlapping liquids as a rule on surface rays' hits (lighting/liquid_csg.h,
// LiquidCsg), for the levels that have them (FaithfulFeatures::liquidCsg): in visible.glsl for
// the megakernel and the AOVs, and in the wavefront trace kernel, which applies it for the shade
// kernel (wavefront_trace.comp). Needs scene_buffers.glsl and trace.glsl. The rule's table
// follows the face flags in their buffer (renderer/gl/gl_lighting.h liquidCsgTable, which spells
// out its layout); what does not depend on the hit point is answered there, so only the point's
// tests are here. The distances are in float on the face planes the tracer hits, where the CPU's
// are in the Scene's double planes: the same answers but within float rounding of the tolerance.
#ifndef BT_LIQUID_CSG_GLSL
#define BT_LIQUID_CSG_GLSL
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
