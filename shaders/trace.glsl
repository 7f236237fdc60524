// Closest hit of a ray against the brushes: BVH traversal with a short stack, ray vs brush by
// clipping the ray against every plane of the brush (Haines, Graphics Gems II).
// Needs scene_buffers.glsl.

const uint NO_FACE = 0xffffffffu;

struct Hit {
  float t;   // distance along the ray (dir is unit length)
  uint face; // index into faces[], NO_FACE for a miss
};

// Slab test; returns the entry distance, or a value > tMax on a miss.
float intersectBounds(vec3 origin, vec3 invDir, vec3 bmin, vec3 bmax, float tMax) {
  vec3 t0 = (bmin - origin) * invDir;
  vec3 t1 = (bmax - origin) * invDir;
  vec3 tNear = min(t0, t1);
  vec3 tFar = max(t0, t1);
  float enter = max(max(tNear.x, tNear.y), max(tNear.z, 0.0));
  float leave = min(min(tFar.x, tFar.y), min(tFar.z, tMax));
  return enter <= leave ? enter : 3.0e38;
}

// The ray enters a convex brush through the last plane it crosses from outside and leaves it
// through the first it crosses from inside. A ray that starts inside the brush (its last entry
// lies behind the origin) misses: the camera or a bounce inside solid sees out, as with Quake's
// noclip. Bounce rays start a little in front of their surface, so their own brush is behind.
bool intersectBrush(GpuBrush b, vec3 origin, vec3 dir, float tMax, out float tHit, out uint face) {
  float tEnter = -3.0e38;
  float tLeave = tMax;
  face = NO_FACE;
  for (uint i = b.firstFace; i < b.firstFace + b.faceCount; ++i) {
    float distance = dot(faces[i].normal, origin) - faces[i].dist; // > 0: in front (outside)
    float denom = dot(faces[i].normal, dir);
    if (denom < 0.0) {
      float t = -distance / denom;
      if (t > tEnter) {
        tEnter = t;
        face = i;
      }
    } else if (denom > 0.0) {
      tLeave = min(tLeave, -distance / denom);
    } else if (distance > 0.0) {
      return false; // parallel to the plane and outside it
    }
    if (tEnter > tLeave) return false;
  }
  if (face == NO_FACE || tEnter < 0.0) return false;
  tHit = tEnter;
  return true;
}

Hit traceClosest(vec3 origin, vec3 dir, float tMax) {
  Hit hit = Hit(tMax, NO_FACE);
  vec3 invDir = 1.0 / dir; // IEEE infinities for axis-parallel rays are what the slab test wants
  // A balanced BVH over a million brushes is 20 levels deep; 32 leaves room for SAH's skew.
  uint stack[32];
  uint depth = 0u;
  uint node = 0u;
  if (intersectBounds(origin, invDir, nodes[0].boundsMin, nodes[0].boundsMax, tMax) > tMax) return hit;
  while (true) {
    GpuBvhNode n = nodes[node];
    if (n.count > 0u) {
      for (uint i = n.leftOrFirst; i < n.leftOrFirst + n.count; ++i) {
        GpuBrush b = brushes[i];
        if (intersectBounds(origin, invDir, b.boundsMin, b.boundsMax, hit.t) > hit.t) continue;
        float t;
        uint face;
        if (intersectBrush(b, origin, dir, hit.t, t, face) && t < hit.t) {
          hit.t = t;
          hit.face = face;
        }
      }
    } else {
      uint near = n.leftOrFirst;
      uint far = n.leftOrFirst + 1u;
      float tNear = intersectBounds(origin, invDir, nodes[near].boundsMin, nodes[near].boundsMax, hit.t);
      float tFar = intersectBounds(origin, invDir, nodes[far].boundsMin, nodes[far].boundsMax, hit.t);
      if (tFar < tNear) {
        uint s = near; near = far; far = s;
        float ts = tNear; tNear = tFar; tFar = ts;
      }
      if (tNear <= hit.t) {
        if (tFar <= hit.t && depth < 32u) stack[depth++] = far;
        node = near;
        continue;
      }
    }
    // Pop the next subtree still nearer than the closest hit.
    if (depth == 0u) break;
    node = stack[--depth];
  }
  return hit;
}
