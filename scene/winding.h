// Convex polygons on a plane ("windings", as Quake's tools call them), in double precision.
//
// Both importers build every brush side's polygon the way qbsp does: a huge square on the
// side's plane, clipped by the brush's other planes. Each passes the epsilon it needs (qbsp's
// ON_EPSILON for .map sources; a larger one for compiled, snapped BSP vertices).
#pragma once

#include "scene/scene.h"

#include <vector>

namespace bt {

using Winding = std::vector<dvec3>;

// A square of half-size `radius` on the plane, counter-clockwise seen from the front (the side
// the normal points to).
Winding baseWinding(const Plane& plane, double radius);

// The part of `w` behind `plane` (distance <= epsilon). Empty when nothing is left.
Winding clipBehind(const Winding& w, const Plane& plane, double epsilon);

struct SplitWinding {
  Winding front, back;
};
// Both parts of `w` split by `plane`; a part is empty when `w` lies entirely on the other side.
// Points within epsilon of the plane go to both parts.
SplitWinding splitWinding(const Winding& w, const Plane& plane, double epsilon);

// Area vector (Newell): direction = the side from which the winding is counter-clockwise,
// length = area.
dvec3 areaVector(const Winding& w);
double area(const Winding& w);

// The part of the convex polygon `w` inside the convex polygon `clip`, both lying on (about) one
// plane with normal `normal`; `clip` must be counter-clockwise seen from the front.
Winding intersectConvex(const Winding& w, const Winding& clip, const dvec3& normal);

// Removes points closer than epsilon to their predecessor; a winding left with fewer than three
// points becomes empty.
void removeDuplicatePoints(Winding& w, double epsilon = 1e-6);

// The point of convex polygon `w` (counter-clockwise seen along `normal`) nearest to p, a point of
// its plane: p itself inside, else the nearest point of its boundary. The compilers move a luxel
// centre that falls off its face there.
dvec3 nearestOnPolygon(const Winding& w, const dvec3& normal, const dvec3& p);

} // namespace bt
