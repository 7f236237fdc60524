#include "bvh/trace_scene.h"

#include "bvh/ray_brush.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace bt {

using namespace trace_detail; // the kernels: ray_brush.h

namespace {

// ---------------------------------------------------------------------------------------------
// Building
// ---------------------------------------------------------------------------------------------

// A plane normal counts as axial when its other two components are below this: importers
// compute normals in double from integer points, so box sides come out exact or within a few
// ulps; anything tilted more than this is traced as a slanted plane, which is always correct.
constexpr double kAxialTolerance = 1e-9;

// The axis (0..2) and box side (0 = min, 1 = max) a plane normal faces, or -1.
int axialSide(const dvec3& n) {
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    if (std::abs(n[b]) < kAxialTolerance && std::abs(n[c]) < kAxialTolerance && std::abs(n[a]) > 0.5) return 2 * a + (n[a] > 0.0 ? 1 : 0);
  }
  return -1;
}

float roundDown(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -kInfinity) : f;
}

float roundUp(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, kInfinity) : f;
}

GpuFace toGpuFace(const Face& f) {
  GpuFace g{};
  for (int a = 0; a < 3; ++a) {
    g.plane[a] = static_cast<float>(f.plane.normal[a]);
    g.origin[a] = static_cast<float>(f.frame.origin[a]);
    g.tangent[a] = static_cast<float>(f.frame.tangent[a]);
    g.bitangent[a] = static_cast<float>(f.frame.bitangent[a]);
  }
  g.plane[3] = static_cast<float>(f.plane.dist);
  g.material = f.material;
  g.brush = f.brush;
  return g;
}

// What TraceScene needs of a face to place it in its brush, worked out once per face while the
// face is converted, so that the brush pass reads two small arrays instead of the faces again.
struct FaceRole {
  static constexpr uint8_t kSlanted = 6, kNoWinding = 7; // else the box side 0..5 (axialSide)
  uint8_t kind;
  float axialPosition; // for a box side: the float plane, dist / normal[axis]
};

FaceRole faceRole(const Face& face) {
  if (face.winding.empty()) return {FaceRole::kNoWinding, 0.0f}; // a redundant plane: it never bounds the brush
  const int side = axialSide(face.plane.normal);
  if (side < 0) return {FaceRole::kSlanted, 0.0f};
  return {static_cast<uint8_t>(side), static_cast<float>(face.plane.dist / face.plane.normal[side / 2])};
}

// The GpuBrush of a scene brush (sideCount counted, firstSide not yet placed), or nothing when
// no face of it has a winding (a brush the importer could not build: nothing of it can be hit).
std::optional<GpuBrush> makeGpuBrush(const Scene& scene, uint32_t brushIndex, std::span<const FaceRole> roles) {
  const Brush& brush = scene.brushes[brushIndex];
  GpuBrush g{};
  std::fill(std::begin(g.axialFace), std::end(g.axialFace), kNoFace);
  std::array<float, 6> axialPosition{};
  bool anyWinding = false;
  for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) {
    const FaceRole role = roles[f];
    if (role.kind == FaceRole::kNoWinding) continue;
    anyWinding = true;
    if (role.kind == FaceRole::kSlanted) {
      ++g.sideCount;
    } else if (g.axialFace[role.kind] == kNoFace) {
      // A convex brush's axial face with a winding lies on its bounding box. A second one on
      // the same side is a duplicate plane, and the first already covers it.
      g.axialFace[role.kind] = f;
      axialPosition[role.kind] = role.axialPosition;
    }
  }
  if (!anyWinding) return std::nullopt;
  // Box sides without an axial face come from the winding bounds, which Brush::bounds holds
  // (scene.h); only a scene that left it empty has its winding points read here.
  Bounds windingBounds = brush.bounds;
  if (windingBounds.empty())
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
      for (const dvec3& p : scene.faces[f].winding) windingBounds.grow(p);
  const dvec3 lo = windingBounds.min, hi = windingBounds.max;
  for (int a = 0; a < 3; ++a) {
    // Sides with an axial face sit exactly at that face's float plane, so that two brushes
    // sharing a face meet with neither a gap nor an overlap; the others are rounded outward.
    g.boundsMin[a] = g.axialFace[2 * a] != kNoFace ? axialPosition[2 * a] : roundDown(lo[a]);
    g.boundsMax[a] = g.axialFace[2 * a + 1] != kNoFace ? axialPosition[2 * a + 1] : roundUp(hi[a]);
  }
  g.sceneBrush = brushIndex;
  return g;
}

