// The structs that the CPU tracer and the GL compute tracer share, byte for byte.
//
// Every struct here is uploaded as-is into a std430 shader storage buffer, so each one is made
// of 4-byte scalars laid out in 16-byte rows (a vec3 followed by one 4-byte scalar, as std430
// packs `vec3 a; uint b;`). The static_asserts pin the size and every offset; the GLSL
// declaration that matches is written beside each struct. Other parts append their own
// sections (materials, lights, ...) below, in the same style.
#pragma once

#include <cstddef>
#include <cstdint>

namespace bt {

// "No face": an unused slot in GpuBrush::axialFace.
inline constexpr uint32_t kNoFace = 0xffffffffu;

// ---------------------------------------------------------------------------------------------
// BVH (bvh/trace_scene.h builds these)
// ---------------------------------------------------------------------------------------------

// No leaf of a TraceScene BVH is deeper than this (root = depth 0), so a traversal stack of
// kBvhMaxDepth entries never overflows.
inline constexpr uint32_t kBvhMaxDepth = 64;

// One node of the flattened brush BVH, 32 bytes. nodes[0] is the root.
//   count == 0: interior node; its children are nodes[leftFirst] and nodes[leftFirst + 1].
//   count >  0: leaf; it holds brushes[leftFirst .. leftFirst + count) of TraceScene::brushes().
// A scene with no traceable brush has no nodes at all (check the node count before traversal).
// The bounds are rounded outward from the brush bounds, so they always contain their brushes.
//
//   struct BvhNode { vec3 boundsMin; uint leftFirst; vec3 boundsMax; uint count; };
struct GpuBvhNode {
  float boundsMin[3];
  uint32_t leftFirst;
  float boundsMax[3];
  uint32_t count;
};
static_assert(sizeof(GpuBvhNode) == 32);
static_assert(offsetof(GpuBvhNode, boundsMin) == 0);
static_assert(offsetof(GpuBvhNode, leftFirst) == 12);
static_assert(offsetof(GpuBvhNode, boundsMax) == 16);
static_assert(offsetof(GpuBvhNode, count) == 28);

// One brush, 64 bytes, in BVH leaf order (not Scene order: sceneBrush maps back).
//
// A brush is the intersection of the half-spaces behind its faces' planes. The ray test
// (Haines' convex polyhedron clip) takes the axial planes from the bounds instead of from the
// faces, the way Quake 3's collision code keeps brush sides axial-first: a box brush then costs
// one slab test and nothing else. So:
//   - boundsMin/boundsMax: the brush's bounding box. A side of the box that carries an axial
//     face sits exactly at that face's plane (float(dist)); the other sides come from the
//     windings, rounded outward.
//   - axialFace[6]: the face lying on each side of the box, in the order -X, +X, -Y, +Y, -Z, +Z,
//     or kNoFace where no face of the brush lies on that side (only an edge or a vertex of the
//     brush touches it).
//   - sides[firstSide .. firstSide + sideCount) of TraceScene::sides(): the face indices of the
//     remaining (non-axial) faces, whose planes the test clips against one by one.
// Face indices index TraceScene::faces() and Scene::faces alike.
//
//   struct Brush { vec3 boundsMin; uint firstSide; vec3 boundsMax; uint sideCount;
//                  uint axialFace[6]; uint sceneBrush; uint pad; };
struct GpuBrush {
  float boundsMin[3];
  uint32_t firstSide;
  float boundsMax[3];
  uint32_t sideCount;
  uint32_t axialFace[6];
  uint32_t sceneBrush; // index into Scene::brushes
  uint32_t pad;        // zero; keeps the struct a whole number of 16-byte rows
};
static_assert(sizeof(GpuBrush) == 64);
static_assert(offsetof(GpuBrush, boundsMin) == 0);
static_assert(offsetof(GpuBrush, firstSide) == 12);
static_assert(offsetof(GpuBrush, boundsMax) == 16);
static_assert(offsetof(GpuBrush, sideCount) == 28);
static_assert(offsetof(GpuBrush, axialFace) == 32);
static_assert(offsetof(GpuBrush, sceneBrush) == 56);
static_assert(offsetof(GpuBrush, pad) == 60);

// One face (brush side), 64 bytes, in Scene::faces order: faces[i] is Scene::faces[i].
//   plane:  normal xyz (unit, pointing out of the brush) and dist w; p is on the plane when
//           dot(normal, p) == dist.
//   origin, tangent, bitangent: the texture frame of scene.h, in texels:
//           s = dot(p - origin, tangent), t = dot(p - origin, bitangent);
//           the texture is sampled at (s / material width, t / material height).
//   material: index into Scene::materials; brush: index into Scene::brushes.
// Faces with an empty winding (redundant planes) are never hit.
//
//   struct Face { vec4 plane; vec3 origin; uint material; vec3 tangent; uint brush;
//                 vec3 bitangent; uint pad; };
struct GpuFace {
  float plane[4];
  float origin[3];
  uint32_t material;
  float tangent[3];
  uint32_t brush;
  float bitangent[3];
  uint32_t pad; // zero
};
static_assert(sizeof(GpuFace) == 64);
static_assert(offsetof(GpuFace, plane) == 0);
static_assert(offsetof(GpuFace, origin) == 16);
static_assert(offsetof(GpuFace, material) == 28);
static_assert(offsetof(GpuFace, tangent) == 32);
static_assert(offsetof(GpuFace, brush) == 44);
static_assert(offsetof(GpuFace, bitangent) == 48);
static_assert(offsetof(GpuFace, pad) == 60);

} // namespace bt
