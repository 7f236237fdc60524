// Ray queries on bvh/trace_scene.h's TraceScene, uploaded unchanged (nodes, brushes, sides,
// faces) and read as texels (scene_buffers.glsl says why). This is a port of bvh/trace_scene.cpp, rule for rule, so that the GL tracer and the
// CPU reference return the same hit for the same ray; trace_scene.h states the contract:
//   - direction components below 2^-100 count as zero; a zero component means "inside that slab
//     or miss", never 0 * inf; the CPU's infinities are FLT_MAX here;
//   - a brush's box slabs stand in for its axial faces (GpuBrush::axialFace), its slanted sides
//     clip the interval one by one (Haines); ties between planes at the same t go to the one
//     met more head-on, then to the box side, then to the earlier side;
//   - a ray starting inside a brush hits where it leaves, with `inside` set;
//   - among brushes, the smallest t wins; at equal t entering beats leaving, then the higher
//     face index (the later brush, as qbsp keeps it) wins (trace_scene.cpp closer);
//   - mesh triangles (scene/gpu_structs.h GpuTriangle) have their own tree, walked after the
//     brushes' up to the closest brush hit: Moller-Trumbore, barycentric bounds widened by
//     TRIANGLE_EDGE_EPSILON, double-sided, the face of the side the ray meets, never inside.
// Needs scene_buffers.glsl. BT_BVH_MAX_DEPTH is scene/gpu_structs.h's kBvhMaxDepth, defined by
// the program (renderer/gl) and by the build's glslangValidator run alike.

#include "gl_bindings.glsl"
#include "scene_constants.glsl"
#ifndef BT_BVH_MAX_DEPTH
#error "BT_BVH_MAX_DEPTH (scene/gpu_structs.h kBvhMaxDepth) must be defined"
#endif
#ifndef BT_TRIANGLE_EDGE_EPSILON_INVERSE
#error "BT_TRIANGLE_EDGE_EPSILON_INVERSE (scene/gpu_structs.h kTriangleEdgeEpsilonInverse) must be defined"
#endif

const uint NO_FACE = BT_NO_FACE;

// Measurement switches of raybench.comp's variants (gl_bench's `variant`, bench/README.md issue
// 20 session 27); no program of the renderer defines them:
//   BT_RB_COUNT       counts per ray, in walkCounts: interior nodes visited, brushes whose box is
//                     tested, brushes whose box holds the interval (their planes are read), planes
//                     tested; and the deepest stack (walkDeepest);
//   BT_RB_NODES_ONLY  every leaf answers "no hit" unread (the node walk alone);
//   BT_RB_BOXES_ONLY  each leaf's brush boxes tested, no plane read, never a hit;
//   BT_RB_STACK_DEPTH N  a traversal stack of N entries, not kBvhMaxDepth (exact only while no walk
//                     goes deeper: the count's deepest stack says);
//   BT_RB_PLAIN_TEST  every node test plain (boxOverlaps careful = false), whatever the ray: what
//                     the walk costs with no zero-direction rules (exact only for rays without).
#ifdef BT_RB_COUNT
uvec4 walkCounts = uvec4(0u);
uint walkDeepest = 0u;
#endif
// FLT_MAX stands in for the CPU's infinity: every t of a real ray is far below it (directions
// are flushed below 2^-100, coordinates are Quake's), and GPU compilers may assume that no
// value is infinite (NVIDIA's does).
#define INFINITY 3.4028235e38

struct Hit {
  float t;     // distance along the ray (in units of dir's length)
  uint face;   // index into faces[] (= Scene::faces), NO_FACE for a miss
  bool inside; // the ray started inside the brush; face is where it leaves
};

// A ray prepared for traversal (trace_scene.cpp RayContext).
struct TraceRay {
  vec3 origin;
  vec3 dir;
  vec3 invDir;  // 0 on zero components
  bool hasZero; // some component is 0: slab tests take the careful path
  float tMin, tMax;
};

TraceRay makeTraceRay(vec3 origin, vec3 dir, float tMin, float tMax) {
  vec3 d = mix(dir, vec3(0.0), lessThan(abs(dir), vec3(uintBitsToFloat(0x0d800000u)))); // below 2^-100
  vec3 inv = vec3(d.x != 0.0 ? 1.0 / d.x : 0.0, d.y != 0.0 ? 1.0 / d.y : 0.0, d.z != 0.0 ? 1.0 / d.z : 0.0);
  return TraceRay(origin, d, inv, any(equal(d, vec3(0.0))), tMin, tMax);
}

