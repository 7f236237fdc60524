// TraceScene: the brushes of a Scene in a binned-SAH BVH, and the ray queries on it.
//
// The CPU reference tracer calls closestHit()/occluded(); the GL tracer uploads nodes(),
// brushes(), sides() and faces() (scene/gpu_structs.h) as shader storage buffers and runs the
// same traversal and brush test in GLSL. The rules below are the contract both follow, so that
// both return the same hit for the same ray.
//
// Ray vs brush (Haines, "Fast Ray-Convex Polyhedron Intersection", Graphics Gems II):
//   the ray's parameter interval is clipped by every plane of the brush: a plane the ray
//   crosses from front to back (dot(n, d) < 0) raises the entry t, one it crosses from back to
//   front lowers the exit t, and a plane parallel to the ray with the origin in front of it
//   rejects the brush. A ray lying exactly in a plane counts as behind it (inside). The six
//   axial planes come from the bounding-box slab test (see GpuBrush); the box slabs also clip
//   the interval on sides without an axial face, where they are merely redundant.
//   - hit from outside: the entry t lies in (tMin, tMax); face = the plane that set the entry
//     (a box side's axial face if that side has one and its t is not below the slanted planes',
//     else the slanted plane with the largest entry t); inside = false.
//   - ray starting inside (entry t <= tMin): the hit is where it leaves, the exit t, if that
//     lies in (tMin, tMax); face = the plane that set the exit (same rule); inside = true.
//     A segment that lies wholly inside one brush hits nothing in that brush.
//   - entry t > exit t: miss. Entry == exit (grazing an edge) is a hit.
//   - two planes of the brush at exactly the same t (the ray meets an edge): the one the ray
//     meets more head-on (larger |dot(n, d)|) gives the face; on equal terms the box side, then
//     the earlier side in sides().
// Closest hit over brushes: smallest t; at equal t a hit entering its brush beats one leaving
// the brush the ray started in (a ray leaving a liquid exactly where a wall starts stops at the
// wall), then the higher face index, i.e. the later brush in the file: qbsp's CSG keeps the
// later of two overlapping brushes' coplanar faces, so a .map preview shows what the compiled
// level shows. The answer never depends on traversal order (two brushes sharing a face, a ray
// along the shared plane: both top faces are hit at the same t, the later one wins on CPU and GPU).
//
// Mesh triangles (scene.h Mesh, gpu_structs.h GpuTriangle) are a second primitive with a BVH of
// their own, traversed after the brushes' with the closest brush hit as its limit; a level
// without meshes has an empty triangle BVH and traces as before. A triangle hit is never
// `inside`; its face is the side facing the ray (so a hit always meets a face whose normal
// faces the ray, as with brushes), and it follows the same closest-hit order: at equal t, an
// entering brush hit and a triangle hit compare by face index, and mesh faces come after the
// faces of the brushes before them in the file.
//
// Neighbouring brushes: a shared face has the same float plane on both sides (axial: the same
// box coordinate; slanted: exactly negated), so both brushes compute the same t for it and the
// hidden faces between them are never the closest hit, except for a ray that lands exactly on
// the edge of the shared face at a shallower angle to the visible faces than to the hidden one
// (it is a tie within one brush, resolved head-on; tests/bvh/ray_brush_test.cpp pins it).
//
// Traversal, for ports: direction components below 2^-100 count as zero, and a zero component
// means "inside that slab or miss" (never 0 * inf); slab t = (bound - origin) * (1 / d) for
// nodes and brush boxes alike; a node is visited when max(near, tMin) <= min(far, best t),
// inclusive so that equal-t hits reach the tie-break; a brush whose box starts beyond the
// best t is skipped; children nearer first; the stack needs kBvhMaxDepth entries.
//
// Epsilons: the test itself has none; everything is exact IEEE float with the rules above, so
// the BVH and a brute-force loop agree bit for bit. Self-intersection is avoided by the caller:
// start secondary rays at offsetRayOrigin(hit point, geometric normal) with tMin = 0, and go on
// past a skipped hit from continueRayAfter(t): both tracers follow this one rule
// (shaders/ray_offsets.glsl holds its numbers for both).
#pragma once

#include "bvh/ray.h"         // Ray, RayContext
#include "bvh/sah_builder.h" // Aabb, sahCost() and the SAH cost model
#include "bvh/wide_bvh.h"
#include "scene/gpu_structs.h"
#include "scene/scene.h"
#include "shaders/ray_offsets.glsl" // shared with shaders/visible.glsl

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

