#include "lighting/qbsp_faces.h"

#include "lighting/game_rules.h"
#include "quake/bspfile_q2.h"
#include "quake/entity_keys.h"
#include "scene/parallel_for.h"
#include "scene/winding.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace bt {

namespace {

constexpr double kMinPieceWidth = 8.0;       // GLQuake does not cut off slivers thinner than this
constexpr double kContinuousEpsilon = 0.005; // qbsp: edges turning less than this go straight on

void subdivide(const Winding& w, double size, std::vector<Winding>& pieces) {
  if (w.size() < 3) return;
  if (pieces.size() >= kMaxPiecesPerFace) {
    pieces.push_back(w); // the rest stays whole
    return;
  }
  dvec3 lo = w[0], hi = w[0];
  for (const dvec3& p : w) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (int axis = 0; axis < 3; ++axis) {
    const double cut = size * std::floor((lo[axis] + hi[axis]) * 0.5 / size + 0.5);
    if (hi[axis] - cut < kMinPieceWidth || cut - lo[axis] < kMinPieceWidth) continue;
    Plane plane;
    plane.normal = dvec3(0.0);
    plane.normal[axis] = 1.0;
    plane.dist = cut;
    const SplitWinding split = splitWinding(w, plane, 0.0);
    subdivide(split.front, size, pieces);
    subdivide(split.back, size, pieces);
    return;
  }
  pieces.push_back(w);
}

} // namespace

void subdivideForQbsp(const Winding& w, const TextureFrame& frame, std::vector<Winding>& pieces) {
  constexpr double kSubdivideTexels = 240.0, kCutMargin = 16.0;
  // Cut in qbsp's winding (ours the other way round): where each piece starts is where its clip
  // starts it, and that decides its T-junction fans.
  std::vector<Winding> current{Winding(w.rbegin(), w.rend())}, next;
  for (const dvec3& axis : {frame.tangent, frame.bitangent}) {
    const double scale = glm::length(axis);
    if (scale <= 0.0) continue;
    for (Winding rest : current) {
      while (rest.size() >= 3 && current.size() + next.size() < kMaxPiecesPerFace) {
        double lo = 1e300, hi = -1e300;
        for (const dvec3& p : rest) lo = std::min(lo, glm::dot(p, axis)), hi = std::max(hi, glm::dot(p, axis));
        if (std::ceil(hi) - std::floor(lo) <= kSubdivideTexels) break;
        const Plane cut{axis / scale, (lo + kSubdivideTexels - kCutMargin) / scale};
        SplitWinding split = splitWinding(rest, cut, 0.0);
        if (split.front.size() < 3 || split.back.size() < 3) break; // nothing cut off: keep it whole
        next.push_back(std::move(split.back));
        rest = std::move(split.front);
      }
      if (rest.size() >= 3) next.push_back(std::move(rest));
    }
    current.swap(next);
    next.clear();
  }
  for (Winding& piece : current) pieces.emplace_back(piece.rbegin(), piece.rend());
}

namespace {

// Carves brush `b` out of `fragments` (qbsp's CSG): the parts in front of any of its planes
// stay, the part behind all of them goes. A fragment lying on one of its planes stays when it
// faces the same way (it is that brush's neighbour, not buried in it), unless `ownsCoplanar`:
// qbsp makes one face of a portal, from the side of the brush that comes later in the map
// (FindPortalSide), so a later brush's coplanar side takes the overlap.
void carve(const Scene& scene, const Brush& brush, const dvec3& faceNormal, std::vector<Winding>& fragments, bool ownsCoplanar) {
  std::vector<Winding> kept;
  for (Winding& fragment : fragments) {
    Winding inside = std::move(fragment);
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount && !inside.empty(); ++f) {
      const Plane& plane = scene.faces[f].plane;
      // splitWinding's answer where the fragment lies on one side, or on the plane, found without
      // copying it: most brushes a side's box reaches only touch it (each side's visibility in
      // quake1WorldTree carves every side of the level).
      bool anyFront = false, anyBack = false;
      for (const dvec3& p : inside) {
        const double d = plane.distanceTo(p);
        anyFront = anyFront || d > kOnPlaneEpsilon;
        anyBack = anyBack || d < -kOnPlaneEpsilon;
      }
      if (!anyFront && !anyBack) { // on the plane
        if (glm::dot(plane.normal, faceNormal) > 0.0 && !ownsCoplanar) {
          kept.push_back(std::move(inside));
          inside.clear();
        }
        continue;
      }
      if (!anyBack) { // in front: outside the brush, all of it
        kept.push_back(std::move(inside));
        inside.clear();
        break;
      }
      if (!anyFront) continue; // behind: the next plane decides
      SplitWinding split = splitWinding(inside, plane, kOnPlaneEpsilon);
      if (split.front.size() >= 3) kept.push_back(std::move(split.front));
      inside = split.back.size() >= 3 ? std::move(split.back) : Winding{};
    }
  }
  fragments = std::move(kept);
}