// The ray's interval in a box, near > far on a miss, and which box side set each end: its
// slot in GpuBrush::axialFace (2 * axis + 1 for the +side), -1 if none did, with |d| along
// that axis. On equal t the axis the ray meets more head-on (larger |d|) takes the end: the
// tie rule of trace_scene.cpp brushBox.
// Written per axis with no vector indexed by a run-time value: GPU compilers put such vectors
// in local memory, and may read them before the guard that keeps the index in range.
struct Slab {
  float near, far;
  int nearSlot, farSlot;
  float nearFacing, farFacing;
};

void clipSlab(inout Slab s, inout bool miss, float origin, float dir, float invDir, float lo, float hi, int axis) {
  if (dir == 0.0) {
    miss = miss || origin < lo || origin > hi;
    return;
  }
  bool negative = dir < 0.0;
  float tNear = ((negative ? hi : lo) - origin) * invDir;
  float tFar = ((negative ? lo : hi) - origin) * invDir;
  float facing = abs(dir);
  if (tNear > s.near || (tNear == s.near && s.nearSlot >= 0 && facing > s.nearFacing)) {
    s.near = tNear;
    s.nearSlot = 2 * axis + (negative ? 1 : 0); // entering through the +side when going down
    s.nearFacing = facing;
  }
  if (tFar < s.far || (tFar == s.far && s.farSlot >= 0 && facing > s.farFacing)) {
    s.far = tFar;
    s.farSlot = 2 * axis + (negative ? 0 : 1);
    s.farFacing = facing;
  }
}

Slab intersectBox(TraceRay r, vec3 boxMin, vec3 boxMax) {
  Slab s = Slab(-INFINITY, INFINITY, -1, -1, 0.0, 0.0);
  bool miss = false;
  clipSlab(s, miss, r.origin.x, r.dir.x, r.invDir.x, boxMin.x, boxMax.x, 0);
  clipSlab(s, miss, r.origin.y, r.dir.y, r.invDir.y, boxMin.y, boxMax.y, 1);
  clipSlab(s, miss, r.origin.z, r.dir.z, r.invDir.z, boxMin.z, boxMax.z, 2);
  if (miss) s = Slab(INFINITY, -INFINITY, -1, -1, 0.0, 0.0);
  return s;
}

// renderer/gl/gl_structs.h GlBvhNode: an interior node of TraceScene's tree with both
// children's boxes, 4 texels: (leftMin, left), (leftMax, -), (rightMin, right), (rightMax, -).
// A child reference is a GlBvhNode index, or a leaf (LEAF_REF set: brushes first .. first +
// count), or NO_CHILD (0: node 0 is the root, nobody's child) on the root of a scene with fewer
// than two leaves.
const uint NO_CHILD = BT_GL_NO_CHILD;
const uint LEAF_REF = BT_GL_LEAF_REF;
uint leafFirst(uint ref) { return ref & 0x00ffffffu; }
uint leafCount(uint ref) { return (ref >> 24) & 0x7fu; }

