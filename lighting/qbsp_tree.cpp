#include "lighting/qbsp_tree.h"

#include "scene/winding.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace bt {

namespace {

constexpr double kPlaneSideEpsilon = 0.001; // qbsp3's PLANESIDE_EPSILON: a box this close is on the plane
constexpr double kSplitEpsilon = 0.1;       // a side winding crosses a plane by more than this to count as cut
constexpr double kWorldHalfSize = 65536.0;  // the midwinding's starting square
constexpr double kMinBrushExtent = 1e-3;    // a piece thinner than this on an axis is no brush (microvolume)

enum PlaneSide { kFront = 1, kBack = 2, kBoth = 3, kFacing = 4 }; // qbsp3's PSIDE_*

struct TreeSide {
  Plane plane; // pointing out of the brush
  Winding winding;
  bool visible = false;
  bool onNode = false; // its plane is already a node above
  bool tested = false; // its plane was valued at this node
};

struct TreeBrush {
  std::vector<TreeSide> sides;
  Bounds bounds;
  bool detail = false;
};

bool isAxial(const Plane& p) {
  return std::abs(p.normal.x) == 1.0 || std::abs(p.normal.y) == 1.0 || std::abs(p.normal.z) == 1.0;
}

int axisOf(const Plane& p) {
  for (int i = 0; i < 3; ++i)
    if (std::abs(p.normal[i]) == 1.0) return i;
  return -1;
}

void updateBounds(TreeBrush& b) {
  b.bounds = Bounds{};
  for (const TreeSide& s : b.sides)
    for (const dvec3& p : s.winding) b.bounds.grow(p);
}

// qbsp3's BoxOnPlaneSide.
int boxOnPlaneSide(const Bounds& box, const Plane& plane) {
  if (const int axis = axisOf(plane); axis >= 0) {
    // the positive plane's normal is +1 on its axis
    int side = 0;
    if (box.max[axis] > plane.dist + kPlaneSideEpsilon) side |= kFront;
    if (box.min[axis] < plane.dist - kPlaneSideEpsilon) side |= kBack;
    return side;
  }
  dvec3 nearCorner, farCorner;
  for (int i = 0; i < 3; ++i) {
    farCorner[i] = plane.normal[i] < 0.0 ? box.min[i] : box.max[i];
    nearCorner[i] = plane.normal[i] < 0.0 ? box.max[i] : box.min[i];
  }
  int side = 0;
  if (plane.distanceTo(farCorner) >= kPlaneSideEpsilon) side = kFront;
  if (plane.distanceTo(nearCorner) < kPlaneSideEpsilon) side |= kBack;
  return side;
}

// qbsp3's TestBrushToPlanenum: the brush's side of `plane` (a positive plane), the visible sides
// it would cut and whether it lies within a unit of the plane without touching it.
int testBrushToPlane(const TreeBrush& brush, const Plane& plane, int& splits, int& epsilonBrush) {
  splits = 0;
  for (const TreeSide& s : brush.sides)
    if (sameQbspPlane(s.plane, plane)) return glm::dot(s.plane.normal, plane.normal) > 0.0 ? (kBack | kFacing) : (kFront | kFacing);
  const int side = boxOnPlaneSide(brush.bounds, plane);
  if (side != kBoth) return side;
  double dFront = 0.0, dBack = 0.0;
  for (const TreeSide& s : brush.sides) {
    if (s.onNode || !s.visible) continue;
    bool front = false, back = false;
    for (const dvec3& p : s.winding) {
      const double d = plane.distanceTo(p);
      dFront = std::max(dFront, d), dBack = std::min(dBack, d);
      front = front || d > kSplitEpsilon;
      back = back || d < -kSplitEpsilon;
    }
    splits += front && back;
  }
  if ((dFront > 0.0 && dFront < 1.0) || (dBack < 0.0 && dBack > -1.0)) ++epsilonBrush;
  return side;
}

// SelectSplitPlane's qbsp3 value: 5 facing - 5 sides cut - |front - back|, +5 when axial,
// -1000 a brush within a unit; visible sides first, then hidden ones.
const TreeSide* selectSplit(std::vector<TreeBrush>& brushes) {
  if (brushes.empty()) return nullptr;
  const TreeSide* best = nullptr;
  int bestValue = -99999;
  // Passes: visible structural, hidden structural, visible detail, hidden detail.
  for (int pass = 0; pass < 4 && !best; ++pass) {
    for (TreeBrush& brush : brushes) {
      if (brush.detail != (pass >= 2)) continue;
      for (TreeSide& side : brush.sides) {
        if (side.winding.empty() || side.onNode || side.tested || side.visible != (pass % 2 == 0)) continue;
        const Plane plane = positivePlane(side.plane);
        int front = 0, back = 0, facing = 0, splits = 0, epsilonBrush = 0;
        for (TreeBrush& test : brushes) {
          int brushSplits = 0;
          const int s = testBrushToPlane(test, plane, brushSplits, epsilonBrush);
          splits += brushSplits;
          if (s & kFacing) {
            ++facing;
            for (TreeSide& t : test.sides)
              if (sameQbspPlane(t.plane, plane)) t.tested = true;
          }
          front += (s & kFront) != 0;
          back += (s & kBack) != 0;
        }
        const int value = 5 * facing - 5 * splits - std::abs(front - back) + (isAxial(plane) ? 5 : 0) - 1000 * epsilonBrush;
        if (value > bestValue) bestValue = value, best = &side;
      }
    }
  }
  for (TreeBrush& brush : brushes)
    for (TreeSide& side : brush.sides) side.tested = false;
  return best;
}

// qbsp's SplitBrush: the parts of `brush` in front of and behind `plane`, each closed by the
// plane's cross-section of the brush (a side already on a node). Empty brushes where none.
void splitBrush(TreeBrush&& brush, const Plane& plane, std::vector<TreeBrush>& front, std::vector<TreeBrush>& back) {
  double dFront = 0.0, dBack = 0.0;
  for (const TreeSide& s : brush.sides)
    for (const dvec3& p : s.winding) {
      const double d = plane.distanceTo(p);
      dFront = std::max(dFront, d), dBack = std::min(dBack, d);
    }
  if (dFront < kSplitEpsilon) return back.push_back(std::move(brush));
  if (dBack > -kSplitEpsilon) return front.push_back(std::move(brush));
  Winding mid = baseWinding(plane, kWorldHalfSize);
  for (const TreeSide& s : brush.sides)
    if (!mid.empty()) mid = clipBehind(mid, s.plane, 0.0);
  if (mid.size() < 3 || area(mid) < 1e-3) return (dFront > -dBack ? front : back).push_back(std::move(brush));
  TreeBrush parts[2];
  parts[0].detail = parts[1].detail = brush.detail; // qbsp's pieces keep the brush's contents
  for (TreeSide& s : brush.sides) {
    SplitWinding split = splitWinding(s.winding, plane, 0.0);
    for (int i = 0; i < 2; ++i) {
      Winding& w = i == 0 ? split.front : split.back;
      if (w.size() < 3) continue;
      TreeSide piece = s;
      piece.winding = std::move(w);
      parts[i].sides.push_back(std::move(piece));
    }
  }
  for (int i = 0; i < 2; ++i) {
    TreeSide cap;
    cap.plane = i == 0 ? plane.flipped() : plane;
    cap.winding = mid;
    cap.onNode = true;
    parts[i].sides.push_back(std::move(cap));
    updateBounds(parts[i]);
    const dvec3 e = parts[i].bounds.extent();
    if (parts[i].sides.size() < 4 || e.x < kMinBrushExtent || e.y < kMinBrushExtent || e.z < kMinBrushExtent) continue;
    (i == 0 ? front : back).push_back(std::move(parts[i]));
  }
}

// qbsp's AddBrushBevels puts a brush's axial sides first, -x +x -y +y -z +z, each swapped into
// its place: SelectSplitPlane then values them in that order, and the first of equal value wins
// (q2_light_low_luxel_res2's boxes in its east wall: y 1064 before z -696, as in the .bsp).
void axialSidesFirst(std::vector<TreeSide>& sides) {
  size_t order = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double dir : {-1.0, 1.0}) {
      const auto it =
          std::find_if(sides.begin() + std::ptrdiff_t(order), sides.end(), [&](const TreeSide& s) { return s.plane.normal[axis] == dir; });
      if (it == sides.end()) continue;
      std::iter_swap(sides.begin() + std::ptrdiff_t(order), it);
      ++order;
    }
}