// Drops vertices where the polygon goes straight on; false when it turns the wrong way
// anywhere (not convex, seen from the side `normal` points to, counter-clockwise).
bool makeConvex(Winding& w, const dvec3& normal) {
  removeDuplicatePoints(w, 1e-6); // an edge without length has no direction
  for (size_t i = 0; i < w.size() && w.size() >= 3;) {
    const dvec3& prev = w[(i + w.size() - 1) % w.size()];
    const dvec3& next = w[(i + 1) % w.size()];
    const dvec3 in = glm::normalize(w[i] - prev), out = glm::normalize(next - w[i]);
    const double turn = glm::dot(glm::cross(in, out), normal);
    if (turn < -kContinuousEpsilon) return false;
    if (turn <= kContinuousEpsilon)
      w.erase(w.begin() + std::ptrdiff_t(i));
    else
      ++i;
  }
  return w.size() >= 3;
}

// qbsp's TryMerge: two coplanar polygons sharing an edge become one when the result is convex.
std::optional<Winding> tryMerge(const Winding& a, const Winding& b, const dvec3& normal) {
  auto same = [](const dvec3& p, const dvec3& q) { return glm::length(p - q) < kOnPlaneEpsilon; };
  for (size_t i = 0; i < a.size(); ++i)
    for (size_t j = 0; j < b.size(); ++j) {
      const size_t i1 = i + 1 == a.size() ? 0 : i + 1, j1 = j + 1 == b.size() ? 0 : j + 1;
      if (!same(a[i], b[j1]) || !same(a[i1], b[j])) continue;
      // b past the shared edge, then a from a[i1] round to a[i]: qbsp's merged winding (its f1
      // from the shared edge's second point on, then f2's) the other way round, so that it starts
      // where qbsp's does (our last point is its first).
      Winding merged;
      for (size_t k = 2; k < b.size(); ++k) merged.push_back(b[(j + k) % b.size()]);
      for (size_t k = 0; k < a.size(); ++k) merged.push_back(a[(i1 + k) % a.size()]);
      if (makeConvex(merged, normal)) return merged;
      return std::nullopt;
    }
  return std::nullopt;
}

Bounds boundsOf(const Winding& w) {
  Bounds b;
  for (const dvec3& p : w) b.grow(p);
  return b;
}

// Polygons whose boxes are this far apart on some axis have no two vertices that tryMerge
// takes for the same (twice its tolerance: no rounding in the distance can bridge that).
bool apartForMerge(const Bounds& a, const Bounds& b) {
  for (int i = 0; i < 3; ++i)
    if (a.min[i] > b.max[i] + 2.0 * kOnPlaneEpsilon || b.min[i] > a.max[i] + 2.0 * kOnPlaneEpsilon) return true;
  return false;
}

// qbsp's MergeAll over one plane and texture: merge until no pair merges any more, each time the
// first pair in order (i, then j > i) that merges.
void mergeCoplanar(std::vector<Winding>& polygons, const dvec3& normal) {
  std::vector<Bounds> bounds;
  for (const Winding& w : polygons) bounds.push_back(boundsOf(w));
  auto merge = [&](size_t i, size_t j) {
    if (apartForMerge(bounds[i], bounds[j])) return false;
    std::optional<Winding> m = tryMerge(polygons[i], polygons[j], normal);
    if (!m) return false;
    polygons[i] = std::move(*m);
    bounds[i] = boundsOf(polygons[i]);
    polygons.erase(polygons.begin() + std::ptrdiff_t(j));
    bounds.erase(bounds.begin() + std::ptrdiff_t(j));
    return true;
  };
  // After a merge into polygon `changed`, the pairs of the rows before it that do not include it
  // failed before and fail again (tryMerge reads only the two polygons): those rows are tried
  // against `changed` alone.
  size_t changed = 0;
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < polygons.size() && !merged; ++i) {
      if (i < changed) {
        if ((merged = merge(i, changed))) changed = i;
        continue;
      }
      for (size_t j = i + 1; j < polygons.size() && !merged; ++j)
        if ((merged = merge(i, j))) changed = i;
    }
  }
}

bool overlaps(const Bounds& a, const Bounds& b) {
  for (int i = 0; i < 3; ++i)
    if (a.min[i] > b.max[i] + kOnPlaneEpsilon || b.min[i] > a.max[i] + kOnPlaneEpsilon) return false;
  return true;
}

// --- the compiler's faces of a brush model's surface -----------------------------------------
//
// qbsp builds its faces from the portals of a BSP tree and merges, on each node, the pieces
// that make a convex polygon again, so where the tree's split planes fall decides the faces'
// shapes (and with them where the surface lights go). The world's sides go down the world's
// tree (below); a brush model's we split with a small tree grown on the surface alone, the way
// qbsp3 grows its tree: the brushes that reach the surface's plane leave their cross-sections ("footprints")
// on it, and the surface is split by the planes of the footprints' edges, the best first by
// SelectSplitSide's rule, until what is left of the surface in a cell is one convex polygon.