// Where the traversal reads the scene, and where it keeps its stack, depends on the machine the
// program is built for (renderer/gl TracerPrograms picks the defines from the context):
//   BT_TRACE_SOFTWARE (Mesa's llvmpipe, compute shaders run on CPU SIMD lanes): rows read as
//     buffer-texture texels, the stack's top in registers and the rest in shared memory, each of
//     which llvmpipe runs far faster than storage-buffer loads and private arrays at per-lane
//     addresses (see scene_buffers.glsl and NodeStack below);
//   otherwise (GPUs): storage-buffer rows and a private stack array, which trace several times
//     faster there than the software layout (bench/README.md).
#ifdef BT_TRACE_SOFTWARE
uvec4 nodeRow(uint n, uint row) { return texelFetch(nodeTexels, int(4u * n + row)); }
uvec4 brushRow(uint b, uint row) { return texelFetch(brushTexels, int(4u * b + row)); }
uvec4 primitiveRow(uint row) { return texelFetch(brushTexels, int(row)); } // brushes', then triangles' rows
uint sideFace(uint i) { return texelFetch(sideTexels, int(i)).x; }
vec4 facePlane(uint f) { return texelFetch(faceTexels, int(4u * f)); }
#else
// The buffers behind the texel views (renderer/gl/gl_structs.h Binding), as rows.
layout(std430, binding = BT_BINDING_NODES) readonly buffer NodeRows { uvec4 nodeRows[]; };
layout(std430, binding = BT_BINDING_BRUSHES) readonly buffer BrushRows { uvec4 brushRows[]; };
layout(std430, binding = BT_BINDING_SIDES) readonly buffer SideFaces { uint sideFaces[]; };
uvec4 nodeRow(uint n, uint row) { return nodeRows[4u * n + row]; }
uvec4 brushRow(uint b, uint row) { return brushRows[4u * b + row]; }
uvec4 primitiveRow(uint row) { return brushRows[row]; } // brushes', then triangles' rows
uint sideFace(uint i) { return sideFaces[i]; }
vec4 facePlane(uint f) { return faces[f].plane; }
#endif

// Whether a child box can hold a hit with t in (tMin, tLimit]; inclusive at tLimit so that a
// hit at exactly the best t still reaches the tie-break (closer). `entry` is where the ray's
// interval in it starts, max(near, tMin): the box stays worth visiting while entry <= best t.
// intersectBox's near and far without its branches (trace_scene.cpp nodeOverlaps).
//   careful = false, for a ray with no zero direction component: the slabs' near and far, min and
//     max of the two planes' t;
//   careful = true, for any ray: a zero component (invDir 0) sets no bound on the interval, and
//     misses the box when the origin is outside that slab. For a ray with no zero component it
//     computes what the plain test does, bit for bit, at about twice the instructions: the node
//     tests are most of the walk's time, and on an H200 the plain test makes every ray kind half
//     as fast again (bench/README.md, issue 20 session 27). One formula for all rays on llvmpipe,
//     which runs the code on both sides of a branch, masked, even when all its SIMD lanes take the
//     same side (a branch on hasZero here cost a fifth of the bounce rays' time there).
bool boxOverlaps(TraceRay r, uvec4 minRow, uvec4 maxRow, float tLimit, bool careful, out float entry) {
  vec3 boundsMin = uintBitsToFloat(minRow.xyz), boundsMax = uintBitsToFloat(maxRow.xyz);
  vec3 t0 = (boundsMin - r.origin) * r.invDir, t1 = (boundsMax - r.origin) * r.invDir;
  if (!careful) {
    vec3 tNear = min(t0, t1), tFar = max(t0, t1);
    float near = max(max(tNear.x, tNear.y), tNear.z), far = min(min(tFar.x, tFar.y), tFar.z);
    entry = max(near, r.tMin);
    return entry <= min(far, tLimit) && near <= far;
  }
  bvec3 zero = equal(r.invDir, vec3(0.0));
  vec3 tNear = mix(min(t0, t1), vec3(-INFINITY), zero), tFar = mix(max(t0, t1), vec3(INFINITY), zero);
  float near = max(max(tNear.x, tNear.y), tNear.z), far = min(min(tFar.x, tFar.y), tFar.z);
  bool outsideSlab = any(bvec3(uvec3(zero) & (uvec3(lessThan(r.origin, boundsMin)) | uvec3(greaterThan(r.origin, boundsMax)))));
  entry = max(near, r.tMin);
  return !outsideSlab && entry <= min(far, tLimit) && near <= far;
}

// A plane crossing candidate: t, the face, and how head-on the ray meets it (|dot(n, d)|).
struct Crossing {
  float t;
  uint face;
  float facing;
};

// GpuBrush b's rows (brushRow): (boundsMin, firstSide), (boundsMax, sideCount), axialFace[0..3],
// (axialFace[4..5], sceneBrush, pad).

// GpuBrush::axialFace[slot], slot 0..5; the component is chosen by comparisons rather than by a
// run-time vector index (see Slab).
uint axialFace(uint b, int slot) {
  uvec4 row = brushRow(b, 2u + uint(slot >> 2));
  int c = slot & 3;
  return c == 0 ? row.x : c == 1 ? row.y : c == 2 ? row.z : row.w;
}