int32_t build(std::vector<QbspTree::Node>& nodes, std::vector<TreeBrush> brushes) {
  const TreeSide* chosen = selectSplit(brushes);
  if (!chosen) return -1;
  const Plane plane = positivePlane(chosen->plane);
  std::vector<TreeBrush> children[2];
  for (TreeBrush& b : brushes) {
    int splits = 0, epsilonBrush = 0;
    const int side = testBrushToPlane(b, plane, splits, epsilonBrush);
    if ((side & kBoth) == kBoth) {
      splitBrush(std::move(b), plane, children[0], children[1]);
      continue;
    }
    if (side & kFacing)
      for (TreeSide& s : b.sides)
        if (sameQbspPlane(s.plane, plane)) s.onNode = true;
    if (side & kFront)
      children[0].push_back(std::move(b));
    else if (side & kBack)
      children[1].push_back(std::move(b));
  }
  const int32_t index = int32_t(nodes.size());
  nodes.push_back({plane, {-1, -1}});
  for (int i = 0; i < 2; ++i) {
    const int32_t child = build(nodes, std::move(children[i]));
    nodes[size_t(index)].children[i] = child;
  }
  return index;
}

} // namespace

bool sameQbspPlane(const Plane& a, const Plane& b) {
  auto near = [](const Plane& p, const Plane& q) {
    return std::abs(p.dist - q.dist) < 0.01 && std::abs(p.normal.x - q.normal.x) < 1e-5 && std::abs(p.normal.y - q.normal.y) < 1e-5 &&
        std::abs(p.normal.z - q.normal.z) < 1e-5;
  };
  return near(a, b) || near(a, b.flipped());
}

Plane positivePlane(const Plane& p) {
  int major = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(p.normal[k]) > std::abs(p.normal[major]) + 1e-9) major = k;
  return p.normal[major] < 0.0 ? p.flipped() : p;
}

QbspTree::QbspTree(const Scene& scene, std::span<const Input> brushes, std::vector<Filler> fillers) : fillers_(std::move(fillers)) {
  std::vector<TreeBrush> list;
  for (const Input& in : brushes) {
    const Brush& brush = scene.brushes[in.brush];
    TreeBrush t;
    t.detail = in.detail;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) {
      const Face& face = scene.faces[f];
      if (face.winding.size() < 3) continue;
      t.sides.push_back({face.plane, face.winding, in.visible});
    }
    axialSidesFirst(t.sides);
    updateBounds(t);
    if (t.sides.size() < 4 || t.bounds.empty()) continue;
    list.push_back(std::move(t));
  }
  build(nodes_, std::move(list));
}

} // namespace bt
