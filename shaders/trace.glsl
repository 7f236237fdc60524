// Closest hit of a ray against the brushes: BVH traversal with a short stack, ray vs brush by
// clipping the ray against every plane of the brush (Haines, Graphics Gems II).
// Needs scene_buffers.glsl.

const uint NO_FACE = 0xffffffffu;

struct Hit {
  float t;     // distance along the ray (in units of dir's length)
  uint face;   // index into faces[], NO_FACE for a miss
  bool inside; // the ray started inside the brush; face is where it leaves
};

const float MISS = 3.4e38; // the slab test's miss: beyond every tMax the tracer passes (at most 3e38)

// Slab test; returns the entry distance, or MISS.
float intersectBounds(vec3 origin, vec3 invDir, vec3 bmin, vec3 bmax, float tMin, float tMax) {
  vec3 t0 = (bmin - origin) * invDir;
  vec3 t1 = (bmax - origin) * invDir;
  vec3 tNear = min(t0, t1);
  vec3 tFar = max(t0, t1);
  float enter = max(max(tNear.x, tNear.y), max(tNear.z, tMin));
  float leave = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
  return enter <= leave ? enter : MISS;
}

// Ray vs convex brush, the rules of bvh/trace_scene.h: the interval (tMin, tMax) is clipped by
// every plane; a plane crossed from front to back raises the entry, one crossed from back to
// front lowers the exit, a parallel plane with the origin in front rejects the brush.
// From outside: the hit is the entry and its plane. Starting inside (entry <= tMin): the hit is
// the exit and its plane, with inside set. Entry > exit: miss. tMax is inclusive here so that
// traceClosest can see a second hit at the same t and break the tie.
bool intersectBrush(GpuBrush b, vec3 origin, vec3 dir, float tMin, float tMax, out Hit hit) {
  float tEnter = -3.0e38, tLeave = 3.0e38;
  uint enterFace = NO_FACE, leaveFace = NO_FACE;
  for (uint i = b.firstFace; i < b.firstFace + b.faceCount; ++i) {
    float distance = dot(faces[i].normal, origin) - faces[i].dist; // > 0: in front (outside)
    float denom = dot(faces[i].normal, dir);
    if (denom < 0.0) {
      float t = -distance / denom;
      if (t > tEnter) { tEnter = t; enterFace = i; }
    } else if (denom > 0.0) {
      float t = -distance / denom;
      if (t < tLeave) { tLeave = t; leaveFace = i; }
    } else if (distance > 0.0) {
      return false; // parallel to the plane and outside it
    }
  }
  if (tEnter > tLeave) return false;
  if (tEnter > tMin) {
    if (tEnter > tMax || enterFace == NO_FACE) return false;
    hit = Hit(tEnter, enterFace, false);
    return true;
  }
  if (tLeave <= tMin || tLeave > tMax || leaveFace == NO_FACE) return false;
  hit = Hit(tLeave, leaveFace, true);
  return true;
}

// The closest hit in (tMin, tMax); a hit at exactly tMax is not one. Equal t goes to the smaller face index, so the answer does
// not depend on the traversal order.
Hit traceClosest(vec3 origin, vec3 dir, float tMin, float tMax) {
  Hit best = Hit(tMax, NO_FACE, false);
  vec3 invDir = 1.0 / dir; // IEEE infinities for axis-parallel rays are what the slab test wants
  // A balanced BVH over a million brushes is 20 levels deep; 32 leaves room for SAH's skew.
  uint stack[32];
  uint depth = 0u;
  uint node = 0u;
  if (intersectBounds(origin, invDir, nodes[0].boundsMin, nodes[0].boundsMax, tMin, tMax) == MISS) return best;
  while (true) {
    GpuBvhNode n = nodes[node];
    if (n.count > 0u) {
      for (uint i = n.leftOrFirst; i < n.leftOrFirst + n.count; ++i) {
        GpuBrush b = brushes[i];
        if (intersectBounds(origin, invDir, b.boundsMin, b.boundsMax, tMin, best.t) == MISS) continue;
        Hit h;
        if (intersectBrush(b, origin, dir, tMin, best.t, h) &&
            (h.t < best.t || (h.t == best.t && best.face != NO_FACE && h.face < best.face)))
          best = h;
      }
    } else {
      uint near = n.leftOrFirst;
      uint far = n.leftOrFirst + 1u;
      float tNear = intersectBounds(origin, invDir, nodes[near].boundsMin, nodes[near].boundsMax, tMin, best.t);
      float tFar = intersectBounds(origin, invDir, nodes[far].boundsMin, nodes[far].boundsMax, tMin, best.t);
      if (tFar < tNear) {
        uint s = near; near = far; far = s;
        float ts = tNear; tNear = tFar; tFar = ts;
      }
      if (tNear != MISS) {
        if (tFar != MISS && depth < 32u) stack[depth++] = far;
        node = near;
        continue;
      }
    }
    // Pop the next subtree; one farther than the closest hit is rejected on its next visit.
    if (depth == 0u) break;
    node = stack[--depth];
  }
  return best;
}