constexpr double kPlaneSideEpsilon = 0.1; // qbsp3 counts a point this close to a plane as on it
// qbsp3 counts the brush sides a plane cuts; a plane standing on the surface that cuts a brush's
// footprint cuts four of its sides: the two the line crosses, and the brush's top and bottom.
constexpr int kSidesCutPerBrush = 4;
constexpr double kWorldHalfSize = 65536.0;

// The part of `brush` that lies on `plane`; empty when the brush does not reach the plane.
Winding crossSection(const Scene& scene, const Brush& brush, const Plane& plane) {
  Winding w = baseWinding(plane, kWorldHalfSize);
  for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount && !w.empty(); ++f)
    w = clipBehind(w, scene.faces[f].plane, kOnPlaneEpsilon);
  return w.size() >= 3 && area(w) > 1.0 ? w : Winding{};
}

enum PlaneSide { kFront = 1, kBack = 2, kBoth = 3 }; // qbsp3's PSIDE_*

int sideOf(const Winding& w, const Plane& plane) {
  int side = 0;
  for (const dvec3& p : w) {
    const double d = plane.distanceTo(p);
    if (d > kPlaneSideEpsilon) side |= kFront;
    if (d < -kPlaneSideEpsilon) side |= kBack;
  }
  return side;
}

bool hasEdgeOn(const Winding& w, const Plane& plane) {
  for (size_t i = 0; i < w.size(); ++i)
    if (std::abs(plane.distanceTo(w[i])) < kPlaneSideEpsilon && std::abs(plane.distanceTo(w[(i + 1) % w.size()])) < kPlaneSideEpsilon)
      return true;
  return false;
}

bool isAxial(const Plane& plane) {
  return std::abs(plane.normal.x) == 1.0 || std::abs(plane.normal.y) == 1.0 || std::abs(plane.normal.z) == 1.0;
}

// The planes standing on the surface through the footprints' edges, each once, its largest
// normal component positive.
std::vector<Plane> edgePlanes(const std::vector<Winding>& footprints, const dvec3& surfaceNormal) {
  std::vector<Plane> planes;
  for (const Winding& w : footprints)
    for (size_t i = 0; i < w.size(); ++i) {
      const dvec3 along = glm::cross(w[(i + 1) % w.size()] - w[i], surfaceNormal);
      if (glm::length(along) < 1e-6) continue;
      Plane plane;
      plane.normal = glm::normalize(along);
      int major = 0;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(plane.normal[k]) < 1e-9) plane.normal[k] = 0.0; // axial edges give axial planes
        if (std::abs(plane.normal[k]) > std::abs(plane.normal[major])) major = k;
      }
      if (plane.normal[major] < 0.0) plane.normal = -plane.normal;
      plane.dist = glm::dot(plane.normal, w[i]);
      const bool known = std::any_of(planes.begin(), planes.end(), [&](const Plane& q) {
        return glm::length(q.normal - plane.normal) < 1e-6 && std::abs(q.dist - plane.dist) < kOnPlaneEpsilon;
      });
      if (!known) planes.push_back(plane);
    }
  return planes;
}

// qbsp3's SelectSplitSide over the footprints in a cell (ericw-tools' SelectSplitPlane:
// 5 facing - 5 sides cut - |front - back|, +5 when axial): brushes with a side on the plane count
// for it, the sides it cuts against it, and so does an unbalanced split. Only planes that cut the
// surface's fragments in the cell are candidates; the first of equal value wins.
const Plane* chooseSplit(const std::vector<Winding>& fragments, const std::vector<Winding>& footprints,
                         const std::vector<Plane>& candidates) {
  const Plane* best = nullptr;
  int bestValue = std::numeric_limits<int>::min();
  for (const Plane& plane : candidates) {
    int fragmentSides = 0;
    for (const Winding& w : fragments) fragmentSides |= sideOf(w, plane);
    if (fragmentSides != kBoth) continue;
    int facing = 0, splits = 0, front = 0, back = 0;
    for (const Winding& w : footprints) {
      facing += hasEdgeOn(w, plane);
      const int side = sideOf(w, plane);
      splits += side == kBoth;
      front += side == kFront;
      back += side == kBack;
    }
    const int value = 5 * facing - 5 * kSidesCutPerBrush * splits - std::abs(front - back) + (isAxial(plane) ? 5 : 0);
    if (value > bestValue) bestValue = value, best = &plane;
  }
  return best;
}

void splitAll(const std::vector<Winding>& polygons, const Plane& plane, std::vector<Winding>& front, std::vector<Winding>& back) {
  for (const Winding& w : polygons) {
    SplitWinding split = splitWinding(w, plane, 0.0);
    if (split.front.size() >= 3 && area(split.front) > 1e-3) front.push_back(std::move(split.front));
    if (split.back.size() >= 3 && area(split.back) > 1e-3) back.push_back(std::move(split.back));
  }
}