namespace bt {

struct Hit {
  float t = 0.0f;
  uint32_t face = kNoFace;  // index into Scene::faces AND TraceScene::faces()
  uint32_t brush = kNoFace; // index into Scene::brushes; kNoBrush for a mesh triangle
  uint32_t slot = kNoFace;  // index into TraceScene::brushes() (or triangles()): intersectBrush's argument
  bool inside = false;      // the ray started inside the brush; face is where it leaves
};

struct BvhBuildOptions {
  int leafSize = 4;  // a node with more brushes than this is always split; smaller ones
                     // are split only where the SAH says it pays
  int binCount = 32; // SAH bins per axis of a large node (a node of n boxes gets
                     // min(binCount, max(5n / 8, 8)), at most 24 below 256 boxes; nodes of 8 or
                     // fewer an exact sweep; nodes of 2048 or more bin a sample); with 32 the
                     // tree's SAH is close to the exact full sweep's (tests/bvh checks how close)
  int threads = 0;   // 0 = all cores
  // No reinsertion/optimisation pass: the binned tree's SAH is already close to the exact
  // full sweep's on the shared maps (tests/bvh), so there is little left for one to gain.
  std::vector<bool> includeBrush; // per Scene brush; empty = all. Excluded brushes are never hit.
  std::vector<bool> includeMesh;  // per Scene mesh, the same
};

class TraceScene {
public:
  static TraceScene build(const Scene& scene, const BvhBuildOptions& options = {});

  // The closest hit with t in (ray.tMin, ray.tMax), by the rules above.
  std::optional<Hit> closestHit(const Ray& ray) const;
  // Whether closestHit(ray) would find anything, without looking for the closest.
  bool occluded(const Ray& ray) const;
  // Some hit with t in (ray.tMin, ray.tMax), the first the traversal meets (not the closest):
  // what a shadow ray needs when that hit is a blocker.
  std::optional<Hit> anyHit(const Ray& ray) const;
  // The same for a ray prepared once for several queries (bvh/ray.h).
  std::optional<Hit> anyHit(const RayContext& ray) const;

  // closestHit() of each of up to kPacketRays rays (hits[i] answers rays[i], bit for bit), the
  // brushes in one walk of the BVH whose node tests take the rays kPacketLanes at a time: for
  // rays that go nearly the same way from nearly the same place (a penumbra's suns from one
  // point), whose single walks mostly visit the same nodes. Every brush a ray's own walk would
  // test it tests (its leaf's box passes the same test), and the closest-hit order does not
  // depend on the order of the tests; a brush is tested only against the rays that reach its
  // leaf. Rays with a zero direction component, and every ray of a level with meshes, take
  // closestHit() itself.
  static constexpr size_t kPacketRays = 64, kPacketLanes = 4;
  void closestHits(std::span<const Ray> rays, std::span<std::optional<Hit>> hits) const;

  // Whether p lies inside some brush for which `counts(scene brush index)` is true: strictly, or
  // with `onSurface` also on its boundary. ericw-tools' "point in solid" tests, which move a
  // luxel's sample point out of walls and a light off the face it lies on.
  template <class Counts> bool inside(const glm::vec3& p, const Counts& counts, bool onSurface = false) const;
  // Whether p lies at most `margin` outside such a brush (behind every side's plane moved out by
  // `margin`): ericw-tools' Light_PointInSolid, which takes both sides of a BSP plane nearer than
  // 0.1 unit to the point.
  template <class Counts> bool nearInside(const glm::vec3& p, float margin, const Counts& counts) const;

  // The brush BVH's walk without a ray: into every node whose box `enter(lo, hi)` accepts, calling
  // `visit(slot)` for each brush of the leaves it reaches (slot: index into brushes()) until one
  // returns true, which walkBrushes then returns. Point tests and packets of rays share it.
  template <class Enter, class Visit> bool walkBrushes(const Enter& enter, const Visit& visit) const;

  // The hit of one brush (index into brushes()), by the rules above; what the BVH calls per leaf.
  std::optional<Hit> intersectBrush(const Ray& ray, uint32_t brushIndex) const;
  std::optional<Hit> intersectBrush(const RayContext& ray, uint32_t brushIndex) const;
  // Whether intersectBrush(ray, brushIndex) is a hit from outside (not `inside`), for a brush
  // that is a box (no slanted sides, an axial face on each of its six): its box interval alone
  // answers, without the face. nullopt for other brushes and for rays with a zero direction
  // component. What a shadow ray's test against a solid recent blocker needs.
  std::optional<bool> entersBox(const RayContext& ray, uint32_t brushIndex) const;
  // The same for one triangle (index into triangles()).
  std::optional<Hit> intersectTriangle(const Ray& ray, uint32_t triangleIndex) const;

  std::span<const GpuBvhNode> nodes() const { return nodes_; }
  std::span<const WideBvhNode> wideNodes() const { return wideNodes_; } // nodes() collapsed (bvh/wide_bvh.h)
  std::span<const GpuBrush> brushes() const { return brushes_; }
  std::span<const uint32_t> sides() const { return sides_; } // see GpuBrush
  std::span<const GpuFace> faces() const { return faces_; }
  std::span<const GpuBvhNode> triangleNodes() const { return triangleNodes_; } // empty without meshes
  std::span<const GpuTriangle> triangles() const { return triangles_; }

