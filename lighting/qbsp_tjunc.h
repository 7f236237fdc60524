// qbsp's T-junction fix (ericw-tools 2.0 tjunc.cc, its default `-tjunc mwt`), which the oracle's
// qbsp runs on a model's faces after it has merged and subdivided them: each face's edges get
// every vertex of the faces it welds with that lies on them (CreateSuperFace), and the face is
// then cut by the minimum weight triangulation of those points into fans (mwt_face,
// compress_triangles_into_fans). A face so gets cut that had no T-junction to fix: a polygon
// whose lightest triangulation is no fan. Each piece is a face of the .bsp, with its own bounce
// light (bounce.h): q2_areaportals' north wall above z 128 is a quad and a triangle there, cut
// along the lightest diagonal of the rectangle with the doorway walls' vertices at z 192 on its
// sides.
#pragma once

#include "scene/winding.h"

#include <array>
#include <cstdint>
#include <set>
#include <unordered_map>
#include <vector>

namespace bt {

// The vertices of a model's compiled faces, each with its face's weld group: faces weld only
// with faces of the same group (qbsp's Welds: the same contents, detail with detail).
class TJunctionVertices {
public:
  void add(const Winding& face, uint32_t weldGroup);
  // The vertices of `weldGroup` in the box lo..hi, in the order they were added.
  std::vector<dvec3> inBox(const dvec3& lo, const dvec3& hi, uint32_t weldGroup) const;

private:
  struct Vertex {
    dvec3 p;
    uint32_t group;
  };
  std::vector<Vertex> vertices_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_; // grid cell -> vertices in it
  std::set<std::array<int64_t, 4>> known_;                    // welded positions and groups
};

// The faces qbsp writes of compiled face `face` (a convex polygon of weld group `weldGroup`):
// the face with the T-junction vertices of `vertices` on its edges, cut into fans.
std::vector<Winding> fixTJunctions(const Winding& face, uint32_t weldGroup, const TJunctionVertices& vertices);

// `w` without the points where it goes straight on: `light` drops them (winding_t::
// remove_colinear) before it places a face's bounce light at the mean of its points.
Winding withoutColinearPoints(const Winding& w);

// The minimum weight triangulation of convex polygon `polygon` gathered into fans, the largest
// first (ericw-tools mwt_face): the polygons qbsp writes for a face whose edges carry `polygon`'s
// points. Empty when no triangulation avoids a degenerate triangle.
std::vector<Winding> minimumWeightFans(const Winding& polygon);

} // namespace bt