void splitIntoFaces(const std::vector<Winding>& fragments, const std::vector<Winding>& footprints, const std::vector<Plane>& candidates,
                    const dvec3& normal, std::vector<Winding>& faces) {
  if (fragments.empty()) return;
  std::vector<Winding> merged = fragments;
  mergeCoplanar(merged, normal);
  const Plane* split = merged.size() > 1 ? chooseSplit(fragments, footprints, candidates) : nullptr;
  if (!split) {
    for (Winding& w : merged) faces.push_back(std::move(w));
    return;
  }
  // Each candidate cuts the fragments at most once on a path down the tree: depth is bounded.
  std::vector<Winding> frontFragments, backFragments, frontFootprints, backFootprints;
  splitAll(fragments, *split, frontFragments, backFragments);
  splitAll(footprints, *split, frontFootprints, backFootprints);
  splitIntoFaces(frontFragments, frontFootprints, candidates, normal, faces);
  splitIntoFaces(backFragments, backFootprints, candidates, normal, faces);
}

// --- the compiler's faces of a world side: its pieces on the nodes of the world's tree ---------

// qbsp's MergeFaceList (merge.cc MergeFaceToList): each face in turn is merged into the first face
// of the list it merges with, the result tried against the list from its start again, and what
// merges with none joins the list's end.
std::vector<Winding> mergeFaceList(const std::vector<Winding>& faces, const dvec3& normal) {
  std::vector<Winding> list;
  for (Winding face : faces) {
    for (size_t i = 0; i < list.size();) {
      std::optional<Winding> merged = apartForMerge(boundsOf(face), boundsOf(list[i])) ? std::nullopt : tryMerge(face, list[i], normal);
      if (!merged) {
        ++i;
        continue;
      }
      list.erase(list.begin() + std::ptrdiff_t(i));
      face = std::move(*merged);
      i = 0;
    }
    list.push_back(std::move(face));
  }
  return list;
}

// A plane of the tree and the side of it a polygon lies on (0 front, 1 back).
struct PathStep {
  const Plane* plane;
  int side;
};

// The pieces of `fragments` in one leaf under a node, with the planes from that node down to the
// leaf (the cuts qbsp makes in the node's portal on the way there).
struct LeafPieces {
  std::vector<Winding> pieces;
  std::vector<PathStep> path;
};

// `fragments` cut by the planes of the tree under `node`, one list per leaf, the front child's
// leaves first (the order qbsp's MakeFaces_r visits them).
void leafPieces(const QbspTree& tree, int32_t node, std::vector<Winding> fragments, std::vector<PathStep>& path,
                std::vector<LeafPieces>& leaves) {
  if (fragments.empty()) return;
  if (node < 0) {
    leaves.push_back({std::move(fragments), path});
    return;
  }
  const QbspTree::Node& n = tree.nodes()[size_t(node)];
  std::vector<Winding> front, back;
  splitAll(fragments, n.plane, front, back);
  path.push_back({&n.plane, 0});
  leafPieces(tree, n.children[0], std::move(front), path, leaves);
  path.back().side = 1;
  leafPieces(tree, n.children[1], std::move(back), path, leaves);
  path.pop_back();
}

// ericw-tools' BaseWindingForPlane: a square of half-size `extent` on `plane`, its points in the
// compiler's order (clockwise seen from the front, the reverse of ours). Where each of qbsp's
// faces starts comes from here through every clip.
Winding qbspBaseWinding(const Plane& plane, double extent) {
  int major = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(plane.normal[i]) > std::abs(plane.normal[major])) major = i;
  dvec3 up(0.0);
  up[major == 2 ? 0 : 2] = 1.0;
  up = glm::normalize(up - plane.normal * glm::dot(up, plane.normal));
  const dvec3 org = plane.normal * plane.dist;
  const dvec3 right = glm::cross(up, plane.normal) * extent;
  up *= extent;
  return {org - right + up, org + right + up, org + right - up, org - right - up};
}

// ericw-tools' winding clip, the part on `side` of `plane`: the points kept in their order from the
// first, each crossing where an edge crosses (its start stays the first point kept).
Winding qbspClip(const Winding& w, const Plane& plane, int side, double epsilon) {
  const Plane facing = side == 0 ? plane : plane.flipped();
  SplitWinding split = splitWinding(w, facing, epsilon);
  return std::move(split.front);
}

// The contents that the face `piece` (facing `normal`) looks into: those of the world's fillers
// (QbspTree::Filler) around the point 1 unit in front of its vertices' mean, or'd together (0:
// empty space).
int32_t contentsInFrontOf(const Scene& scene, const QbspTree& world, const Winding& piece, const dvec3& normal) {
  if (world.fillers().empty()) return 0;
  dvec3 c(0.0);
  for (const dvec3& p : piece) c += p;
  c = c / double(piece.size()) + normal * kVoidProbeDistance;
  int32_t front = 0;
  for (const auto& [b, bits] : world.fillers()) {
    const Brush& brush = scene.brushes[b];
    if (glm::any(glm::lessThan(c, brush.bounds.min)) || glm::any(glm::greaterThan(c, brush.bounds.max))) continue;
    bool inside = true;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount && inside; ++f)
      inside = scene.faces[f].plane.distanceTo(c) < 0.0;
    if (inside) front |= bits;
  }
  return front;
}

