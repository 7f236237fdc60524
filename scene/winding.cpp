#include "scene/winding.h"

#include <glm/geometric.hpp>

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

SplitWinding splitWinding(const Winding& w, const Plane& plane, double epsilon) {
  SplitWinding out;
  const size_t n = w.size();
  if (n == 0) return out;
  std::vector<double> dist(n);
  bool anyFront = false, anyBack = false;
  for (size_t i = 0; i < n; ++i) {
    dist[i] = plane.distanceTo(w[i]);
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
  for (size_t i = 0; i < n; ++i) {
    const dvec3& p = w[i];
    const dvec3& q = w[(i + 1) % n];
    const double dp = dist[i], dq = dist[(i + 1) % n];
    if (dp >= -epsilon) out.front.push_back(p);
    if (dp <= epsilon) out.back.push_back(p);
    const bool crosses = (dp > epsilon && dq < -epsilon) || (dp < -epsilon && dq > epsilon);
    if (crosses) {
      const double t = dp / (dp - dq);
      dvec3 mid = p + (q - p) * t;
      // Axial planes: put the coordinate exactly on the plane, as qbsp does, so that
      // neighbouring brushes share vertices bit for bit.
      for (int k = 0; k < 3; ++k) {
        if (plane.normal[k] == 1.0) mid[k] = plane.dist;
        else if (plane.normal[k] == -1.0) mid[k] = -plane.dist;
      }
      out.front.push_back(mid);
      out.back.push_back(mid);
    }
  }
  if (out.front.size() < 3) out.front.clear();
  if (out.back.size() < 3) out.back.clear();
  return out;
}

Winding clipBehind(const Winding& w, const Plane& plane, double epsilon) {
  SplitWinding s = splitWinding(w, plane, epsilon);
  return std::move(s.back);
}

dvec3 areaVector(const Winding& w) {
  dvec3 sum{0.0};
  for (size_t i = 0; i + 2 < w.size(); ++i) sum += glm::cross(w[i + 1] - w[0], w[i + 2] - w[0]);
  return sum * 0.5;
}

double area(const Winding& w) { return glm::length(areaVector(w)); }

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

} // namespace bt
