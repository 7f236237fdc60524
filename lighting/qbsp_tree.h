// qbsp's BSP tree of the world, grown as ericw-tools' BrushBSP grows it (brushbsp.cc, from qbsp3):
// at each node the side plane of the brushes there that SelectSplitPlane values most, the
// brushes split by it, until none is left to split with. Only the planes and their order are
// kept: qbsp makes the faces on each node's plane from the portals under that node and merges
// them there (faces.cc MakeFaces_r, MergeNodeFaces), so a brush side is cut by the planes of
// the nodes above the node its plane lies on, and by no plane below it (qbsp_faces.h).
//
// No mid-split of large nodes (-maxnodesize): the oracle's trees of levels wider than 1024
// units (light_q2_translucent_shadow, bouncecolorscaletest) have at their root the plane of
// best value, not the middle one. Not modelled: ChopBrushes (overlapping brushes are not carved
// into disjoint ones first), hint sides, the check that a plane cuts the node's volume, and the
// clip brushes of a Quake 2 world; each can move a plane. Checked against the compiler's trees
// on the Quake 2 oracle levels only (qbsp_faces.cpp worldTree).
#pragma once

#include "scene/scene.h"
#include "scene/winding.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bt {

class QbspTree {
public:
  struct Input {
    uint32_t brush;
    bool visible; // its sides are drawn; qbsp splits with hidden sides (a Quake 2 area portal's
                  // nodraw) only where no drawn one is left, but counts their brushes everywhere
    bool detail;  // func_detail (Quake 2: CONTENTS_DETAIL): split with once no structural side is left
    // Per face of the brush, those hidden although the brush is `visible` (empty: none): a Quake
    // 1 side seen only from the void or from inside solid (quake1WorldTree).
    std::vector<bool> hiddenSides{};
  };
  // A brush that fills the leaves it lies in without carving faces (Quake 2: an area portal, a
  // liquid), with the contents those leaves take (qbsp3's brush contents; a func_areaportal's
  // brush is CONTENTS_AREAPORTAL whatever its sides say): what a face looks into.
  struct Filler {
    uint32_t brush;
    int32_t contents;
  };
  QbspTree() = default; // no split: no world tree
  // The tree of brushes `brushes` of `scene`, the leaves filled by `fillers`. With `around`, a
  // node that none of those polygons reaches is left a leaf: the nodes above a polygon, and so
  // the cuts qbsp makes in it, are the whole tree's, and the subtrees elsewhere (most of a
  // large level's tree) are not grown.
  QbspTree(const Scene& scene, std::span<const Input> brushes, std::vector<Filler> fillers = {},
           std::optional<std::vector<Winding>> around = std::nullopt);

  struct Node {
    Plane plane;                 // qbsp's positive plane: its largest normal component is positive
    int32_t children[2]{-1, -1}; // front, back; -1 a leaf
  };
  const std::vector<Node>& nodes() const { return nodes_; } // nodes_[0] the root; empty: no split
  const std::vector<Filler>& fillers() const { return fillers_; }

private:
  std::vector<Node> nodes_;
  std::vector<Filler> fillers_;
};

// The same plane either way round (qbsp's plane hash: 1e-5 on the normal, 0.01 on the distance).
bool sameQbspPlane(const Plane& a, const Plane& b);

// qbsp's positive-facing plane: `p` or its flip, whichever has its largest normal component > 0.
Plane positivePlane(const Plane& p);

} // namespace bt