// qbsp's faces on one node: TryMerge merges only faces that look into the same contents (the
// floor under q2_areaportals' doorways looks into their area portals and stays a face of its
// own), so mergeFaceList runs on each such group of `pieces`, the groups in the order of their
// first pieces.
std::vector<Winding> mergeNodeFaces(const Scene& scene, const QbspTree& world, const std::vector<Winding>& pieces, const dvec3& normal) {
  std::vector<int32_t> keys;
  std::vector<std::vector<Winding>> groups;
  for (const Winding& w : pieces) {
    const int32_t key = contentsInFrontOf(scene, world, w, normal);
    const size_t g = size_t(std::find(keys.begin(), keys.end(), key) - keys.begin());
    if (g == keys.size()) keys.push_back(key), groups.emplace_back();
    groups[g].push_back(w);
  }
  std::vector<Winding> merged;
  for (const std::vector<Winding>& group : groups)
    for (Winding& w : mergeFaceList(group, normal)) merged.push_back(std::move(w));
  return merged;
}

// Rotates `piece` to end at `start` when it has that point: our windings run the other way round
// from qbsp's, so qbsp's first point is our last.
void endAt(Winding& piece, const dvec3& start) {
  for (size_t k = 0; k < piece.size(); ++k)
    if (glm::length(piece[k] - start) < kOnPlaneEpsilon) {
      std::rotate(piece.begin(), piece.begin() + std::ptrdiff_t(k + 1), piece.end());
      return;
    }
}

constexpr double kPortalEpsilon = 0.001; // BASE_WINDING_EPSILON, SPLIT_WINDING_EPSILON
constexpr double kBoundaryEpsilon = 0.1; // MakeNodePortal's clip by the node's boundary portals
// The box of the headnode portals: qbsp's is the world's bounds and 24 units more; any box that
// holds the level and lies inside the base windings cuts the same corners in the same order.
constexpr double kHeadnodeBox = 32768.0;

// The face qbsp makes of one portal from our pieces of the side in that portal's cell (`portal`
// in our winding; empty if clipped away). qbsp's face is the portal itself, whole, however CSG
// cut the side around it (a side carved by a neighbour is split along that neighbour's planes
// even where it does not touch it): when the pieces join into the portal's polygon, they are the
// portal, starting where it starts; otherwise each piece keeps its shape and ends where qbsp's
// starts, where it has that point.
std::vector<Winding> cellFaces(std::vector<Winding> pieces, Winding portal, const dvec3& normal) {
  if (portal.size() < 3) return pieces;
  std::vector<Winding> joined = mergeFaceList(pieces, normal);
  if (joined.size() == 1 && std::abs(area(joined.front()) - area(portal)) < kOnPlaneEpsilon) {
    auto onBoundary = [&](const dvec3& p) {
      const Winding& w = joined.front();
      for (size_t i = 0; i < w.size(); ++i) {
        const dvec3 a = w[i], b = w[(i + 1) % w.size()];
        const double t = glm::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        if (glm::length(a + (b - a) * t - p) < kOnPlaneEpsilon) return true;
      }
      return false;
    };
    if (std::all_of(portal.begin(), portal.end(), onBoundary)) return {std::move(portal)};
  }
  for (Winding& piece : pieces) endAt(piece, portal.back());
  return pieces;
}

struct NodeFaceContext {
  const Scene& scene;
  const QbspTree& tree;
  const Plane& surface;
};