  double sahCost() const { return sahCost_; } // of nodes(), see bvh/sah_builder.h
  Bounds bounds() const { return bounds_; }   // of the traceable brushes and triangles

private:
  std::vector<GpuBvhNode> nodes_;
  std::vector<WideBvhNode> wideNodes_;
  std::vector<GpuBrush> brushes_;
  std::vector<uint32_t> sides_;
  std::vector<GpuFace> faces_;
  std::vector<GpuBvhNode> triangleNodes_;
  std::vector<GpuTriangle> triangles_;
  double sahCost_ = 0.0;
  Bounds bounds_;

  // inside()'s walk: boxes widened by `margin`, closed or open; `within(d, w)` says whether a
  // point at d = n.p lies inside the slanted side n.x = w.
  template <class Counts, class Within>
  bool insideBy(const glm::vec3& p, float margin, bool closed, const Counts& counts, const Within& within) const;
};

template <class Counts> bool TraceScene::inside(const glm::vec3& p, const Counts& counts, bool onSurface) const {
  if (onSurface) return insideBy(p, 0.0f, true, counts, [](float d, float w) { return d <= w; });
  return insideBy(p, 0.0f, false, counts, [](float d, float w) { return d < w; });
}

template <class Counts> bool TraceScene::nearInside(const glm::vec3& p, float margin, const Counts& counts) const {
  return insideBy(p, margin, true, counts, [margin](float d, float w) { return d <= w + margin; });
}

template <class Counts, class Within>
bool TraceScene::insideBy(const glm::vec3& p, float margin, bool closed, const Counts& counts, const Within& within) const {
  // A brush's box is its axial sides (only slanted sides are listed), widened by the margin.
  auto inBox = [&](const float* lo, const float* hi) {
    if (!closed) return p.x > lo[0] && p.x < hi[0] && p.y > lo[1] && p.y < hi[1] && p.z > lo[2] && p.z < hi[2];
    return p.x >= lo[0] - margin && p.x <= hi[0] + margin && p.y >= lo[1] - margin && p.y <= hi[1] + margin && p.z >= lo[2] - margin &&
        p.z <= hi[2] + margin;
  };
  return walkBrushes(inBox, [&](uint32_t slot) {
    const GpuBrush& b = brushes_[slot];
    if (!inBox(b.boundsMin, b.boundsMax)) return false;
    for (uint32_t k = b.firstSide; k < b.firstSide + b.sideCount; ++k) {
      const float* plane = faces_[sides_[k]].plane;
      if (!within(plane[0] * p.x + plane[1] * p.y + plane[2] * p.z, plane[3])) return false;
    }
    return bool(counts(b.sceneBrush));
  });
}

template <class Enter, class Visit> bool TraceScene::walkBrushes(const Enter& enter, const Visit& visit) const {
  if (nodes_.empty() || !enter(nodes_[0].boundsMin, nodes_[0].boundsMax)) return false;
  uint32_t stack[kBvhMaxDepth + 1]; // one pop and up to two pushes per level
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const GpuBvhNode& node = nodes_[stack[--top]];
    if (node.count == 0) {
      for (uint32_t c = node.leftFirst; c < node.leftFirst + 2; ++c)
        if (enter(nodes_[c].boundsMin, nodes_[c].boundsMax)) stack[top++] = c;
      continue;
    }
    for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i)
      if (visit(i)) return true;
  }
  return false;
}

// Where a ray leaving a surface should start: p pushed along the geometric normal n (unit, on the
// side the ray leaves to) by BT_SURFACE_OFFSET.
inline constexpr float kSurfaceOffset = BT_SURFACE_OFFSET;
inline glm::vec3 offsetRayOrigin(const glm::vec3& p, const glm::vec3& n) {
  return p + n * kSurfaceOffset;
}
// Where a ray that skips a hit at t goes on from.
inline float continueRayAfter(float t) {
  return t + BT_SKIP_STEP;
}

// Texture coordinates in texels at a point on a face: (s, t) from the face's frame.
glm::vec2 textureCoordinates(const GpuFace& face, const glm::vec3& p);

// Bilinear filtering with repeat wrap and texel centres at +0.5, as a GL sampler with
// GL_LINEAR + GL_REPEAT and no mipmaps computes it; (u, v) in texture space (s / width,
// t / height), v = 0 at the image's first row (rows uploaded in stored order, no flip).
// Returns the texel values / 255 (no sRGB decode). An empty image gives (0, 0, 0, 0).
glm::vec4 sampleBilinearRepeat(const Image& image, float u, float v);

} // namespace bt