// Haines' clip against brush b (trace_scene.cpp hitBrush). A brush whose box starts beyond
// tLimit is rejected before its planes are read.
bool hitBrush(TraceRay r, uint b, float tLimit, out Hit hit) {
  hit = Hit(0.0, NO_FACE, false);
  uvec4 row0 = brushRow(b, 0u), row1 = brushRow(b, 1u);
  Slab box = intersectBox(r, uintBitsToFloat(row0.xyz), uintBitsToFloat(row1.xyz));
  if (box.near > box.far || box.far <= r.tMin || box.near >= r.tMax || box.near > tLimit) return false;
#ifdef BT_RB_BOXES_ONLY
  hit.face = floatBitsToUint(box.near); // keeps the box test's result live
  return false;
#endif
#ifdef BT_RB_COUNT
  ++walkCounts.z;
#endif

  Crossing enter = Crossing(-INFINITY, NO_FACE, 0.0), exit = Crossing(INFINITY, NO_FACE, 0.0);
  float near0 = max(box.near, r.tMin);
  uint firstSide = row0.w, endSide = firstSide + row1.w;
  for (uint i = firstSide; i < endSide; ++i) {
#ifdef BT_RB_COUNT
    ++walkCounts.w;
#endif
    uint f = sideFace(i);
    vec4 plane = facePlane(f);
    float denom = plane.x * r.dir.x + plane.y * r.dir.y + plane.z * r.dir.z;
    float dist = plane.x * r.origin.x + plane.y * r.origin.y + plane.z * r.origin.z - plane.w;
    if (denom < 0.0) { // crossing from front to back: entering
      float t = -dist / denom;
      if (t > enter.t || (t == enter.t && -denom > enter.facing)) enter = Crossing(t, f, -denom);
    } else if (denom > 0.0) { // leaving
      float t = -dist / denom;
      if (t < exit.t || (t == exit.t && denom > exit.facing)) exit = Crossing(t, f, denom);
    } else if (dist > 0.0) {
      return false; // parallel and in front: never inside
    }
    if (max(near0, enter.t) > min(box.far, exit.t)) return false;
  }

  // The box sides (those with an axial face) merge into the slanted candidates, same rule; a
  // box side without an axial face keeps the slanted plane's face and the box's t.
  if (box.nearSlot >= 0) {
    uint face = axialFace(b, box.nearSlot);
    if (box.near > enter.t || (box.near == enter.t && face != NO_FACE && box.nearFacing >= enter.facing))
      enter = Crossing(box.near, face != NO_FACE ? face : enter.face, box.nearFacing);
  }
  if (box.farSlot >= 0) {
    uint face = axialFace(b, box.farSlot);
    if (box.far < exit.t || (box.far == exit.t && face != NO_FACE && box.farFacing >= exit.facing))
      exit = Crossing(box.far, face != NO_FACE ? face : exit.face, box.farFacing);
  }
  if (enter.t > exit.t) return false;
  if (enter.t > r.tMin) {
    if (!(enter.t < r.tMax)) return false;
    hit = Hit(enter.t, enter.face, false);
  } else {
    if (!(exit.t > r.tMin && exit.t < r.tMax)) return false;
    hit = Hit(exit.t, exit.face, true);
  }
  return hit.face != NO_FACE; // only a broken winding leaves no face
}

// scene/gpu_structs.h kTriangleEdgeEpsilon.
const float TRIANGLE_EDGE_EPSILON = 1.0 / float(BT_TRIANGLE_EDGE_EPSILON_INVERSE);

