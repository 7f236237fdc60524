#include "lighting/qbsp_tree.h"

#include "scene/winding.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <future>

namespace bt {

namespace {

constexpr double kPlaneSideEpsilon = 0.001; // qbsp3's PLANESIDE_EPSILON: a box this close is on the plane
constexpr double kSplitEpsilon = 0.1;       // a side winding crosses a plane by more than this to count as cut
constexpr double kWorldHalfSize = 65536.0;  // the midwinding's starting square
constexpr double kMinBrushExtent = 1e-3;    // a piece thinner than this on an axis is no brush (microvolume)
constexpr double kPlaneTouchEpsilon = 0.1;  // a polygon this close to a node's plane is on both its sides
constexpr int kParallelDepth = 4;           // the top levels whose front subtrees grow on threads of their own (up to 15)

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

// A brush's box and how near a side on some plane could lie to that plane and still count as on
// it (sameQbspPlane: 0.01 on the distance, 1e-5 on each normal component, at the box's farthest
// corner from the origin).
struct Clearance {
  dvec3 min, max;
  double slack;
};

Clearance clearanceOf(const Bounds& box) {
  return {box.min, box.max, 0.02 + 3e-5 * glm::length(glm::max(glm::abs(box.min), glm::abs(box.max)))};
}

// kFront or kBack when all of the box lies further from `plane` (a positive plane) than a side on
// it could, else 0.
int clearSide(const Clearance& box, const Plane& plane, int axis) {
  double nearest = 0.0, farthest = 0.0;
  if (axis >= 0) {
    nearest = box.min[axis], farthest = box.max[axis]; // the positive plane's normal is +1 on its axis
  } else {
    for (int i = 0; i < 3; ++i) {
      const double a = plane.normal[i] * box.min[i], b = plane.normal[i] * box.max[i];
      nearest += std::min(a, b), farthest += std::max(a, b);
    }
  }
  if (nearest - plane.dist > box.slack) return kFront;
  if (farthest - plane.dist < -box.slack) return kBack;
  return 0;
}

// testBrushToPlane below for a brush whose box is not clear of the plane (clearSide 0).
int testNearBrushToPlane(const TreeBrush& brush, const Plane& plane, int& splits, int& epsilonBrush) {
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

// qbsp3's TestBrushToPlanenum: the brush's side of `plane` (a positive plane), the visible sides
// it would cut and whether it lies within a unit of the plane without touching it.
int testBrushToPlane(const TreeBrush& brush, const Plane& plane, int& splits, int& epsilonBrush) {
  splits = 0;
  // Most brushes lie well clear of the plane: their box says so before their sides are read (a
  // side on the plane, by sameQbspPlane's tolerances, lies within clearSide's slack). The whole
  // world's tree values each plane against every brush, so this is most of its time.
  if (const int side = clearSide(clearanceOf(brush.bounds), plane, axisOf(plane)); side != 0) return side;
  return testNearBrushToPlane(brush, plane, splits, epsilonBrush);
}

// A node's brushes sorted along each axis, so that an axial plane (most of them) is valued
// against the brushes near it alone: the others lie clear of it (clearSide), and two binary
// searches count those in front and behind. The answer is the same as clearSide's on every brush.
class AxisIndex {
public:
  explicit AxisIndex(const std::vector<Clearance>& boxes) {
    for (const Clearance& c : boxes) slack_ = std::max(slack_, c.slack);
    for (int a = 0; a < 3; ++a) {
      Axis& axis = axes_[a];
      for (uint32_t k = 0; k < boxes.size(); ++k) {
        axis.mins.push_back(boxes[k].min[a]), axis.maxs.push_back(boxes[k].max[a]);
        (boxes[k].max[a] - boxes[k].min[a] > kLongBrush ? axis.longOnes : axis.byMin).push_back(k);
      }
      std::sort(axis.mins.begin(), axis.mins.end());
      std::sort(axis.maxs.begin(), axis.maxs.end());
      std::sort(axis.byMin.begin(), axis.byMin.end(), [&](uint32_t x, uint32_t y) { return boxes[x].min[a] < boxes[y].min[a]; });
      for (const uint32_t k : axis.byMin) axis.byMinValue.push_back(boxes[k].min[a]);
    }
  }

  // For the plane at `dist` on axis `a` (normal +1 there): the brushes surely in front and surely
  // behind it, counted; `near(k)` called for each other one.
  template <class Near> void visit(const std::vector<Clearance>& boxes, int a, double dist, int& front, int& back, const Near& near) const {
    const Axis& axis = axes_[a];
    const double lo = dist - slack_, hi = dist + slack_;
    front += int(axis.mins.end() - std::upper_bound(axis.mins.begin(), axis.mins.end(), hi));
    back += int(std::lower_bound(axis.maxs.begin(), axis.maxs.end(), lo) - axis.maxs.begin());
    // A short brush that reaches `lo` starts at most kLongBrush before it.
    const auto first = std::lower_bound(axis.byMinValue.begin(), axis.byMinValue.end(), lo - kLongBrush);
    const auto last = std::upper_bound(axis.byMinValue.begin(), axis.byMinValue.end(), hi);
    for (auto it = first; it != last; ++it)
      if (const uint32_t k = axis.byMin[size_t(it - axis.byMinValue.begin())]; boxes[k].max[a] >= lo) near(k);
    for (const uint32_t k : axis.longOnes)
      if (boxes[k].min[a] <= hi && boxes[k].max[a] >= lo) near(k);
  }

private:
  static constexpr double kLongBrush = 512.0; // longer brushes on an axis are looked at for every plane on it
  struct Axis {
    std::vector<double> mins, maxs; // every brush's, sorted
    std::vector<uint32_t> byMin;    // the brushes no longer than kLongBrush, by their box's minimum
    std::vector<double> byMinValue; // that minimum, in that order
    std::vector<uint32_t> longOnes; // the others
  };
  Axis axes_[3];
  double slack_ = 0.0; // the largest of the brushes' slacks
};

// SelectSplitPlane's qbsp3 value: 5 facing - 5 sides cut - |front - back|, +5 when axial,
// -1000 a brush within a unit; visible sides first, then hidden ones.
const TreeSide* selectSplit(std::vector<TreeBrush>& brushes) {
  if (brushes.empty()) return nullptr;
  const TreeSide* best = nullptr;
  int bestValue = -99999;
  // The brushes' boxes side by side: a plane is valued against every brush, and most are clear.
  std::vector<Clearance> boxes;
  for (const TreeBrush& brush : brushes) boxes.push_back(clearanceOf(brush.bounds));
  const AxisIndex index(boxes);
  // Passes: visible structural, hidden structural, visible detail, hidden detail.
  for (int pass = 0; pass < 4 && !best; ++pass) {
    for (TreeBrush& brush : brushes) {
      if (brush.detail != (pass >= 2)) continue;
      for (TreeSide& side : brush.sides) {
        if (side.winding.empty() || side.onNode || side.tested || side.visible != (pass % 2 == 0)) continue;
        const Plane plane = positivePlane(side.plane);
        const int axis = axisOf(plane);
        int front = 0, back = 0, facing = 0, splits = 0, epsilonBrush = 0;
        auto count = [&](size_t k) {
          TreeBrush& test = brushes[k];
          int brushSplits = 0;
          int s = clearSide(boxes[k], plane, axis);
          if (s == 0) s = testNearBrushToPlane(test, plane, brushSplits, epsilonBrush);
          splits += brushSplits;
          if (s & kFacing) {
            ++facing;
            for (TreeSide& t : test.sides)
              if (sameQbspPlane(t.plane, plane)) t.tested = true;
          }
          front += (s & kFront) != 0;
          back += (s & kBack) != 0;
        };
        if (axis >= 0)
          index.visit(boxes, axis, plane.dist, front, back, count);
        else
          for (size_t k = 0; k < brushes.size(); ++k) count(k);
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
// its place; where a brush has no side on one of them it appends an axial bevel there and swaps
// that in, so a slanted side swapped out goes to the end. SelectSplitPlane values the sides in
// that order, and the first of equal value wins (q2_light_low_luxel_res2's boxes in its east
// wall: y 1064 before z -696; testsurfacelight's slanted brushes at the lava's west end). The
// bevels themselves never split: dropped here.
void axialSidesFirst(std::vector<TreeSide>& sides) {
  std::vector<int> order(sides.size()); // indices into `sides`; -1 a bevel
  for (size_t i = 0; i < sides.size(); ++i) order[i] = int(i);
  size_t place = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const double dir : {-1.0, 1.0}) {
      auto it = std::find_if(order.begin(), order.end(), [&](int i) { return i >= 0 && sides[size_t(i)].plane.normal[axis] == dir; });
      if (it == order.end()) it = order.insert(order.end(), -1);
      std::iter_swap(order.begin() + std::ptrdiff_t(place), it);
      ++place;
    }
  std::vector<TreeSide> sorted;
  for (const int i : order)
    if (i >= 0) sorted.push_back(std::move(sides[size_t(i)]));
  sides = std::move(sorted);
}

// The subtree of `brushes`, its nodes in qbsp's order (a node, then its front subtree, then its
// back one), children numbered within it; empty: a leaf. `around`: where the tree is wanted (the
// polygons whose cuts the caller needs), or everywhere. The front subtrees of the top
// `parallelDepth` levels grow on threads of their own: the subtrees share nothing, and a large
// level's tree is otherwise grown on one core while the level waits.
std::vector<QbspTree::Node> build(std::vector<TreeBrush> brushes, const std::optional<std::vector<Winding>>& around, int parallelDepth) {
  if (around && around->empty()) return {}; // no polygon of interest here: what lies below cuts none
  const TreeSide* chosen = selectSplit(brushes);
  if (!chosen) return {};
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
  // A polygon on the plane, or touching it, is wanted on both sides: its own node's faces are
  // cut by the subtrees of both (qbsp_faces.cpp nodeFaces), and a neighbour's cuts reach it there.
  std::optional<std::vector<Winding>> childAround[2];
  if (around) {
    childAround[0].emplace(), childAround[1].emplace();
    for (const Winding& w : *around)
      for (int i = 0; i < 2; ++i)
        if (Winding part = clipBehind(w, i == 0 ? plane.flipped() : plane, kPlaneTouchEpsilon); part.size() >= 3)
          childAround[i]->push_back(std::move(part));
  }
  auto grow = [&](int i) { return build(std::move(children[i]), childAround[i], parallelDepth - 1); };
  std::vector<QbspTree::Node> subtrees[2];
  if (parallelDepth > 0) {
    std::future<std::vector<QbspTree::Node>> front = std::async(std::launch::async, grow, 0);
    subtrees[1] = grow(1);
    subtrees[0] = front.get();
  } else {
    subtrees[0] = grow(0), subtrees[1] = grow(1);
  }
  std::vector<QbspTree::Node> nodes{{plane, {-1, -1}}};
  nodes.reserve(1 + subtrees[0].size() + subtrees[1].size());
  for (int i = 0; i < 2; ++i) {
    if (subtrees[i].empty()) continue;
    const int32_t offset = int32_t(nodes.size());
    nodes.front().children[i] = offset;
    for (QbspTree::Node node : subtrees[i]) {
      for (int32_t& child : node.children)
        if (child >= 0) child += offset;
      nodes.push_back(node);
    }
  }
  return nodes;
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

QbspTree::QbspTree(const Scene& scene, std::span<const Input> brushes, std::vector<Filler> fillers,
                   std::optional<std::vector<Winding>> around)
    : fillers_(std::move(fillers)) {
  std::vector<TreeBrush> list;
  for (const Input& in : brushes) {
    const Brush& brush = scene.brushes[in.brush];
    TreeBrush t;
    t.detail = in.detail;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f) {
      const Face& face = scene.faces[f];
      if (face.winding.size() < 3) continue;
      const bool hidden = f - brush.firstFace < in.hiddenSides.size() && in.hiddenSides[f - brush.firstFace];
      t.sides.push_back({face.plane, face.winding, in.visible && !hidden});
    }
    axialSidesFirst(t.sides);
    updateBounds(t);
    if (t.sides.size() < 4 || t.bounds.empty()) continue;
    list.push_back(std::move(t));
  }
  nodes_ = build(std::move(list), around, kParallelDepth);
}

} // namespace bt