// Runs work(begin, end) over [0, count) in `threads` contiguous chunks at once (0 = all cores).
// Every chunk writes only its own part of the output, so the result is the same for any count.
template <typename Work> void parallelChunks(size_t count, int threads, const Work& work) {
  if (threads <= 0) threads = static_cast<int>(std::thread::hardware_concurrency());
  // A chunk is a fraction of a millisecond of work below some 16k items (faces or brushes),
  // less than starting a thread and waiting for it can cost on a busy machine.
  const size_t chunks = std::clamp<size_t>(count / 16384, 1, static_cast<size_t>(std::max(threads, 1)));
  std::vector<std::jthread> helpers;
  for (size_t c = 1; c < chunks; ++c) helpers.emplace_back([&, c] { work(count * c / chunks, count * (c + 1) / chunks); });
  work(0, count / chunks);
}

// The mesh triangles and their BVH. Boxes are the float vertices' bounds widened by a few ulps
// of the coordinates, so that a ray that the widened triangle test accepts at an edge (or a
// flat triangle's box of no thickness) is never refused by its node first.
void buildTriangles(const Scene& scene, const BvhBuildOptions& options, std::vector<GpuBvhNode>& nodes,
                    std::vector<GpuTriangle>& triangles) {
  if (!options.includeMesh.empty() && options.includeMesh.size() != scene.meshes.size())
    throw std::invalid_argument("BvhBuildOptions::includeMesh must be empty or have one entry per mesh");
  std::vector<GpuTriangle> all;
  std::vector<Aabb> boxes;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!options.includeMesh.empty() && !options.includeMesh[m]) continue;
    if (mesh.firstFace > scene.faces.size() || mesh.faceCount > scene.faces.size() - mesh.firstFace)
      throw std::invalid_argument("TraceScene::build: a mesh's faces lie outside Scene::faces");
    for (uint32_t f = mesh.firstFace; f + 1 < mesh.firstFace + mesh.faceCount; f += 2) {
      const std::vector<dvec3>& w = scene.faces[f].winding;
      if (w.size() != 3) continue;
      GpuTriangle t{};
      t.face = f;
      Aabb box{glm::vec3(kInfinity), glm::vec3(-kInfinity)};
      float* corners[3] = {t.v0, t.v1, t.v2};
      for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) {
          corners[k][a] = static_cast<float>(w[k][a]);
          const float pad = std::abs(corners[k][a]) * 0x1p-20f + 0x1p-20f;
          box.min[a] = std::min(box.min[a], corners[k][a] - pad);
          box.max[a] = std::max(box.max[a], corners[k][a] + pad);
        }
      if (!std::isfinite(box.min.x + box.min.y + box.min.z + box.max.x + box.max.y + box.max.z)) continue;
      all.push_back(t);
      boxes.push_back(box);
    }
  }
  if (all.empty()) return;
  FlatBvh bvh = buildBinnedSah(boxes, {options.leafSize, options.binCount, options.threads});
  nodes = std::move(bvh.nodes);
  triangles.resize(bvh.order.size());
  for (size_t i = 0; i < bvh.order.size(); ++i) triangles[i] = all[bvh.order[i]];
}

// The boxes of the brushes that can be traced, and which scene brush each is (boxes[i] is
// the box of scene brush boxBrush[i]).
void traceableBoxes(std::span<const GpuBrush> candidates, std::vector<Aabb>& boxes, std::vector<uint32_t>& boxBrush) {
  boxes.reserve(candidates.size());
  boxBrush.reserve(candidates.size());
  for (const GpuBrush& g : candidates) {
    if (g.sceneBrush == kNoFace) continue;
    // A brush whose bounds overflow float, or whose opposite axial faces cross (a sliver with no
    // inside), cannot be traced, and the builder refuses such boxes; the importers keep
    // coordinates finite and drop brushes without volume, so this only keeps a corrupt scene
    // from throwing.
    const bool finite = std::isfinite(g.boundsMin[0] + g.boundsMin[1] + g.boundsMin[2] + g.boundsMax[0] + g.boundsMax[1] + g.boundsMax[2]);
    const Aabb box{{g.boundsMin[0], g.boundsMin[1], g.boundsMin[2]}, {g.boundsMax[0], g.boundsMax[1], g.boundsMax[2]}};
    if (!finite || box.empty()) continue;
    boxes.push_back(box);
    boxBrush.push_back(g.sceneBrush);
  }
}