// Moller-Trumbore against triangle k, whose 3 rows start at brush-buffer row firstRow + 3k
// (trace_scene.cpp hitTriangle): (v0, face), (v1, pad), (v2, pad).
bool hitTriangle(TraceRay r, uint firstRow, uint k, float tLimit, out Hit hit) {
  hit = Hit(0.0, NO_FACE, false);
  uvec4 row0 = primitiveRow(firstRow + 3u * k), row1 = primitiveRow(firstRow + 3u * k + 1u), row2 = primitiveRow(firstRow + 3u * k + 2u);
  vec3 v0 = uintBitsToFloat(row0.xyz);
  vec3 e1 = uintBitsToFloat(row1.xyz) - v0, e2 = uintBitsToFloat(row2.xyz) - v0;
  vec3 p = cross(r.dir, e2);
  float det = dot(e1, p);
  if (det == 0.0) return false; // the ray lies in the triangle's plane
  float inv = 1.0 / det;
  vec3 s = r.origin - v0;
  float u = dot(s, p) * inv;
  if (u < -TRIANGLE_EDGE_EPSILON || u > 1.0 + TRIANGLE_EDGE_EPSILON) return false;
  vec3 q = cross(s, e1);
  float v = dot(r.dir, q) * inv;
  if (v < -TRIANGLE_EDGE_EPSILON || u + v > 1.0 + TRIANGLE_EDGE_EPSILON) return false;
  float t = dot(e2, q) * inv;
  if (!(t > r.tMin && t < r.tMax) || t > tLimit) return false;
  hit = Hit(t, det > 0.0 ? row0.w : row0.w + 1u, false);
  return true;
}

// The closest-hit order of trace_scene.cpp closer(): smaller t; at equal t entering before
// leaving, then the later brush (higher face index), as qbsp's CSG keeps it.
bool closer(Hit hit, Hit best) {
  if (hit.t != best.t) return hit.t < best.t;
  if (best.face == NO_FACE) return true;
  if (hit.inside != best.inside) return !hit.inside;
  return hit.face > best.face;
}

// Depth-first traversal, nearer child first, kBvhMaxDepth stack entries (the builder's bound;
// with BT_TRACE_SOFTWARE 14 KiB of shared memory per workgroup). Written as Aila and Laine's "while-while": an inner
// loop runs down interior nodes until the ray reaches a leaf, then the leaf's brushes are
// tested. Invocations that run in lockstep (8 to a SIMD group on llvmpipe, a warp on GPUs)
// then test their brushes together, where a loop that takes either step per iteration runs
// both steps, masked, whenever its invocations differ (faster on llvmpipe: bench/README.md).
//   anyHit = false: the closest hit in (tMin, tMax).
//   anyHit = true: a shadow ray. The first brush entered from outside through a face that blocks
//     it (blocksRay: none of the classes `passFlags` passes, on one of its channels) ends the search; hits on faces with them, and exits from a
//     brush the ray starts in (but where blocksFromInside), are passed through. This is what the CPU integrator's occluded()
//     finds by skipping from one closest hit to the next.
// Every query of a shader goes through one call of this function: NVIDIA inlines each call
// site, so each extra one would compile the whole traversal again (see pathtrace.comp).
//
// BT_TRACE_SOFTWARE: the stack's top 8 entries live in registers (NodeStack), shifted one place per push or pop:
// on llvmpipe any memory access at a per-invocation index is a loop over the SIMD lanes, which
// took a fifth of the traversal's time, and most walks stay within 8 entries. The entries below
// live in shared memory, one column per invocation (entry d of invocation i at d * 64 + i):
// llvmpipe stores into a private array at a per-invocation index by reading, blending and
// writing every lane's slot, a shared store writes the active lanes only; on GPUs the column
// layout keeps neighbouring invocations in different banks. Every program that traces
// therefore runs 8 x 8 invocations per workgroup, declared here so that a program with another
// size fails to compile.
#if defined(BT_RB_GROUP_X) && !defined(BT_TRACE_SOFTWARE)
layout(local_size_x = BT_RB_GROUP_X, local_size_y = BT_RB_GROUP_Y) in; // raybench.comp's shapes
#else
layout(local_size_x = 8, local_size_y = 8) in;
#endif
#ifdef BT_TRACE_SOFTWARE
const uint TRACE_INVOCATIONS = 64u;
const int STACK_REGISTERS = 8;
shared uint traversalStack[(BT_BVH_MAX_DEPTH - STACK_REGISTERS) * TRACE_INVOCATIONS];

// Entries size - 1 (the top, lo.x) down to size - 8 (hi.w) in registers, the older ones at
// traversalStack[entry * TRACE_INVOCATIONS + invocation]. At most kBvhMaxDepth entries (a walk
// holds one per level above its node), so the shared part needs kBvhMaxDepth - 8.
struct NodeStack {
  uvec4 lo, hi;
  int size;
};

