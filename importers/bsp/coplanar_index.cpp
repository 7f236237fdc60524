#include "importers/bsp/coplanar_index.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt::bsp {

namespace {
constexpr double kCellSize = 8.0;         // distance buckets, in units
constexpr double kPlaneEpsilon = 0.1;     // qbsp's ON_EPSILON: compiled vertices sit this close
constexpr double kNormalAgreement = 0.99; // cosine between a polygon's and a side's normal
constexpr double kAxisTie = 0.05;         // normals this close to 45 degrees go in both buckets

// Signed dominant axis, 0..5 (+x, -x, +y, -y, +z, -z).
int dominantAxis(const dvec3& n) {
  const dvec3 a = glm::abs(n);
  const int i = (a.x >= a.y && a.x >= a.z) ? 0 : (a.y >= a.z ? 1 : 2);
  return i * 2 + (n[i] < 0.0 ? 1 : 0);
}

int64_t distCell(double dist) {
  // Clamped so that corrupt files (huge or NaN distances) stay defined behaviour.
  const double cell = std::floor(dist / kCellSize);
  return std::isfinite(cell) ? static_cast<int64_t>(std::clamp(cell, -1e15, 1e15)) : 0;
}
} // namespace

uint64_t CoplanarIndex::key(int axis, int64_t cell) {
  return (static_cast<uint64_t>(cell) << 3) ^ static_cast<uint64_t>(axis);
}

void CoplanarIndex::add(const Plane& plane, Winding polygon, uint32_t payload) {
  if (polygon.size() < 3) return;
  Entry e{plane, std::move(polygon), dvec3(std::numeric_limits<double>::infinity()), dvec3(-std::numeric_limits<double>::infinity()),
          payload};
  for (const dvec3& p : e.polygon) {
    e.boundsMin = glm::min(e.boundsMin, p);
    e.boundsMax = glm::max(e.boundsMax, p);
  }
  const uint32_t index = static_cast<uint32_t>(entries_.size());
  const dvec3 a = glm::abs(plane.normal);
  const double largest = std::max({a.x, a.y, a.z});
  for (int i = 0; i < 3; ++i) {
    if (a[i] < largest - kAxisTie) continue;
    const int axis = i * 2 + (plane.normal[i] < 0.0 ? 1 : 0);
    const int64_t lo = distCell(plane.dist - kPlaneEpsilon), hi = distCell(plane.dist + kPlaneEpsilon);
    for (int64_t c = lo; c <= hi; ++c) buckets_[key(axis, c)].push_back(index);
  }
  entries_.push_back(std::move(e));
}

std::vector<CoplanarIndex::Overlap> CoplanarIndex::overlaps(const Plane& plane, const Winding& winding, double minArea) const {
  std::vector<Overlap> out;
  if (winding.size() < 3) return out;
  const auto bucket = buckets_.find(key(dominantAxis(plane.normal), distCell(plane.dist)));
  if (bucket == buckets_.end()) return out;

  dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const dvec3& p : winding) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  for (uint32_t index : bucket->second) {
    const Entry& e = entries_[index];
    if (glm::any(glm::greaterThan(e.boundsMin, hi + kPlaneEpsilon)) || glm::any(glm::lessThan(e.boundsMax, lo - kPlaneEpsilon))) continue;
    if (glm::dot(e.plane.normal, plane.normal) < kNormalAgreement) continue;
    bool onPlane = true;
    for (const dvec3& p : e.polygon) onPlane = onPlane && std::abs(plane.distanceTo(p)) <= kPlaneEpsilon;
    if (!onPlane) continue;
    const double overlap = area(intersectConvex(e.polygon, winding, plane.normal));
    if (overlap > minArea) out.push_back({e.payload, overlap, &e.polygon});
  }
  return out;
}

std::optional<uint32_t> CoplanarIndex::bestOverlap(const Plane& plane, const Winding& winding) const {
  std::optional<uint32_t> best;
  double bestArea = 0.0;
  for (const Overlap& o : overlaps(plane, winding)) {
    if (o.area > bestArea) {
      bestArea = o.area;
      best = o.payload;
    }
  }
  return best;
}

} // namespace bt::bsp
