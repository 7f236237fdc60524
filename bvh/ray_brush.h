// The ray queries' kernels, shared by TraceScene's single-ray walks (trace_scene.cpp) and its
// packet walk (ray_packet.cpp), so that both run the same float expressions: the rules are
// trace_scene.h's. Internal to bvh/.
#pragma once

#include "bvh/trace_scene.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <span>

namespace bt::trace_detail {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The ray's parameter interval inside a box, [near, far]; near > far when it misses. The same
// float expressions serve nodes and brush boxes, so a node's interval always contains those
// of the brush boxes below it (rounding is monotonic), which is what lets the BVH agree with
// a brute-force loop exactly.
struct Slab {
  float near, far;
  int nearAxis, farAxis; // the axis that set near/far, -1 if none did
};

// ZeroSafe = false is the fast path for rays without zero direction components.
template <bool ZeroSafe> [[gnu::always_inline]] inline Slab intersectBox(const RayContext& r, const float* boxMin, const float* boxMax) {
  Slab s{-kInfinity, kInfinity, -1, -1};
  for (int a = 0; a < 3; ++a) {
    if (ZeroSafe && r.direction[a] == 0.0f) {
      if (r.origin[a] < boxMin[a] || r.origin[a] > boxMax[a]) return {kInfinity, -kInfinity, -1, -1};
      continue;
    }
    const float* nearSide = r.negative[a] ? boxMax : boxMin;
    const float* farSide = r.negative[a] ? boxMin : boxMax;
    const float tNear = (nearSide[a] - r.origin[a]) * r.invDirection[a];
    const float tFar = (farSide[a] - r.origin[a]) * r.invDirection[a];
    if (tNear > s.near) s.near = tNear, s.nearAxis = a;
    if (tFar < s.far) s.far = tFar, s.farAxis = a;
  }
  return s;
}

#if BT_SSE_NODE_TEST
// A box's interval [near, far] as intersectBox<false> gives its values, the three axes at once,
// lane by lane the scalar expressions (min/max of the two slab planes picks the value
// intersectBox picks by the direction's sign). `boxMin` and `boxMax` are each followed by a
// fourth word (GpuBvhNode, GpuBrush: an index or count, a denormal as a float, slow to compute
// with), masked to 0 first.
[[gnu::always_inline]] inline void boxInterval(const RayContext& r, const float* boxMin, const float* boxMax, float& near, float& far) {
  const __m128 keep = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
  const __m128 lo = _mm_and_ps(_mm_loadu_ps(boxMin), keep), hi = _mm_and_ps(_mm_loadu_ps(boxMax), keep);
  const __m128 t0 = _mm_mul_ps(_mm_sub_ps(lo, r.origin4), r.invDirection4);
  const __m128 t1 = _mm_mul_ps(_mm_sub_ps(hi, r.origin4), r.invDirection4);
  const __m128 lower = _mm_min_ps(t0, t1), upper = _mm_max_ps(t0, t1);
  near = _mm_cvtss_f32(_mm_max_ss(_mm_max_ss(lower, _mm_shuffle_ps(lower, lower, 1)), _mm_shuffle_ps(lower, lower, 2)));
  far = _mm_cvtss_f32(_mm_min_ss(_mm_min_ss(upper, _mm_shuffle_ps(upper, upper, 1)), _mm_shuffle_ps(upper, upper, 2)));
}
#endif

// Whether a node can hold a hit with t in (tMin, tLimit]. Inclusive at tLimit so that a brush
// hit at exactly the best t so far is still found and the tie-break (closer) applies.
template <bool ZeroSafe>
[[gnu::always_inline]] inline bool nodeOverlaps(const RayContext& r, const GpuBvhNode& node, float tLimit, float& near) {
  float far;
  if constexpr (ZeroSafe) {
    const Slab s = intersectBox<true>(r, node.boundsMin, node.boundsMax);
    near = s.near, far = s.far;
  } else {
#if BT_SSE_NODE_TEST
    boxInterval(r, node.boundsMin, node.boundsMax, near, far);
#else
    // The same per-axis values as intersectBox (min/max of the two slab planes picks the one
    // intersectBox picks by the direction's sign), without the bookkeeping of which axis won.
    const float x0 = (node.boundsMin[0] - r.origin.x) * r.invDirection.x, x1 = (node.boundsMax[0] - r.origin.x) * r.invDirection.x;
    const float y0 = (node.boundsMin[1] - r.origin.y) * r.invDirection.y, y1 = (node.boundsMax[1] - r.origin.y) * r.invDirection.y;
    const float z0 = (node.boundsMin[2] - r.origin.z) * r.invDirection.z, z1 = (node.boundsMax[2] - r.origin.z) * r.invDirection.z;
    near = std::max({std::min(x0, x1), std::min(y0, y1), std::min(z0, z1)});
    far = std::min({std::max(x0, x1), std::max(y0, y1), std::max(z0, z1)});
#endif
  }
  return std::max(near, r.tMin) <= std::min(far, tLimit) && near <= far;
}

// The closest-hit order (trace_scene.h): smaller t; at equal t a hit entering its brush before
// one leaving its brush (a ray that leaves a liquid where it meets a wall stops at the wall),
// then the later brush, as qbsp's CSG keeps the later of two overlapping brushes' coplanar faces.
inline bool closer(const Hit& hit, const Hit& best) {
  if (hit.t != best.t) return hit.t < best.t;
  if (best.face == kNoFace) return true;
  if (hit.inside != best.inside) return !hit.inside;
  return hit.face > best.face;
}

// The box slabs of a brush, as intersectBox() computes them, plus which axis set near/far.
// When two axes give the same t (the ray meets an edge exactly), the one the ray meets more
// head-on (larger |d|) takes it: the hidden face between two neighbouring brushes is always
// the one met at a glancing angle by rays that reach their shared edge from the open side.
template <bool ZeroSafe> [[gnu::always_inline]] inline Slab brushBox(const RayContext& r, const GpuBrush& brush) {
  Slab s{-kInfinity, kInfinity, -1, -1};
  for (int a = 0; a < 3; ++a) {
    if (ZeroSafe && r.direction[a] == 0.0f) {
      if (r.origin[a] < brush.boundsMin[a] || r.origin[a] > brush.boundsMax[a]) return {kInfinity, -kInfinity, -1, -1};
      continue;
    }
    const float* nearSide = r.negative[a] ? brush.boundsMax : brush.boundsMin;
    const float* farSide = r.negative[a] ? brush.boundsMin : brush.boundsMax;
    const float tNear = (nearSide[a] - r.origin[a]) * r.invDirection[a];
    const float tFar = (farSide[a] - r.origin[a]) * r.invDirection[a];
    const float facing = std::abs(r.direction[a]);
    if (tNear > s.near || (tNear == s.near && s.nearAxis >= 0 && facing > std::abs(r.direction[s.nearAxis])))
      s.near = tNear, s.nearAxis = a;
    if (tFar < s.far || (tFar == s.far && s.farAxis >= 0 && facing > std::abs(r.direction[s.farAxis]))) s.far = tFar, s.farAxis = a;
  }
  return s;
}

#if BT_SSE_NODE_TEST
// The axis of `axes` (a bit per axis) that brushBox's tie rule keeps: the one the ray meets most
// head-on, the earliest of equals.
[[gnu::always_inline]] inline int headOnAxis(const RayContext& r, int axes) {
  int best = std::countr_zero(unsigned(axes));
  if ((axes & (axes - 1)) == 0) return best; // one axis: no tie (nearly every ray)
  for (int a = best + 1; a < 3; ++a)
    if ((axes >> a) & 1 && std::abs(r.direction[a]) > std::abs(r.direction[best])) best = a;
  return best;
}

// brushBox<false>, bit for bit, from the box's slabs in one register each, or false where
// hitBrush rejects the box on its interval (it misses, or lies outside (tMin, tMax) or beyond
// tLimit): most brushes of a leaf the ray reaches do. A slab's lane min(t0, t1) is brushBox's
// tNear of that axis (the sign of d picks the smaller; a brush box has thickness, so the two are
// never zeros of both signs), max(t0, t1) its tFar; near is the largest lane and nearAxis the
// lane brushBox's tie rule keeps among those equal to it (far and farAxis alike). brushBox keeps
// no axis for a value it never passes: near at -inf, far at +inf.
[[gnu::always_inline]] inline bool brushBoxLanes(const RayContext& r, const GpuBrush& brush, float tLimit, Slab& box) {
  const __m128 keep = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
  const __m128 lo = _mm_and_ps(_mm_loadu_ps(brush.boundsMin), keep), hi = _mm_and_ps(_mm_loadu_ps(brush.boundsMax), keep);
  const __m128 t0 = _mm_mul_ps(_mm_sub_ps(lo, r.origin4), r.invDirection4);
  const __m128 t1 = _mm_mul_ps(_mm_sub_ps(hi, r.origin4), r.invDirection4);
  const __m128 lower = _mm_min_ps(t0, t1), upper = _mm_max_ps(t0, t1);
  const float near = _mm_cvtss_f32(_mm_max_ss(_mm_max_ss(lower, _mm_shuffle_ps(lower, lower, 1)), _mm_shuffle_ps(lower, lower, 2)));
  const float far = _mm_cvtss_f32(_mm_min_ss(_mm_min_ss(upper, _mm_shuffle_ps(upper, upper, 1)), _mm_shuffle_ps(upper, upper, 2)));
  if (near > far || far <= r.tMin || near >= r.tMax || near > tLimit) return false;
  alignas(16) float nears[4], fars[4];
  _mm_store_ps(nears, lower);
  _mm_store_ps(fars, upper);
  const int nearAxes = _mm_movemask_ps(_mm_cmpeq_ps(lower, _mm_set1_ps(near))) & 7;
  const int farAxes = _mm_movemask_ps(_mm_cmpeq_ps(upper, _mm_set1_ps(far))) & 7;
  box.nearAxis = near == -kInfinity ? -1 : headOnAxis(r, nearAxes);
  box.farAxis = far == kInfinity ? -1 : headOnAxis(r, farAxes);
  box.near = box.nearAxis >= 0 ? nears[box.nearAxis] : -kInfinity;
  box.far = box.farAxis >= 0 ? fars[box.farAxis] : kInfinity;
  return true;
}
#endif

// A plane crossing candidate: t, the face, and how head-on the ray meets it (|dot(n, d)|).
struct Crossing {
  float t;
  uint32_t face = kNoFace;
  float facing = 0.0f;
};

// Haines' clip against one brush; the contract is spelled out in trace_scene.h. A brush whose
// box starts beyond tLimit (the closest hit so far) is rejected before its planes are read:
// its hit could only be farther (a hit at exactly tLimit still competes in the tie-break).
template <bool ZeroSafe> inline bool hitBrush(const RayContext& r, const GpuBrush& brush, std::span<const uint32_t> sides,
                                              std::span<const GpuFace> faces, float tLimit, Hit& hit) {
  Slab box;
#if BT_SSE_NODE_TEST
  if constexpr (!ZeroSafe) {
    if (!brushBoxLanes(r, brush, tLimit, box)) return false;
  } else
#endif
  {
    box = brushBox<ZeroSafe>(r, brush);
    if (box.near > box.far || box.far <= r.tMin || box.near >= r.tMax || box.near > tLimit) return false;
  }

  Crossing enter{-kInfinity}, exit{kInfinity};
  const float near0 = std::max(box.near, r.tMin);
  for (uint32_t i = brush.firstSide; i < brush.firstSide + brush.sideCount; ++i) {
    const GpuFace& f = faces[sides[i]];
    const float denom = f.plane[0] * r.direction.x + f.plane[1] * r.direction.y + f.plane[2] * r.direction.z;
    const float dist = f.plane[0] * r.origin.x + f.plane[1] * r.origin.y + f.plane[2] * r.origin.z - f.plane[3];
    if (denom < 0.0f) { // crossing from front to back: entering
      const float t = -dist / denom;
      if (t > enter.t || (t == enter.t && -denom > enter.facing)) enter = {t, sides[i], -denom};
    } else if (denom > 0.0f) { // leaving
      const float t = -dist / denom;
      if (t < exit.t || (t == exit.t && denom > exit.facing)) exit = {t, sides[i], denom};
    } else if (dist > 0.0f) {
      return false; // parallel and in front: never inside
    }
    if (std::max(near0, enter.t) > std::min(box.far, exit.t)) return false;
  }

  // Merge the box sides (those with an axial face) into the slanted candidates, same rule.
  if (box.nearAxis >= 0) {
    const Crossing side{box.near, brush.axialFace[2 * box.nearAxis + r.negative[box.nearAxis]], std::abs(r.direction[box.nearAxis])};
    if (side.t > enter.t || (side.t == enter.t && side.face != kNoFace && side.facing >= enter.facing)) {
      // A box side without an axial face only touches the brush in an edge: the slanted plane
      // the ray crosses there keeps the face, the box keeps the (larger, conservative) t.
      enter = {side.t, side.face != kNoFace ? side.face : enter.face, side.facing};
    }
  }
  if (box.farAxis >= 0) {
    const Crossing side{box.far, brush.axialFace[2 * box.farAxis + 1 - r.negative[box.farAxis]], std::abs(r.direction[box.farAxis])};
    if (side.t < exit.t || (side.t == exit.t && side.face != kNoFace && side.facing >= exit.facing))
      exit = {side.t, side.face != kNoFace ? side.face : exit.face, side.facing};
  }
  if (enter.t > exit.t) return false;
  if (enter.t > r.tMin) {
    if (!(enter.t < r.tMax)) return false;
    hit.t = enter.t;
    hit.face = enter.face;
    hit.inside = false;
  } else {
    if (!(exit.t > r.tMin && exit.t < r.tMax)) return false;
    hit.t = exit.t;
    hit.face = exit.face;
    hit.inside = true;
  }
  // Only a brush whose planes and box disagree (a broken winding) can leave no face here.
  if (hit.face == kNoFace) return false;
  hit.brush = brush.sceneBrush;
  return true;
}

} // namespace bt::trace_detail