// Hands `fragments` of a side on plane `surface` down the tree from `node`: each node's plane
// cuts them, until the node whose plane is the side's own. There qbsp makes the side's faces of
// the portals between the leaves on its two sides (cut by the planes of both subtrees), visiting
// the leaves the side looks into, and merges them on the node (faces.cc MakeFaces_r,
// MergeNodeFaces): the planes below the node cut no face, those above do, and neither does the
// merge join faces that look into different contents (mergeNodeFaces). `above` holds the planes
// from the root down to `node`.
void nodeFaces(const NodeFaceContext& ctx, int32_t node, std::vector<Winding> fragments, std::vector<PathStep>& above,
               std::vector<Winding>& faces) {
  const QbspTree& tree = ctx.tree;
  const Plane& surface = ctx.surface;
  if (fragments.empty()) return;
  if (node < 0) {
    for (Winding& w : mergeNodeFaces(ctx.scene, tree, fragments, surface.normal)) faces.push_back(std::move(w));
    return;
  }
  const QbspTree::Node& n = tree.nodes()[size_t(node)];
  if (sameQbspPlane(n.plane, surface)) {
    const int seen = glm::dot(n.plane.normal, surface.normal) > 0.0 ? 0 : 1;
    std::vector<PathStep> path;
    std::vector<LeafPieces> outer;
    leafPieces(tree, n.children[seen], std::move(fragments), path, outer);
    // Each face is a portal of the node: the plane's base winding cut by the planes above, the
    // nearest first (portals.cc BaseWindingForNode), then by those of the front subtree down to
    // its leaf and of the back subtree down to its own (ClipNodePortalsToTree_r); a face on the
    // back side is the portal turned round (FaceFromPortal). Where it starts decides how the
    // merge, the subdivision and the T-junction fans cut it.
    Winding portal = qbspBaseWinding(n.plane, kWorldHalfSize);
    for (auto it = above.rbegin(); it != above.rend() && !portal.empty(); ++it)
      portal = qbspClip(portal, *it->plane, it->side, kPortalEpsilon);
    // Then by the portals around the whole tree (MakeHeadnodePortals: -x -y -z, then +x +y +z),
    // where the planes above leave it open.
    for (int k = 0; k < 6 && !portal.empty(); ++k) {
      Plane bound{dvec3(0.0), -kHeadnodeBox};
      bound.normal[k % 3] = k < 3 ? 1.0 : -1.0;
      portal = qbspClip(portal, bound, 0, kBoundaryEpsilon);
    }
    std::vector<Winding> pieces;
    for (LeafPieces& leaf : outer) {
      std::vector<LeafPieces> across;
      leafPieces(tree, n.children[1 - seen], std::move(leaf.pieces), path, across);
      for (auto cell = across.begin(); cell != across.end(); ++cell) {
        Winding w = portal;
        for (const std::vector<PathStep>* steps : {seen == 0 ? &leaf.path : &cell->path, seen == 0 ? &cell->path : &leaf.path})
          for (const PathStep& step : *steps)
            if (w.size() >= 3) w = qbspClip(w, *step.plane, step.side, kPortalEpsilon);
        if (w.size() >= 3 && seen == 0) std::reverse(w.begin(), w.end()); // our winding: qbsp's turned round
        for (Winding& piece : cellFaces(std::move(cell->pieces), std::move(w), surface.normal)) pieces.push_back(std::move(piece));
      }
    }
    for (Winding& w : mergeNodeFaces(ctx.scene, tree, pieces, surface.normal)) faces.push_back(std::move(w));
    return;
  }
  std::vector<Winding> front, back;
  splitAll(fragments, n.plane, front, back);
  above.push_back({&n.plane, 0});
  nodeFaces(ctx, n.children[0], std::move(front), above, faces);
  above.back().side = 1;
  nodeFaces(ctx, n.children[1], std::move(back), above, faces);
  above.pop_back();
}

} // namespace

std::vector<Winding> compilerFaces(const Scene& scene, const std::vector<uint32_t>& sides, const std::vector<Winding>& fragments,
                                   const std::vector<BrushContents>& contents, const QbspTree& world) {
  const Face& surface = scene.faces[sides.front()];
  if (surface.brush < contents.size() && contents[surface.brush] != BrushContents::Empty && !world.nodes().empty()) {
    std::vector<Winding> faces;
    std::vector<PathStep> above;
    nodeFaces({scene, world, surface.plane}, 0, fragments, above, faces);
    return faces;
  }
  return surfaceTreeFaces(scene, sides, fragments, contents);
}

std::vector<Winding> surfaceTreeFaces(const Scene& scene, const std::vector<uint32_t>& sides, const std::vector<Winding>& fragments,
                                      const std::vector<BrushContents>& contents) {
  const Face& surface = scene.faces[sides.front()];
  Bounds bounds;
  for (const Winding& w : fragments)
    for (const dvec3& p : w) bounds.grow(p);
  std::vector<Winding> footprints;
  for (uint32_t side : sides) footprints.push_back(scene.faces[side].winding);
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    if (contents[b] == BrushContents::Empty || !overlaps(bounds, scene.brushes[b].bounds)) continue;
    if (std::any_of(sides.begin(), sides.end(), [&](uint32_t side) { return scene.faces[side].brush == b; })) continue;
    if (Winding w = crossSection(scene, scene.brushes[b], surface.plane); !w.empty()) footprints.push_back(std::move(w));
  }
  std::vector<Winding> faces;
  splitIntoFaces(fragments, footprints, edgePlanes(footprints, surface.plane.normal), surface.plane.normal, faces);
  return faces;
}

VoidTest::VoidTest(const Scene& scene, const TraceScene& tracer) : tracer_(tracer) {
  // qbsp floods the inside from the point entities; one that the void reaches is a leak.
  bool anyEntity = false;
  for (const Entity& e : scene.entities) {
    if (e.brushCount > 0) continue;
    const std::optional<glm::vec3> origin = quake::parseVec3(e.value("origin"));
    if (!origin) continue;
    anyEntity = true;
    if (escapes(dvec3(*origin))) {
      sealed_ = false; // one leak is enough
      break;
    }
  }
  sealed_ = sealed_ && anyEntity;
}