// The root's box is the float min and max of all the boxes under it, their bounds: no need to
// grow them box by box.
void growByRoot(Bounds& bounds, std::span<const GpuBvhNode> nodes) {
  if (nodes.empty()) return;
  bounds.grow(dvec3(nodes[0].boundsMin[0], nodes[0].boundsMin[1], nodes[0].boundsMin[2]));
  bounds.grow(dvec3(nodes[0].boundsMax[0], nodes[0].boundsMax[1], nodes[0].boundsMax[2]));
}

// The slanted sides of `brushes` (in leaf order), each brush's after the previous one's, so that
// a leaf's planes are adjacent; sets each brush's firstSide.
std::vector<uint32_t> sidesInLeafOrder(const Scene& scene, std::span<const FaceRole> roles, std::span<GpuBrush> brushes, int threads) {
  uint32_t sideCount = 0;
  for (GpuBrush& g : brushes) {
    g.firstSide = sideCount;
    sideCount += g.sideCount;
  }
  std::vector<uint32_t> sides(sideCount);
  parallelChunks(brushes.size(), threads, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      if (brushes[i].sideCount == 0) continue; // a box: all its sides are axial
      const Brush& brush = scene.brushes[brushes[i].sceneBrush];
      uint32_t side = brushes[i].firstSide;
      for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
        if (roles[f].kind == FaceRole::kSlanted) sides[side++] = f;
    }
  });
  return sides;
}

void checkBuildInput(const Scene& scene, const BvhBuildOptions& options) {
  if (!options.includeBrush.empty() && options.includeBrush.size() != scene.brushes.size())
    throw std::invalid_argument("BvhBuildOptions::includeBrush must be empty or have one entry per brush");
  for (const Brush& b : scene.brushes)
    if (b.firstFace > scene.faces.size() || b.faceCount > scene.faces.size() - b.firstFace)
      throw std::invalid_argument("TraceScene::build: a brush's faces lie outside Scene::faces");
}

} // namespace

TraceScene TraceScene::build(const Scene& scene, const BvhBuildOptions& options) {
  checkBuildInput(scene, options);
  TraceScene ts;
  const int threads = options.threads;
  ts.faces_.resize(scene.faces.size());
  std::vector<FaceRole> roles(scene.faces.size());
  parallelChunks(scene.faces.size(), threads, [&](size_t begin, size_t end) {
    for (size_t f = begin; f < end; ++f) {
      ts.faces_[f] = toGpuFace(scene.faces[f]);
      roles[f] = faceRole(scene.faces[f]);
    }
  });

  // Every brush in scene order first (sceneBrush == kNoFace: not traced); they are put in leaf
  // order once the BVH has fixed it.
  std::vector<GpuBrush> candidates(scene.brushes.size());
  parallelChunks(scene.brushes.size(), threads, [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; ++b) {
      candidates[b].sceneBrush = kNoFace;
      if (!options.includeBrush.empty() && !options.includeBrush[b]) continue;
      if (std::optional<GpuBrush> g = makeGpuBrush(scene, static_cast<uint32_t>(b), roles)) candidates[b] = *g;
    }
  });
  std::vector<Aabb> boxes;
  std::vector<uint32_t> boxBrush;
  traceableBoxes(candidates, boxes, boxBrush);

  FlatBvh bvh = buildBinnedSah(boxes, {options.leafSize, options.binCount, options.threads});
  ts.nodes_ = std::move(bvh.nodes);
  growByRoot(ts.bounds_, ts.nodes_);
  // Brushes and their side lists in leaf order, so a leaf's brushes and planes are adjacent.
  ts.brushes_.resize(bvh.order.size());
  parallelChunks(ts.brushes_.size(), threads, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) ts.brushes_[i] = candidates[boxBrush[bvh.order[i]]];
  });
  ts.sides_ = sidesInLeafOrder(scene, roles, ts.brushes_, threads);
  ts.wideNodes_ = collapseToWide(ts.nodes_, ts.brushes_);
  ts.sahCost_ = bt::sahCost(ts.nodes_);
  buildTriangles(scene, options, ts.triangleNodes_, ts.triangles_);
  growByRoot(ts.bounds_, ts.triangleNodes_);
  return ts;
}