void pushNode(inout NodeStack s, uint node) {
  if (s.size >= STACK_REGISTERS) traversalStack[uint(s.size - STACK_REGISTERS) * TRACE_INVOCATIONS + gl_LocalInvocationIndex] = s.hi.w;
  s.hi = uvec4(s.lo.w, s.hi.xyz);
  s.lo = uvec4(node, s.lo.xyz);
  ++s.size;
#ifdef BT_RB_COUNT
  walkDeepest = max(walkDeepest, uint(s.size));
#endif
}

uint popNode(inout NodeStack s) {
  uint node = s.lo.x;
  s.lo = uvec4(s.lo.yzw, s.hi.x);
  s.hi = uvec4(s.hi.yzw, 0u);
  --s.size;
  if (s.size >= STACK_REGISTERS) s.hi.w = traversalStack[uint(s.size - STACK_REGISTERS) * TRACE_INVOCATIONS + gl_LocalInvocationIndex];
  return node;
}
#else
// GPUs: a private array (the compiler keeps it in registers and local memory).
#ifdef BT_RB_STACK_DEPTH
uint traversalStack[BT_RB_STACK_DEPTH];
#else
uint traversalStack[BT_BVH_MAX_DEPTH];
#endif
struct NodeStack {
  int size;
};
#ifdef BT_RB_COUNT
void pushNode(inout NodeStack s, uint node) {
  traversalStack[s.size++] = node;
  walkDeepest = max(walkDeepest, uint(s.size));
}
#else
void pushNode(inout NodeStack s, uint node) { traversalStack[s.size++] = node; }
#endif
uint popNode(inout NodeStack s) { return traversalStack[--s.size]; }
#endif

// Alpha-tested faces (lighting passesThrough): a hole for every ray where the base colour's
// filtered alpha fails the face's test. Programs without textures.glsl (raybench) test nothing.
bool maskedOut(uint face, vec3 p) {
#ifdef BT_ALPHA_TEST
  uint flags = faceFlags[face];
  if ((flags & FACE_MASKED) == 0u) return false;
  GlMaterial m = materials[faces[face].material];
  float a = materialBaseColor(m, faceUv(faces[face], m, p)).a;
  if ((flags & FACE_MASK_GT0) != 0u) return !(a > 0.0);
  if ((flags & FACE_MASK_LT128) != 0u) return !(a < 0.5);
  return !(a >= 0.5);
#else
  return false;
#endif
}

// The alpha test of a closest hit (a ray that is not any-hit), at the hit of a ray from `origin`
// along `dir`: pathtrace.comp's advance() passes what it fails. The wavefront form's trace kernel
// tests it for its shade kernel (wavefront.glsl, pathtrace.comp hitMasked), which then holds no
// copy of the texture sampling for it: each copy is code for the driver's back end to compile, and
// the shade kernel's compile is what the very first image waits for.
bool closestHitMasked(Hit hit, bool anyHit, vec3 origin, vec3 dir) {
  return !anyHit && hit.face != NO_FACE && !hit.inside && maskedOut(hit.face, origin + dir * hit.t);
}

// Whether a face (its word in faceFlags) blocks a ray of pass word `passFlags`: none of the classes
// the ray passes, and one of the channels it is blocked on (scene_constants.glsl).
bool blocksRay(uint flags, uint passFlags) {
  return (flags & passFlags & FACE_CLASS_BITS) == 0u && (flags & passFlags & ~FACE_CLASS_BITS) != 0u;
}

// Whether a shadow ray that leaves brush b (a hit `inside`) is blocked there, as one entering it
// through a face that blocks it (lighting/visibility.cpp stopsShadowRay): where the brush's pad
// word (RenderScene::blocksFromInside, renderer/gl/gl_scene.cpp) shares bits with the pass word,
// the channel bits, which only a faithful ray's has. Compiled into the faithful programs of the
// levels that have such brushes (FaithfulFeatures::blocksFromInside) and the wavefront trace
// kernel; every other program passes every exit, as before.
bool blocksFromInside(bool inTriangles, uint b, uint passFlags) {
#ifdef BT_BLOCKS_FROM_INSIDE
  return !inTriangles && (brushRow(b, 3u).w & passFlags) != 0u;
#else
  return false;
#endif
}