bool VoidTest::inVoid(const dvec3& p) const {
  return sealed_ && escapes(p);
}

bool VoidTest::escapes(const dvec3& p) const {
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z) {
        if (x == 0 && y == 0 && z == 0) continue;
        const Ray ray{glm::vec3(p), 0.0f, glm::normalize(glm::vec3(x, y, z)), std::numeric_limits<float>::infinity()};
        if (!tracer_.occluded(ray)) return true;
      }
  return false;
}

std::vector<Winding> subdivideOnGrid(const Winding& winding, double size) {
  std::vector<Winding> pieces;
  subdivide(winding, size, pieces);
  return pieces;
}

std::vector<Winding> visibleFragments(const Scene& scene, uint32_t faceIndex, const std::vector<BrushContents>& contents) {
  const Face& face = scene.faces[faceIndex];
  if (face.winding.size() < 3) return {};
  const bool liquid = face.brush < contents.size() && contents[face.brush] == BrushContents::Liquid;
  Bounds bounds;
  for (const dvec3& p : face.winding) bounds.grow(p);
  std::vector<Winding> fragments{face.winding};
  for (size_t b = 0; b < scene.brushes.size() && !fragments.empty(); ++b) {
    const bool carves = contents[b] == BrushContents::Solid || (liquid && contents[b] == BrushContents::Liquid);
    if (b == face.brush || !carves || !overlaps(bounds, scene.brushes[b].bounds)) continue;
    carve(scene, scene.brushes[b], face.plane.normal, fragments, b > face.brush);
  }
  return fragments;
}

bool qbspDetail(const Scene& scene, uint32_t b) {
  const Brush& brush = scene.brushes[b];
  bool detail = brush.entity < scene.entities.size() && scene.entities[brush.entity].classname().starts_with("func_detail");
  for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
    if (const std::optional<SurfaceAttributes>& surface = scene.faces[f].surface; surface)
      detail = detail || (surface->contents & quake::q2::CONTENTS_DETAIL) ||
          (surface->flags & (quake::q2::SURF_TRANS33 | quake::q2::SURF_TRANS66));
  return detail;
}

uint32_t weldGroup(const Scene& scene, const std::vector<BrushContents>& contents, uint32_t brush) {
  return uint32_t(contents[brush]) * 2 + (qbspDetail(scene, brush) ? 1 : 0);
}

uint32_t quake1WeldGroup(const Scene& scene, const std::vector<BrushContents>& contents, uint32_t brush) {
  // testsurfacelight's lava top carries the vertices of the func_detail walls that meet it on
  // x -64 (the .bsp's faces 801-804), not those of the structural walls.
  return qbspDetail(scene, brush) || contents[brush] == BrushContents::Liquid ? 1 : 0;
}

namespace {

constexpr int32_t kQuake1Liquid = 1; // what a Quake 1 face looking into a liquid looks into (QbspTree::Filler)

// After its first tree, qbsp fills the void outside and marks a brush side visible only where a
// portal on its plane joins a leaf inside the brush to a leaf neither solid nor void (outside.cc
// MarkVisibleBrushSides): some of the side lies outside every solid brush (func_detail
// included) and out of the void. Liquids do not hide it: a liquid side against another liquid
// (testsurfacelight's lava brushes, side by side) stays visible, although CSG makes no face
// there (visibleFragments).
bool quake1SideVisible(const Scene& scene, uint32_t faceIndex, const std::vector<BrushContents>& contents,
                       const std::vector<uint32_t>& neighbours, const VoidTest& voidTest) {
  const Face& face = scene.faces[faceIndex];
  if (face.winding.size() < 3) return false;
  std::vector<Winding> fragments{face.winding};
  Bounds bounds;
  for (const dvec3& p : face.winding) bounds.grow(p);
  for (const uint32_t b : neighbours) {
    if (fragments.empty()) break;
    if (contents[b] == BrushContents::Solid && overlaps(bounds, scene.brushes[b].bounds))
      carve(scene, scene.brushes[b], face.plane.normal, fragments, false);
  }
  return std::any_of(fragments.begin(), fragments.end(), [&](const Winding& w) {
    dvec3 mean(0.0);
    for (const dvec3& p : w) mean += p;
    return !voidTest.inVoid(mean / double(w.size()) + face.plane.normal * kVoidProbeDistance);
  });
}

// For each brush that carves (contents not Empty), the other such brushes whose boxes overlap its
// own, in index order (the order CSG carves in); none for the others. A side's carve reads these
// only, not every brush of the level: on lq_e4m3 (3,399 brushes, 20,744 sides) that is most of
// what the sides' visibility cost.
std::vector<std::vector<uint32_t>> overlappingBrushes(const Scene& scene, const std::vector<BrushContents>& contents) {
  std::vector<uint32_t> order;
  for (uint32_t b = 0; b < scene.brushes.size(); ++b)
    if (contents[b] != BrushContents::Empty) order.push_back(b);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return scene.brushes[a].bounds.min.x < scene.brushes[b].bounds.min.x; });
  std::vector<std::vector<uint32_t>> neighbours(scene.brushes.size());
  for (size_t i = 0; i < order.size(); ++i) {
    const Bounds& a = scene.brushes[order[i]].bounds;
    for (size_t j = i + 1; j < order.size() && scene.brushes[order[j]].bounds.min.x <= a.max.x + kOnPlaneEpsilon; ++j)
      if (overlaps(a, scene.brushes[order[j]].bounds)) {
        neighbours[order[i]].push_back(order[j]);
        neighbours[order[j]].push_back(order[i]);
      }
  }
  for (std::vector<uint32_t>& list : neighbours) std::sort(list.begin(), list.end());
  return neighbours;
}

} // namespace