std::optional<Hit> TraceScene::intersectBrush(const Ray& ray, uint32_t brushIndex) const {
  return intersectBrush(RayContext(ray), brushIndex);
}

std::optional<Hit> TraceScene::intersectBrush(const RayContext& r, uint32_t brushIndex) const {
  Hit hit;
  const GpuBrush& brush = brushes_.at(brushIndex);
  hit.slot = brushIndex;
  const bool found =
      r.hasZeroComponent ? hitBrush<true>(r, brush, sides_, faces_, r.tMax, hit) : hitBrush<false>(r, brush, sides_, faces_, r.tMax, hit);
  if (found) return hit;
  return std::nullopt;
}

std::optional<bool> TraceScene::entersBox(const RayContext& r, uint32_t brushIndex) const {
  const GpuBrush& brush = brushes_[brushIndex];
  if (r.hasZeroComponent || brush.sideCount != 0) return std::nullopt;
  for (uint32_t face : brush.axialFace)
    if (face == kNoFace) return std::nullopt;
  // hitBrush<false> on a box: brushBox's near and far (the same values as these), no planes, and
  // the entry's face is the axial face of the side that set near, which exists.
  float near, far;
#if BT_SSE_NODE_TEST
  boxInterval(r, brush.boundsMin, brush.boundsMax, near, far);
#else
  const Slab box = intersectBox<false>(r, brush.boundsMin, brush.boundsMax);
  near = box.near, far = box.far;
#endif
  return near <= far && near > r.tMin && near < r.tMax;
}

namespace {

// Moller-Trumbore against one mesh triangle (gpu_structs.h GpuTriangle has the rules), double-sided.
[[gnu::always_inline]] inline bool hitTriangle(const RayContext& r, const GpuTriangle& tri, float tLimit, Hit& hit) {
  const glm::vec3 v0(tri.v0[0], tri.v0[1], tri.v0[2]);
  const glm::vec3 e1 = glm::vec3(tri.v1[0], tri.v1[1], tri.v1[2]) - v0;
  const glm::vec3 e2 = glm::vec3(tri.v2[0], tri.v2[1], tri.v2[2]) - v0;
  const glm::vec3 p = glm::cross(r.direction, e2);
  const float det = glm::dot(e1, p);
  if (det == 0.0f) return false; // the ray lies in the triangle's plane: it sees no area
  const float inv = 1.0f / det;
  const glm::vec3 s = r.origin - v0;
  const float u = glm::dot(s, p) * inv;
  if (u < -kTriangleEdgeEpsilon || u > 1.0f + kTriangleEdgeEpsilon) return false;
  const glm::vec3 q = glm::cross(s, e1);
  const float v = glm::dot(r.direction, q) * inv;
  if (v < -kTriangleEdgeEpsilon || u + v > 1.0f + kTriangleEdgeEpsilon) return false;
  const float t = glm::dot(e2, q) * inv;
  if (!(t > r.tMin && t < r.tMax) || t > tLimit) return false;
  hit.t = t;
  hit.face = det > 0.0f ? tri.face : tri.face + 1;
  hit.brush = kNoBrush;
  hit.inside = false;
  return true;
}

// Depth-first traversal, nearer child first, with a stack of kBvhMaxDepth entries, which the
// builder guarantees is enough (tinybvh's scheme). hitItem(i, tLimit, hit) tests leaf item i.
// `best` comes in with the limit (best.t: tMax, or the closest hit of the other BVH) and the hit
// that set it, and goes out with the closest of both.
template <bool AnyHit, bool ZeroSafe, class HitItem>
[[gnu::always_inline]] inline bool traverse(const RayContext& r, std::span<const GpuBvhNode> nodes, const HitItem& hitItem, Hit& best) {
  if (nodes.empty()) return false;
  bool found = false;
  float near = 0.0f;
  if (!nodeOverlaps<ZeroSafe>(r, nodes[0], best.t, near)) return false;

  uint32_t stack[kBvhMaxDepth];
  int top = 0;
  uint32_t current = 0;
  for (;;) {
    const GpuBvhNode& node = nodes[current];
    if (node.count > 0) {
      for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i) {
        Hit hit;
        if (hitItem(i, best.t, hit) && closer(hit, best)) {
          best = hit;
          best.slot = i;
          found = true;
          if constexpr (AnyHit) return true;
        }
      }
    } else {
      uint32_t a = node.leftFirst, b = node.leftFirst + 1;
      float nearA = 0.0f, nearB = 0.0f;
      const bool hitA = nodeOverlaps<ZeroSafe>(r, nodes[a], best.t, nearA);
      const bool hitB = nodeOverlaps<ZeroSafe>(r, nodes[b], best.t, nearB);
      if (hitA && hitB) {
        if (nearB < nearA) std::swap(a, b);
        stack[top++] = b;
        current = a;
        continue;
      }
      if (hitA || hitB) {
        current = hitA ? a : b;
        continue;
      }
    }
    // Pop, skipping nodes that a closer hit found since has made irrelevant. An any-hit walk
    // returns at its first hit, so its limit has not moved since the node was pushed.
    for (;;) {
      if (top == 0) return found;
      current = stack[--top];
      if (AnyHit || nodeOverlaps<ZeroSafe>(r, nodes[current], best.t, near)) break;
    }
  }
}