// One step down from interior node `current` (boxOverlaps says what `careful` is): the nearer
// child whose box the ray meets, the farther one pushed when it meets both; with neither, the
// stack's top, or an empty leaf when the stack is empty.
uint descend(TraceRay r, uint current, inout NodeStack stack, float tLimit, bool careful) {
#ifdef BT_RB_COUNT
  ++walkCounts.x;
#endif
  uvec4 leftMin = nodeRow(current, 0u), leftMax = nodeRow(current, 1u);
  uvec4 rightMin = nodeRow(current, 2u), rightMax = nodeRow(current, 3u);
  uint a = leftMin.w, b = rightMin.w;
  float entryA, entryB;
  bool hitA = a != NO_CHILD && boxOverlaps(r, leftMin, leftMax, tLimit, careful, entryA);
  bool hitB = b != NO_CHILD && boxOverlaps(r, rightMin, rightMax, tLimit, careful, entryB);
  if (hitA && hitB) {
    if (entryB < entryA) {
      uint swap = a;
      a = b;
      b = swap;
    }
    pushNode(stack, b);
    return a;
  }
  if (hitA || hitB) return hitA ? a : b;
  return stack.size > 0 ? popNode(stack) : LEAF_REF;
}

Hit traceRay(TraceRay r, bool anyHit, uint passFlags) {
  Hit best = Hit(r.tMax, NO_FACE, false);
#ifdef BT_TRACE_SOFTWARE
  NodeStack stack = NodeStack(uvec4(0u), uvec4(0u), 0);
#else
  NodeStack stack = NodeStack(0);
#endif
  uint current = 0u; // a child reference; the root is GlBvhNode 0
  // GlBvhNode 0's pads (renderer/gl/gl_structs.h): the triangle tree's root (NO_CHILD: the
  // level has no mesh) and the row of the first triangle. The walk does the brushes' tree, then
  // the triangles'.
  uvec4 rootPads = uvec4(nodeRow(0u, 1u).w, nodeRow(0u, 3u).w, 0u, 0u);
  bool inTriangles = false;
#if defined(BT_RB_NODES_ONLY) || defined(BT_RB_BOXES_ONLY)
  uint leafSum = 0u;
#endif
  while (true) {
    // Down through interior nodes to the next leaf; with nothing left to visit, an empty leaf.
#ifdef BT_TRACE_SOFTWARE
    while ((current & LEAF_REF) == 0u) current = descend(r, current, stack, best.t, true);
#else
    // Two loops, so that a GPU branches once per leaf on the ray's kind (one kind for a whole
    // subgroup but in the rare groups that hold a zero component) rather than per node test.
#ifdef BT_RB_PLAIN_TEST
    if (false) {
#else
    if (r.hasZero) {
#endif
      while ((current & LEAF_REF) == 0u) current = descend(r, current, stack, best.t, true);
    } else {
      while ((current & LEAF_REF) == 0u) current = descend(r, current, stack, best.t, false);
    }
#endif
    uint first = leafFirst(current), end = first + leafCount(current);
#ifdef BT_RB_NODES_ONLY
    leafSum ^= current; // keeps the walk live
    end = first;
#endif
    for (uint i = first; i < end; ++i) {
      Hit hit;
#ifdef BT_RB_COUNT
      walkCounts.y += inTriangles ? 0u : 1u;
#endif
#ifdef BT_RB_BOXES_ONLY
      bool found = inTriangles ? hitTriangle(r, rootPads.y, i, best.t, hit) : hitBrush(r, i, best.t, hit);
      leafSum ^= hit.face;
      if (!found) continue;
#else
      if (!(inTriangles ? hitTriangle(r, rootPads.y, i, best.t, hit) : hitBrush(r, i, best.t, hit))) continue;
#endif
      if (anyHit) {
        if ((!hit.inside || blocksFromInside(inTriangles, i, passFlags)) && blocksRay(faceFlags[hit.face], passFlags) &&
            !maskedOut(hit.face, r.origin + r.dir * hit.t))
          return hit;
      } else if (closer(hit, best)) {
        best = hit;
      }
    }
    if (stack.size == 0) {
      if (inTriangles || rootPads.x == NO_CHILD) break;
      inTriangles = true;
      current = rootPads.x;
      continue;
    }
    current = popNode(stack);
  }
#if defined(BT_RB_NODES_ONLY) || defined(BT_RB_BOXES_ONLY)
  best.face = leafSum;
#endif
  return best;
}
