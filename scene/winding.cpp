#include "scene/winding.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace bt {

Winding baseWinding(const Plane& plane, double radius) {
  // Pick the world axis least aligned with the normal as "up", then make it perpendicular.
  const dvec3 n = plane.normal;
  const dvec3 a = glm::abs(n);
  dvec3 up = (a.z >= a.x && a.z >= a.y) ? dvec3(1.0, 0.0, 0.0) : dvec3(0.0, 0.0, 1.0);
  up = glm::normalize(up - n * glm::dot(up, n));
  const dvec3 right = glm::cross(up, n); // (right, up, n) is right-handed
  const dvec3 center = n * plane.dist;
  up *= radius;
  const dvec3 r = right * radius;
  return {center - r - up, center + r - up, center + r + up, center - r + up};
}

namespace {

// Signed distances of a winding's points to a plane; windings are small (a brush side has a
// handful of points), so they fit in place and clipping allocates nothing for them.
class PointDistances {
public:
  PointDistances(const Winding& w, const Plane& plane) : heap_(w.size() > kInPlace ? w.size() : 0) {
    data_ = heap_.empty() ? inPlace_.data() : heap_.data();
    for (size_t i = 0; i < w.size(); ++i) data_[i] = plane.distanceTo(w[i]);
  }
  PointDistances(const PointDistances&) = delete;
  PointDistances& operator=(const PointDistances&) = delete;
  double operator[](size_t i) const { return data_[i]; }

private:
  static constexpr size_t kInPlace = 32;
  std::array<double, kInPlace> inPlace_;
  std::vector<double> heap_;
  double* data_;
};

// Where the edge p -> q (distances dp, dq of opposite signs) crosses the plane.
dvec3 crossing(const dvec3& p, const dvec3& q, double dp, double dq, const Plane& plane) {
  const double t = dp / (dp - dq);
  dvec3 mid = p + (q - p) * t;
  // Axial planes: put the coordinate exactly on the plane, as qbsp does, so that
  // neighbouring brushes share vertices bit for bit.
  for (int k = 0; k < 3; ++k) {
    if (plane.normal[k] == 1.0)
      mid[k] = plane.dist;
    else if (plane.normal[k] == -1.0)
      mid[k] = -plane.dist;
  }
  return mid;
}

bool crosses(double dp, double dq, double epsilon) {
  return (dp > epsilon && dq < -epsilon) || (dp < -epsilon && dq > epsilon);
}

} // namespace

SplitWinding splitWinding(const Winding& w, const Plane& plane, double epsilon) {
  SplitWinding out;
  const size_t n = w.size();
  if (n == 0) return out;
  const PointDistances dist(w, plane);
  bool anyFront = false, anyBack = false;
  for (size_t i = 0; i < n; ++i) {
    anyFront |= dist[i] > epsilon;
    anyBack |= dist[i] < -epsilon;
  }
  if (!anyFront && !anyBack) { // on the plane: belongs to neither side's interior, keep on both
    out.front = w;
    out.back = w;
    return out;
  }
  if (!anyFront) {
    out.back = w;
    return out;
  }
  if (!anyBack) {
    out.front = w;
    return out;
  }
  out.front.reserve(n + 1); // a convex polygon gains at most one point on each side
  out.back.reserve(n + 1);
  for (size_t i = 0; i < n; ++i) {
    const size_t next = i + 1 == n ? 0 : i + 1;
    const double dp = dist[i], dq = dist[next];
    if (dp >= -epsilon) out.front.push_back(w[i]);
    if (dp <= epsilon) out.back.push_back(w[i]);
    if (crosses(dp, dq, epsilon)) {
      const dvec3 mid = crossing(w[i], w[next], dp, dq, plane);
      out.front.push_back(mid);
      out.back.push_back(mid);
    }
  }
  if (out.front.size() < 3) out.front.clear();
  if (out.back.size() < 3) out.back.clear();
  return out;
}

// splitWinding's back part, without building the front one: the importers clip every brush side
// by every other plane of its brush.
Winding clipBehind(const Winding& w, const Plane& plane, double epsilon) {
  const size_t n = w.size();
  if (n == 0) return {};
  const PointDistances dist(w, plane);
  bool anyFront = false;
  for (size_t i = 0; i < n; ++i) anyFront |= dist[i] > epsilon;
  if (!anyFront) return w; // behind or on the plane: all of it
  bool anyBack = false;
  for (size_t i = 0; i < n; ++i) anyBack |= dist[i] < -epsilon;
  if (!anyBack) return {};
  Winding back;
  back.reserve(n + 1);
  for (size_t i = 0; i < n; ++i) {
    const size_t next = i + 1 == n ? 0 : i + 1;
    const double dp = dist[i], dq = dist[next];
    if (dp <= epsilon) back.push_back(w[i]);
    if (crosses(dp, dq, epsilon)) back.push_back(crossing(w[i], w[next], dp, dq, plane));
  }
  if (back.size() < 3) back.clear();
  return back;
}

dvec3 areaVector(const Winding& w) {
  dvec3 sum{0.0};
  for (size_t i = 0; i + 2 < w.size(); ++i) sum += glm::cross(w[i + 1] - w[0], w[i + 2] - w[0]);
  return sum * 0.5;
}

double area(const Winding& w) {
  return glm::length(areaVector(w));
}

Winding intersectConvex(const Winding& w, const Winding& clip, const dvec3& normal) {
  Winding out = w;
  for (size_t i = 0; i < clip.size() && !out.empty(); ++i) {
    const dvec3 edge = clip[(i + 1) % clip.size()] - clip[i];
    // For a counter-clockwise polygon, cross(edge, normal) points outwards.
    const dvec3 outward = glm::cross(edge, normal);
    const double len = glm::length(outward);
    if (len < 1e-12) continue;
    const Plane edgePlane{outward / len, glm::dot(outward / len, clip[i])};
    out = clipBehind(out, edgePlane, 1e-6);
  }
  return out;
}

void removeDuplicatePoints(Winding& w, double epsilon) {
  Winding out;
  out.reserve(w.size());
  for (const dvec3& p : w)
    if (out.empty() || glm::length(p - out.back()) > epsilon) out.push_back(p);
  while (out.size() > 1 && glm::length(out.front() - out.back()) <= epsilon) out.pop_back();
  if (out.size() < 3) out.clear();
  w = std::move(out);
}

dvec3 nearestOnPolygon(const Winding& w, const dvec3& n, const dvec3& p) {
  bool inside = true;
  for (size_t i = 0; i < w.size() && inside; ++i) inside = glm::dot(glm::cross(w[(i + 1) % w.size()] - w[i], p - w[i]), n) >= 0.0;
  if (inside) return p;
  // Outside: the nearest point of every edge decides (beyond a corner, the nearest edge need
  // not be one that p is outside of).
  dvec3 best = p;
  double bestDist2 = 1e300;
  for (size_t i = 0; i < w.size(); ++i) {
    const dvec3& a = w[i];
    const dvec3 ab = w[(i + 1) % w.size()] - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const dvec3 q = a + t * ab;
    const double d2 = glm::dot(p - q, p - q);
    if (d2 < bestDist2) bestDist2 = d2, best = q;
  }
  return best;
}

} // namespace bt