#if BT_SSE_NODE_TEST
// traverse<false, false>() over the brushes on the wide tree (bvh/wide_bvh.h): the closest hit
// of a ray without a zero direction component. A node's four boxes in one pass, each lane the
// floats of nodeOverlaps on that box, so a lane is visited exactly when the binary walk would
// visit its node (given the same best t), and every brush that can be the closest hit is tested.
// The closest hit does not depend on the order (trace_scene.h), so the walk takes the lanes
// nearest first, as the binary walk takes the nearer child. The any-hit walks stay on the binary
// tree: the hit they return is the first of their order, and the bake's shadow cache keeps it
// (with this walk's order lqdm5's luxels changed, bench/README.md issue 18 session 27).
bool traverseWide(const RayContext& r, const TraceScene& ts, Hit& best) {
  const std::span<const WideBvhNode> nodes = ts.wideNodes();
  if (nodes.empty()) return false;
  const std::span<const GpuBrush> brushes = ts.brushes();
  const std::span<const uint32_t> sides = ts.sides();
  const std::span<const GpuFace> faces = ts.faces();
  const __m128 ox = _mm_set1_ps(r.origin.x), oy = _mm_set1_ps(r.origin.y), oz = _mm_set1_ps(r.origin.z);
  const __m128 ix = _mm_set1_ps(r.invDirection.x), iy = _mm_set1_ps(r.invDirection.y), iz = _mm_set1_ps(r.invDirection.z);
  const __m128 tMin = _mm_set1_ps(r.tMin);

  struct Entry {
    uint32_t child, count; // a lane's (WideBvhNode)
    float near;            // its box's near t: once the best t is below it, nothing there can win
  };
  Entry stack[kWideBvhStackSize];
  int top = 0;
  bool found = false;
  const auto leaf = [&](uint32_t first, uint32_t count) {
    for (uint32_t i = first; i < first + count; ++i) {
      Hit hit;
      if (hitBrush<false>(r, brushes[i], sides, faces, best.t, hit) && closer(hit, best)) {
        best = hit;
        best.slot = i;
        found = true;
      }
    }
  };
  uint32_t current = 0; // an inner node
  for (;;) {
    const WideBvhNode& node = nodes[current];
    const __m128 x0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.lo[0]), ox), ix), x1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.hi[0]), ox), ix);
    const __m128 y0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.lo[1]), oy), iy), y1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.hi[1]), oy), iy);
    const __m128 z0 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.lo[2]), oz), iz), z1 = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(node.hi[2]), oz), iz);
    const __m128 near = _mm_max_ps(_mm_max_ps(_mm_min_ps(x0, x1), _mm_min_ps(y0, y1)), _mm_min_ps(z0, z1));
    const __m128 far = _mm_min_ps(_mm_min_ps(_mm_max_ps(x0, x1), _mm_max_ps(y0, y1)), _mm_max_ps(z0, z1));
    const __m128 overlaps = _mm_and_ps(_mm_cmple_ps(_mm_max_ps(near, tMin), _mm_min_ps(far, _mm_set1_ps(best.t))), _mm_cmple_ps(near, far));
    int visit = _mm_movemask_ps(overlaps);
    Entry next{0, 0, 0.0f};
    bool descend = false;
    if (visit != 0) {
      alignas(16) float nears[4];
      _mm_store_ps(nears, near);
      int lane = std::countr_zero(unsigned(visit));
      visit &= visit - 1;
      next = {node.child[lane], node.count[lane], nears[lane]};
      descend = true;
      // More than one: the others onto the stack farthest first (an insertion sort of at most
      // three), the nearest of all taken next.
      Entry* first = stack + top;
      for (; visit != 0; visit &= visit - 1) {
        lane = std::countr_zero(unsigned(visit));
        Entry in{node.child[lane], node.count[lane], nears[lane]};
        if (in.near < next.near) std::swap(in, next);
        Entry* at = stack + top++;
        for (; at > first && at[-1].near < in.near; --at) *at = at[-1];
        *at = in;
      }
    }
    // The next inner node: the nearest lane's, else the nearest on the stack, leaves tested on
    // the way.
    for (;;) {
      if (descend) {
        if (next.count == 0) break;
        leaf(next.child, next.count);
      }
      if (top == 0) return found;
      next = stack[--top];
      descend = next.near <= best.t;
    }
    current = next.child;
  }
}
#endif

