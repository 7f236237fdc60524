#include "lighting/qbsp_tjunc.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>

namespace bt {

namespace {

constexpr double kOnEdgeEpsilon = 0.1;    // qbsp's DEFAULT_ON_EPSILON: a vertex this near an edge's line is on it
constexpr double kEdgeBoxMargin = 1.0;    // FindEdgeVerts_FaceBounds grows the edge's box by this
constexpr double kMinAngleDegrees = 0.01; // TriangleIsValid: a thinner angle makes a degenerate triangle
constexpr double kWeldDistance = 1e-3;    // one vertex of the .bsp (qbsp welds its vertices)
// The triangulation takes n^3 steps and its fans n^4 at worst: a face with more points on its
// edges than this (a long floor under a row of hundreds of pillars) keeps its shape whole, as the
// compiler's fallback (a rotated superface) keeps it.
constexpr size_t kMaxTriangulatedPoints = 64;
constexpr double kColinearSine = 1e-5;       // a corner turning less than this goes straight on
constexpr double kCellSize = 64.0;           // the grid the vertices are looked up in
constexpr int64_t kMaxCellsPerLookup = 4096; // a longer box scans every vertex instead

uint64_t cellKey(int64_t x, int64_t y, int64_t z) {
  constexpr int64_t kBias = int64_t(1) << 20, kMask = (int64_t(1) << 21) - 1;
  return (uint64_t((x + kBias) & kMask) << 42) | (uint64_t((y + kBias) & kMask) << 21) | uint64_t((z + kBias) & kMask);
}

int64_t cellOf(double v) {
  return int64_t(std::floor(v / kCellSize));
}

// PointOnEdge: where p lies along the edge from `start` in unit direction `dir`, strictly between
// `from` and `to` (a vertex at an end is that end), when it lies on the edge's line.
std::optional<double> alongEdge(const dvec3& p, const dvec3& start, const dvec3& dir, double from, double to) {
  const double t = glm::dot(p - start, dir);
  if (t <= from + kWeldDistance || t >= to - kWeldDistance) return std::nullopt;
  if (glm::length(p - (start + dir * t)) > kOnEdgeEpsilon) return std::nullopt;
  return t;
}

// TestEdge: the edge's first point `from`, then those of `onEdge` (from index `first` on) that cut
// it, each cutting the rest in two.
void splitEdge(double from, double to, const dvec3& fromPoint, size_t first, const std::vector<dvec3>& onEdge, const dvec3& start,
               const dvec3& dir, Winding& superface) {
  for (size_t k = first; k < onEdge.size(); ++k) {
    const std::optional<double> t = alongEdge(onEdge[k], start, dir, from, to);
    if (!t) continue;
    splitEdge(from, *t, fromPoint, k + 1, onEdge, start, dir, superface);
    splitEdge(*t, to, onEdge[k], k + 1, onEdge, start, dir, superface);
    return;
  }
  superface.push_back(fromPoint);
}

double angleDegrees(const dvec3& a, const dvec3& b, const dvec3& c) {
  const dvec3 u = b - a, v = c - a;
  return std::acos(glm::dot(u, v) / (glm::length(u) * glm::length(v))) * (180.0 / std::numbers::pi);
}

// TriangleIsValid: no angle thinner than kMinAngleDegrees (NaN, a repeated point, fails too).
bool validTriangle(const dvec3& a, const dvec3& b, const dvec3& c) {
  return angleDegrees(a, b, c) >= kMinAngleDegrees && angleDegrees(b, c, a) >= kMinAngleDegrees &&
      angleDegrees(c, a, b) >= kMinAngleDegrees;
}

using Triangle = std::array<size_t, 3>; // indices into the polygon, ascending

// minimum_weight_triangulation: the triangles of least total perimeter, a degenerate one
// weighing almost the most a double holds; the same sums in the same order as the compiler's, so
// that ties (a rectangle's two diagonals) fall as they fall there.
std::vector<Triangle> lightestTriangulation(const Winding& p) {
  const size_t n = p.size();
  std::vector<double> weight(n * n, 0.0);
  std::vector<std::optional<size_t>> apex(n * n);
  const double degenerate = std::nexttoward(std::numeric_limits<double>::max(), 0.0);
  for (size_t diagonal = 0; diagonal < n; ++diagonal)
    for (size_t i = 0, j = diagonal; j < n; ++i, ++j) {
      if (j < i + 2) continue;
      double& best = weight[i + j * n];
      best = std::numeric_limits<double>::max();
      for (size_t k = i + 1; k < j; ++k) {
        const double w = validTriangle(p[i], p[j], p[k])
            ? (glm::distance(p[i], p[j]) + glm::distance(p[j], p[k]) + glm::distance(p[k], p[i])) + weight[i + k * n] + weight[k + j * n]
            : degenerate;
        if (w < best) best = w, apex[i + j * n] = k;
      }
    }
  std::vector<Triangle> triangles;
  std::queue<std::pair<size_t, size_t>> edges;
  edges.emplace(0, n - 1);
  while (!edges.empty()) {
    const auto [a, b] = edges.front();
    edges.pop();
    const std::optional<size_t> c = apex[a + b * n];
    if (a == b || !c) continue;
    Triangle t{a, b, *c};
    std::sort(t.begin(), t.end());
    triangles.push_back(t);
    edges.emplace(a, *c);
    edges.emplace(*c, b);
  }
  return triangles;
}

// triangle_exists: the triangle a b c, in any rotation.
std::optional<size_t> findTriangle(const std::vector<Triangle>& triangles, size_t a, size_t b, size_t c) {
  for (size_t i = 0; i < triangles.size(); ++i)
    for (size_t s = 0; s < 3; ++s)
      if (triangles[i][s] == a && triangles[i][(s + 1) % 3] == b && triangles[i][(s + 2) % 3] == c) return i;
  return std::nullopt;
}

// find_best_fan: the most triangles that wind on from one corner of one triangle (the first of
// the most found, triangle by triangle and corner by corner).
std::vector<size_t> largestFan(const std::vector<Triangle>& triangles, size_t n) {
  std::vector<size_t> best;
  for (const Triangle& t : triangles)
    for (size_t corner = 0; corner < 3; ++corner) {
      const size_t first = t[corner];
      size_t mid = t[(corner + 1) % 3];
      std::vector<size_t> fan;
      for (size_t last = t[(corner + 2) % 3]; last != first; last = (last + 1) % n)
        if (const std::optional<size_t> found = findTriangle(triangles, first, mid, last)) {
          fan.push_back(*found);
          mid = last;
        }
      if (best.empty() || fan.size() > best.size()) best = std::move(fan);
    }
  return best;
}

} // namespace

void TJunctionVertices::add(const Winding& face, uint32_t weldGroup) {
  for (const dvec3& p : face) {
    // One vertex per welded position and group, so that no edge is cut twice at one point.
    const std::array<int64_t, 4> weld{std::llround(p.x / kWeldDistance), std::llround(p.y / kWeldDistance),
                                      std::llround(p.z / kWeldDistance), int64_t(weldGroup)};
    if (!known_.insert(weld).second) continue;
    const uint32_t index = uint32_t(vertices_.size());
    vertices_.push_back({p, weldGroup});
    cells_[cellKey(cellOf(p.x), cellOf(p.y), cellOf(p.z))].push_back(index);
  }
}

std::vector<dvec3> TJunctionVertices::inBox(const dvec3& lo, const dvec3& hi, uint32_t weldGroup) const {
  const int64_t x0 = cellOf(lo.x), y0 = cellOf(lo.y), z0 = cellOf(lo.z), x1 = cellOf(hi.x), y1 = cellOf(hi.y), z1 = cellOf(hi.z);
  std::vector<uint32_t> found;
  auto take = [&](uint32_t i) {
    const dvec3& p = vertices_[i].p;
    if (vertices_[i].group == weldGroup && glm::all(glm::greaterThanEqual(p, lo)) && glm::all(glm::lessThanEqual(p, hi)))
      found.push_back(i);
  };
  if ((x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1) > kMaxCellsPerLookup) {
    for (uint32_t i = 0; i < vertices_.size(); ++i) take(i);
  } else {
    for (int64_t x = x0; x <= x1; ++x)
      for (int64_t y = y0; y <= y1; ++y)
        for (int64_t z = z0; z <= z1; ++z)
          if (const auto it = cells_.find(cellKey(x, y, z)); it != cells_.end())
            for (uint32_t i : it->second) take(i);
    std::sort(found.begin(), found.end());
  }
  std::vector<dvec3> points;
  for (uint32_t i : found) points.push_back(vertices_[i].p);
  return points;
}

Winding withoutColinearPoints(const Winding& w) {
  Winding kept;
  for (size_t i = 0; i < w.size(); ++i) {
    const dvec3 &prev = w[(i + w.size() - 1) % w.size()], &next = w[(i + 1) % w.size()];
    const dvec3 in = w[i] - prev, out = next - w[i];
    const double lengths = glm::length(in) * glm::length(out);
    if (lengths > 0.0 && glm::length(glm::cross(in, out)) > kColinearSine * lengths) kept.push_back(w[i]);
  }
  return kept.size() >= 3 ? kept : w;
}

std::vector<Winding> minimumWeightFans(const Winding& polygon) {
  const size_t n = polygon.size();
  std::vector<Triangle> triangles = lightestTriangulation(polygon);
  if (n < 3 || triangles.size() != n - 2) return {};
  std::vector<Winding> fans;
  while (!triangles.empty()) {
    std::vector<size_t> fan = largestFan(triangles, n);
    if (fan.size() <= 1) { // no two triangles make a fan: each its own face
      for (const Triangle& t : triangles) fans.push_back({polygon[t[0]], polygon[t[1]], polygon[t[2]]});
      break;
    }
    // The fan's corners in the polygon's order (which corner comes first changes no face).
    std::vector<size_t> corners;
    for (size_t t : fan) corners.insert(corners.end(), triangles[t].begin(), triangles[t].end());
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    Winding face;
    for (size_t c : corners) face.push_back(polygon[c]);
    fans.push_back(std::move(face));
    std::sort(fan.begin(), fan.end(), std::greater<>());
    for (size_t t : fan) triangles.erase(triangles.begin() + std::ptrdiff_t(t));
  }
  return fans;
}

std::vector<Winding> fixTJunctions(const Winding& face, uint32_t weldGroup, const TJunctionVertices& vertices) {
  // qbsp winds a face the other way round, from what is our last vertex: its superface starts
  // there, which decides the lightest triangulation's ties (a rectangle's two diagonals).
  const Winding reversed(face.rbegin(), face.rend());
  Winding superface;
  for (size_t i = 0; i < reversed.size(); ++i) {
    const dvec3 &a = reversed[i], &b = reversed[(i + 1) % reversed.size()];
    const double length = glm::distance(a, b);
    if (!(length > 0.0)) continue; // a degenerate edge adds nothing
    const std::vector<dvec3> near = vertices.inBox(glm::min(a, b) - kEdgeBoxMargin, glm::max(a, b) + kEdgeBoxMargin, weldGroup);
    splitEdge(0.0, length, a, 0, near, a, (b - a) / length, superface);
  }
  if (superface.size() < 3) return {}; // the face collapsed
  if (superface.size() == 3) return {face};
  std::vector<Winding> fans = superface.size() <= kMaxTriangulatedPoints ? minimumWeightFans(superface) : std::vector<Winding>{};
  // Without a triangulation the compiler tries rotating the superface's first point, which keeps
  // its shape.
  if (fans.empty()) fans.push_back(std::move(superface));
  for (Winding& w : fans) std::reverse(w.begin(), w.end()); // our winding again
  return fans;
}

} // namespace bt