QbspTree quake1WorldTree(const Scene& scene, const std::vector<BrushContents>& contents, const VoidTest& voidTest,
                         std::vector<Winding> around) {
  const std::vector<std::vector<uint32_t>> neighbours = overlappingBrushes(scene, contents);
  // Each side's visibility is a question of its own (a carve and the void's rays), asked on all
  // cores.
  std::vector<char> visible(scene.faces.size(), 0);
  parallelFor(scene.faces.size(), 0, [&](size_t f) {
    const uint32_t b = scene.faces[f].brush;
    if (b < contents.size() && contents[b] != BrushContents::Empty)
      visible[f] = quake1SideVisible(scene, uint32_t(f), contents, neighbours[b], voidTest);
  });
  std::vector<QbspTree::Input> brushes;
  std::vector<QbspTree::Filler> fillers;
  for (uint32_t b = 0; b < scene.brushes.size(); ++b) {
    if (contents[b] == BrushContents::Empty) continue;
    // qbsp merges no face that looks into a liquid with one that looks into air (TryMerge's
    // water boundary): a wall going down into the lava is two faces, cut where the lava's top is.
    if (contents[b] == BrushContents::Liquid) fillers.push_back({b, kQuake1Liquid});
    const Brush& brush = scene.brushes[b];
    // ericw-tools 2.0 gives a Quake 1 liquid the detail bit: its sides are valued with
    // func_detail's, after the structural ones (testsurfacelight's lava top, z 64, comes below
    // the func_detail bars' y 48 and z 80 in the .bsp's tree).
    QbspTree::Input in{b, true, qbspDetail(scene, b) || contents[b] == BrushContents::Liquid};
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) in.hiddenSides.push_back(!visible[f]);
    brushes.push_back(std::move(in));
  }
  return QbspTree(scene, brushes, std::move(fillers), std::move(around));
}

QbspTree worldTree(const Scene& scene, const std::vector<BrushContents>& contents) {
  // Only Quake 2's worlds go down the tree: there its planes and their order are the compiler's
  // (q2_areaportals, light_q2_translucent_shadow: the .bsp's nodes). A Quake 1 world's own tree
  // (quake1WorldTree) is the .bsp's on falloff, node for node, yet the faces made from it moved
  // falloff's floor off the compiler's (a view 98.6 -> 88.1 %), so only the _surface templates
  // take it; Quake 1 and Half-Life keep the surface trees here for now.
  if (gameOf(scene) != Game::Quake2) return QbspTree(scene, {});
  // Quake 2's qbsp grows the world's tree over its area portals too (CONTENTS_AREAPORTAL):
  // hidden, they still stand on the planes the tree values.
  std::vector<QbspTree::Input> brushes;
  std::vector<QbspTree::Filler> fillers;
  for (uint32_t b = 0; b < scene.brushes.size(); ++b) {
    const Brush& brush = scene.brushes[b];
    const std::string_view classname = brush.entity < scene.entities.size() ? scene.entities[brush.entity].classname() : "";
    const bool detail = qbspDetail(scene, b);
    if (contents[b] != BrushContents::Empty)
      brushes.push_back({b, true, detail});
    else if (classname == "func_areaportal")
      brushes.push_back({b, false, detail});
    if (classname == "func_areaportal") {
      fillers.push_back({b, quake::q2::CONTENTS_AREAPORTAL});
    } else if (contents[b] == BrushContents::Liquid) {
      int32_t bits = 0;
      for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
        if (scene.faces[f].surface) bits |= scene.faces[f].surface->contents;
      fillers.push_back({b, bits});
    }
  }
  return QbspTree(scene, brushes, std::move(fillers));
}

std::vector<Winding> compiledFacePolygons(const Scene& scene, uint32_t faceIndex, const std::vector<BrushContents>& contents,
                                          const QbspTree& world) {
  const std::vector<Winding> fragments = visibleFragments(scene, faceIndex, contents);
  if (fragments.empty()) return {};
  std::vector<Winding> pieces;
  for (const Winding& w : compilerFaces(scene, {faceIndex}, fragments, contents, world))
    subdivideForQbsp(w, scene.faces[faceIndex].frame, pieces);
  return pieces;
}

} // namespace bt
