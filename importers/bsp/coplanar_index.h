// Finds, for a brush side, the compiled polygon lying on it: the BSP face (Q1/HL) or draw
// triangle (Q3) whose texture frame the side takes.
//
// Polygons are bucketed by the dominant axis of their normal and by their distance from the
// origin, so a query only looks at polygons on (nearly) the same plane; among those whose plane
// matches, the one covering most of the side's winding wins.
#pragma once

#include "scene/winding.h"

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

namespace bt::bsp {

class CoplanarIndex {
public:
  // `plane` faces the way the polygon is seen (its front); `polygon` lies on it.
  void add(const Plane& plane, Winding polygon, uint32_t payload);

  struct Overlap {
    uint32_t payload;
    double area;            // of the part of the polygon inside the winding
    const Winding* polygon; // the whole polygon as added
  };
  // The polygons on `plane` (same orientation, within qbsp's 0.1 epsilon) that overlap
  // `winding` (counter-clockwise seen from the front) by more than `minArea`.
  std::vector<Overlap> overlaps(const Plane& plane, const Winding& winding, double minArea = 1e-3) const;

  // The payload of the polygon that overlaps `winding` the most; nullopt when none does.
  std::optional<uint32_t> bestOverlap(const Plane& plane, const Winding& winding) const;

private:
  struct Entry {
    Plane plane;
    Winding polygon;
    dvec3 boundsMin, boundsMax;
    uint32_t payload;
  };
  static uint64_t key(int axis, int64_t distCell);

  std::vector<Entry> entries_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> buckets_; // key -> indices into entries_
};

} // namespace bt::bsp