// Brushes, then (only when the level has meshes) triangles up to the closest brush hit.
template <bool AnyHit, bool ZeroSafe> bool traceBoth(const RayContext& r, const TraceScene& ts, Hit& best) {
  best.t = r.tMax;
  best.face = kNoFace;
  const std::span<const GpuBrush> brushes = ts.brushes();
  const std::span<const uint32_t> sides = ts.sides();
  const std::span<const GpuFace> faces = ts.faces();
  bool found;
#if BT_SSE_NODE_TEST
  if constexpr (!ZeroSafe && !AnyHit)
    found = traverseWide(r, ts, best);
  else
#endif
    found = traverse<AnyHit, ZeroSafe>(
        r, ts.nodes(),
        [&r, brushes, sides, faces](uint32_t i, float tLimit, Hit& hit) {
          return hitBrush<ZeroSafe>(r, brushes[i], sides, faces, tLimit, hit);
        },
        best);
  if (ts.triangleNodes().empty() || (AnyHit && found)) return found;
  const std::span<const GpuTriangle> triangles = ts.triangles();
  found |= traverse<AnyHit, ZeroSafe>(
      r, ts.triangleNodes(), [&r, triangles](uint32_t i, float tLimit, Hit& hit) { return hitTriangle(r, triangles[i], tLimit, hit); },
      best);
  return found;
}

} // namespace

std::optional<Hit> TraceScene::intersectTriangle(const Ray& ray, uint32_t triangleIndex) const {
  Hit hit;
  hit.slot = triangleIndex;
  if (hitTriangle(RayContext(ray), triangles_.at(triangleIndex), ray.tMax, hit)) return hit;
  return std::nullopt;
}

std::optional<Hit> TraceScene::closestHit(const Ray& ray) const {
  Hit best;
  const RayContext r(ray);
  const bool found = r.hasZeroComponent ? traceBoth<false, true>(r, *this, best) : traceBoth<false, false>(r, *this, best);
  if (found) return best;
  return std::nullopt;
}

bool TraceScene::occluded(const Ray& ray) const {
  Hit any;
  const RayContext r(ray);
  return r.hasZeroComponent ? traceBoth<true, true>(r, *this, any) : traceBoth<true, false>(r, *this, any);
}

std::optional<Hit> TraceScene::anyHit(const Ray& ray) const {
  return anyHit(RayContext(ray));
}

std::optional<Hit> TraceScene::anyHit(const RayContext& r) const {
  Hit any;
  const bool found = r.hasZeroComponent ? traceBoth<true, true>(r, *this, any) : traceBoth<true, false>(r, *this, any);
  if (!found) return std::nullopt;
  return any;
}

glm::vec2 textureCoordinates(const GpuFace& face, const glm::vec3& p) {
  const glm::vec3 d = p - glm::vec3(face.origin[0], face.origin[1], face.origin[2]);
  return {glm::dot(d, glm::vec3(face.tangent[0], face.tangent[1], face.tangent[2])),
          glm::dot(d, glm::vec3(face.bitangent[0], face.bitangent[1], face.bitangent[2]))};
}

} // namespace bt
