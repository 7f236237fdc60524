#include "importers/bsp/brushes.h"

#include "importers/bsp/coplanar_index.h"
#include "quake/binary_reader.h"
#include "quake/bspfile_q1.h"
#include "quake/texture_axes.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <iterator>

namespace bt::bsp {

namespace {

// Half the size of the square every side's polygon starts as; larger than any Quake level
// (Q3's limit is +-65536) so that clipping, not the square, shapes every side.
constexpr double kHugeRadius = 1 << 20;
// Sides smaller than this (units^2) are bevels or clipping noise, not surfaces.
constexpr double kMinSideArea = 1e-3;
// Distances below this count as "on the plane" while clipping. qbsp uses 0.1 for its
// ON_EPSILON; compiled vertices are snapped, so a smaller value keeps thin slivers apart.
constexpr double kOnEpsilon = 0.01;

Plane toPlane(const BspPlane& p) {
  return {dvec3(p.normal), static_cast<double>(p.dist)};
}

// The point of `plane` where both texture coordinates are zero: solves
// dot(n, o) = dist, dot(tangent, o) = -sOffset, dot(bitangent, o) = -tOffset.
dvec3 frameOrigin(const Plane& plane, const dvec3& tangent, const dvec3& bitangent, double sOffset, double tOffset) {
  const glm::dmat3 rows(plane.normal, tangent, bitangent); // columns; transpose = rows
  const glm::dmat3 m = glm::transpose(rows);
  if (std::abs(glm::determinant(m)) < 1e-12) return plane.normal * plane.dist; // degenerate projection
  return glm::inverse(m) * dvec3(plane.dist, -sOffset, -tOffset);
}

// The six outward planes of the box [lo, hi], +x, -x, +y, -y, +z, -z.
std::vector<Plane> axialBoxPlanes(const dvec3& lo, const dvec3& hi) {
  std::vector<Plane> planes;
  for (int axis = 0; axis < 3; ++axis) {
    dvec3 n{0.0};
    n[axis] = 1.0;
    planes.push_back({n, hi[axis]});
    planes.push_back({-n, -lo[axis]});
  }
  return planes;
}

// Name the reference decompiler gives hidden sides, by the contents of their brush.
const char* quake1SkipTexture(int32_t contents) {
  switch (contents) {
  case quake::q1::CONTENTS_WATER: return "*waterskip";
  case quake::q1::CONTENTS_SLIME: return "*slimeskip";
  case quake::q1::CONTENTS_LAVA: return "*lavaskip";
  case quake::q1::CONTENTS_SKY: return "skyskip";
  default: return "skip";
  }
}

// A convex brush from its outward planes: each plane's polygon is a huge square clipped by
// every other plane. Planes that end up with no (or a sliver of) polygon do not bound the
// brush (duplicates, Quake 2/3 collision bevels) and are dropped. `kept` receives, for each
// side returned, the index of its plane.
std::vector<CompiledSide> sidesFromPlanes(const std::vector<Plane>& planes, std::vector<size_t>* kept = nullptr) {
  std::vector<CompiledSide> sides;
  for (size_t i = 0; i < planes.size(); ++i) {
    Winding w = baseWinding(planes[i], kHugeRadius);
    for (size_t j = 0; j < planes.size() && !w.empty(); ++j) {
      if (i == j) continue;
      // Of two identical planes only the first keeps its polygon.
      if (j < i && glm::dot(planes[i].normal, planes[j].normal) > 1.0 - 1e-9 && std::abs(planes[i].dist - planes[j].dist) < kOnEpsilon) {
        w.clear();
        break;
      }
      w = clipBehind(w, planes[j], kOnEpsilon);
    }
    removeDuplicatePoints(w);
    if (w.empty() || area(w) < kMinSideArea) continue;
    CompiledSide side;
    side.plane = planes[i];
    side.winding = std::move(w);
    sides.push_back(std::move(side));
    if (kept) kept->push_back(i);
  }
  return sides;
}

// Quake 2 and Quake 3 store a brush alike: a range of brush sides, each naming a plane. Returns
// the sides sidesFromPlanes rebuilds from them and, in `from`, the stored side each came from.
std::vector<CompiledSide> sidesOfStoredBrush(const BspFile& bsp, const Brush& source, std::vector<const BrushSide*>& from) {
  std::vector<Plane> planes;
  std::vector<const BrushSide*> stored;
  for (int32_t s = 0; s < source.sideCount; ++s) {
    const BrushSide& side = bsp.brushSides[static_cast<size_t>(source.firstSide + s)];
    planes.push_back(toPlane(bsp.planes[static_cast<size_t>(side.plane)]));
    stored.push_back(&side);
  }
  std::vector<size_t> kept;
  std::vector<CompiledSide> sides = sidesFromPlanes(planes, &kept);
  from.clear();
  for (size_t k : kept) from.push_back(stored[k]);
  return sides;
}

// ---------------------------------------------------------------------------------------------
// Quake 1: texture frames from the BSP faces lying on each side

// The faces of one model, indexed by plane, for finding the face lying on a brush side.
CoplanarIndex modelFaceIndex(const BspFile& bsp, const Model& model) {
  CoplanarIndex index;
  for (int32_t i = 0; i < model.faceCount; ++i) {
    const size_t f = static_cast<size_t>(model.firstFace + i);
    const Face& face = bsp.faces[f];
    Plane plane = toPlane(bsp.planes[static_cast<size_t>(face.plane)]);
    if (face.side) plane = plane.flipped();
    index.add(plane, bsp.faceVertices(f), static_cast<uint32_t>(f));
  }
  return index;
}

void texturizeQuake1Sides(const BspFile& bsp, const CoplanarIndex& faces, CompiledBrush& brush) {
  for (CompiledSide& side : brush.sides) {
    if (const auto face = faces.bestOverlap(side.plane, side.winding)) {
      const TexInfo& texinfo = bsp.texinfo[static_cast<size_t>(bsp.faces[*face].texinfo)];
      side.texture = texinfo.texture;
      side.frame = texinfoFrame(texinfo, side.plane);
      side.hasSurface = true;
    } else {
      side.texture = quake1SkipTexture(brush.contents);
      side.frame = paraxialFrame(side.plane);
    }
  }
}

// A convex cell of the BSP tree, being split on the way down from the root.
struct CellSide {
  Plane plane; // outward
  Winding winding;
};
using Cell = std::vector<CellSide>;

struct CellSplit {
  Cell front, back;
  bool frontEmpty = false, backEmpty = false;
};

// Splits a convex cell by a node plane: the front cell lies in front of `plane`.
CellSplit splitCell(const Cell& cell, const Plane& plane) {
  CellSplit out;
  // The cell's cross-section on the plane: that plane's polygon clipped by every side.
  Winding section = baseWinding(plane, kHugeRadius);
  for (const CellSide& side : cell) {
    section = clipBehind(section, side.plane, kOnEpsilon);
    if (section.empty()) break;
  }
  removeDuplicatePoints(section);
  if (section.empty() || area(section) < kMinSideArea) {
    // The plane misses the cell: all of it is on one side.
    double lowest = 0.0, highest = 0.0;
    for (const CellSide& side : cell)
      for (const dvec3& p : side.winding) {
        lowest = std::min(lowest, plane.distanceTo(p));
        highest = std::max(highest, plane.distanceTo(p));
      }
    const bool inFront = highest > -lowest;
    (inFront ? out.front : out.back) = cell;
    (inFront ? out.backEmpty : out.frontEmpty) = true;
    return out;
  }
  for (const CellSide& side : cell) {
    SplitWinding parts = splitWinding(side.winding, plane, kOnEpsilon);
    if (parts.front.size() >= 3 && area(parts.front) >= kMinSideArea) out.front.push_back({side.plane, std::move(parts.front)});
    if (parts.back.size() >= 3 && area(parts.back) >= kMinSideArea) out.back.push_back({side.plane, std::move(parts.back)});
  }
  // `section` is counter-clockwise seen from the plane's front: right for the back cell, whose
  // outward normal is the plane's; reversed for the front cell.
  Winding reversed(section.rbegin(), section.rend());
  out.back.push_back({plane, std::move(section)});
  out.front.push_back({plane.flipped(), std::move(reversed)});
  return out;
}

// A box around the model, a bit larger, that bounds the cells of leafs reaching the void.
Cell boundingCell(const Model& model) {
  constexpr double kMargin = 32.0;
  const std::vector<Plane> planes = axialBoxPlanes(dvec3(model.mins) - kMargin, dvec3(model.maxs) + kMargin);
  Cell cell;
  for (CompiledSide& side : sidesFromPlanes(planes)) cell.push_back({side.plane, std::move(side.winding)});
  return cell;
}

// A cell side may carry faces of several textures: two brushes of one solid region, side by side
// on one plane, need no tree node between them. Like the reference decompiler, split such cells
// along an edge of one of the faces until every side has one texinfo.
std::optional<Plane> textureSplitPlane(const BspFile& bsp, const CoplanarIndex& faces, const CellSide& side) {
  const auto on = faces.overlaps(side.plane, side.winding, 0.01);
  bool mixed = false;
  for (const auto& o : on) mixed |= bsp.faces[o.payload].texinfo != bsp.faces[on.front().payload].texinfo;
  if (!mixed) return std::nullopt;
  // Candidates: the lines through the faces' edges. A useful one has a face of one texinfo
  // wholly in front and a face of another wholly behind; the best cuts the fewest faces in two.
  std::optional<Plane> best;
  size_t bestScore = SIZE_MAX;
  constexpr size_t kMaxCandidateFaces = 64; // bounds the work a corrupt file can ask for
  for (size_t c = 0; c < on.size() && c < kMaxCandidateFaces; ++c) {
    const auto& candidateFace = on[c];
    const Winding& polygon = *candidateFace.polygon;
    for (size_t i = 0; i < polygon.size(); ++i) {
      const dvec3 edge = polygon[(i + 1) % polygon.size()] - polygon[i];
      dvec3 n = glm::cross(side.plane.normal, edge);
      const double len = glm::length(n);
      if (len < 1e-6) continue;
      n /= len;
      const Plane split{n, glm::dot(n, polygon[i])};
      size_t cut = 0, frontOnly = 0, backOnly = 0;
      int32_t frontTexinfo = -1, backTexinfo = -1;
      bool separates = false;
      for (const auto& o : on) {
        double lo = 0.0, hi = 0.0;
        for (const dvec3& p : *o.polygon) {
          lo = std::min(lo, split.distanceTo(p));
          hi = std::max(hi, split.distanceTo(p));
        }
        const int32_t texinfo = bsp.faces[o.payload].texinfo;
        if (hi > kOnEpsilon && lo < -kOnEpsilon) {
          ++cut;
        } else if (hi > kOnEpsilon) {
          ++frontOnly;
          separates |= backTexinfo >= 0 && backTexinfo != texinfo;
          frontTexinfo = texinfo;
        } else if (lo < -kOnEpsilon) {
          ++backOnly;
          separates |= frontTexinfo >= 0 && frontTexinfo != texinfo;
          backTexinfo = texinfo;
        }
      }
      if (!separates) continue;
      const size_t score = cut * 100000 + (frontOnly > backOnly ? frontOnly - backOnly : backOnly - frontOnly);
      if (score < bestScore) {
        bestScore = score;
        best = split;
      }
    }
  }
  return best;
}

void splitByTexture(Cell cell, const BspFile& bsp, const CoplanarIndex& faces, int depth, std::vector<Cell>& out) {
  constexpr int kMaxDepth = 32; // each split separates at least two faces; this only guards
  if (depth < kMaxDepth) {
    for (const CellSide& side : cell) {
      const std::optional<Plane> split = textureSplitPlane(bsp, faces, side);
      if (!split) continue;
      CellSplit parts = splitCell(cell, *split);
      if (parts.frontEmpty || parts.backEmpty) continue;
      splitByTexture(std::move(parts.front), bsp, faces, depth + 1, out);
      splitByTexture(std::move(parts.back), bsp, faces, depth + 1, out);
      return;
    }
  }
  out.push_back(std::move(cell));
}

// The planes of a slab `thickness` deep behind a face: the face's plane, its back, and one
// outward plane through each edge of the polygon.
std::vector<Plane> slabPlanes(const Plane& plane, const Winding& polygon, double thickness) {
  std::vector<Plane> planes{plane, {-plane.normal, -(plane.dist - thickness)}};
  for (size_t k = 0; k < polygon.size(); ++k) {
    const dvec3& a = polygon[k];
    const dvec3 edge = polygon[(k + 1) % polygon.size()] - a;
    dvec3 outward = glm::cross(edge, plane.normal);
    const double len = glm::length(outward);
    if (len < 1e-9) continue;
    outward /= len;
    planes.push_back({outward, glm::dot(outward, a)});
  }
  return planes;
}

// Faces no solid cell carries: func_detail_illusionary and other see-through detail compile to
// faces in empty leafs. So that they still show, each becomes a thin slab brush behind the face;
// a face compiled both ways (qbsp's mirrored insides) shares one slab, its twin on the back.
// A liquid surface is compiled facing both ways too, but its brush carries it: the face seen from
// inside the liquid has the liquid cell's side at its back, and is left out. Liquid-textured faces
// with no liquid behind them are func_illusionary_visblocker (qbsp writes its volume as empty
// leafs) and get their slab like any other.
std::vector<CompiledBrush> slabsForUncoveredFaces(const BspFile& bsp, const Model& model, const std::vector<CompiledBrush>& cells) {
  constexpr double kSlabThickness = 1.0 / 16.0; // within qbsp's 0.1 epsilon: the twin still lies "on" the back
  CoplanarIndex sides;
  for (const CompiledBrush& cell : cells)
    for (const CompiledSide& side : cell.sides) sides.add(side.plane, side.winding, 0);

  struct Uncovered {
    size_t face;
    Plane plane;
    Winding polygon; // counter-clockwise seen from the front
  };
  std::vector<Uncovered> uncovered;
  CoplanarIndex uncoveredIndex;
  for (int32_t i = 0; i < model.faceCount; ++i) {
    const size_t f = static_cast<size_t>(model.firstFace + i);
    const std::string_view texture = bsp.faceTexture(f);
    const bool liquid = !texture.empty() && texture[0] == '*';
    const Face& face = bsp.faces[f];
    Plane plane = toPlane(bsp.planes[static_cast<size_t>(face.plane)]);
    if (face.side) plane = plane.flipped();
    const auto points = bsp.faceVertices(f);
    Winding polygon(points.rbegin(), points.rend());
    removeDuplicatePoints(polygon);
    const double faceArea = area(polygon);
    if (faceArea < kMinSideArea) continue;
    double covered = 0.0;
    for (const auto& o : sides.overlaps(plane, polygon)) covered += o.area;
    if (liquid) {
      const Winding back(polygon.rbegin(), polygon.rend());
      for (const auto& o : sides.overlaps(plane.flipped(), back)) covered += o.area;
    }
    if (covered >= 0.5 * faceArea) continue;
    uncoveredIndex.add(plane, polygon, static_cast<uint32_t>(uncovered.size()));
    uncovered.push_back({f, plane, std::move(polygon)});
  }

  std::vector<CompiledBrush> slabs;
  std::vector<bool> used(uncovered.size(), false);
  for (size_t u = 0; u < uncovered.size(); ++u) {
    if (used[u]) continue;
    used[u] = true;
    const Uncovered& front = uncovered[u];
    std::optional<size_t> twin;
    const Winding reversed(front.polygon.rbegin(), front.polygon.rend());
    if (const auto t = uncoveredIndex.bestOverlap(front.plane.flipped(), reversed); t && !used[*t]) {
      twin = *t;
      used[*t] = true;
    }
    const std::vector<Plane> planes = slabPlanes(front.plane, front.polygon, kSlabThickness);
    CompiledBrush slab;
    slab.contents = quake::q1::CONTENTS_EMPTY;
    std::vector<size_t> kept;
    slab.sides = sidesFromPlanes(planes, &kept);
    if (slab.sides.size() < 4) continue;
    for (size_t k = 0; k < slab.sides.size(); ++k) {
      CompiledSide& side = slab.sides[k];
      std::optional<size_t> face;
      if (kept[k] == 0) face = front.face;
      if (kept[k] == 1 && twin) face = uncovered[*twin].face;
      if (face) {
        const TexInfo& texinfo = bsp.texinfo[static_cast<size_t>(bsp.faces[*face].texinfo)];
        side.texture = texinfo.texture;
        side.frame = texinfoFrame(texinfo, side.plane);
        side.hasSurface = true;
      } else {
        side.texture = "skip";
        side.frame = paraxialFrame(side.plane);
      }
    }
    slabs.push_back(std::move(slab));
  }
  return slabs;
}

[[noreturn]] void failTree(const BspFile& bsp, const char* lump, std::string message) {
  throw ImportError(Diagnostic{Severity::Error, bsp.path, 0, 0, fmt::format("lump '{}': {}", lump, message)});
}

} // namespace

TextureFrame paraxialFrame(const Plane& plane) {
  const quake::TextureAxes axes = quake::textureAxisFromPlane(plane.normal);
  TextureFrame frame;
  frame.tangent = axes.s;
  frame.bitangent = axes.t;
  frame.origin = frameOrigin(plane, frame.tangent, frame.bitangent, 0.0, 0.0);
  return frame;
}

TextureFrame texinfoFrame(const TexInfo& texinfo, const Plane& plane) {
  TextureFrame frame;
  frame.tangent = dvec3(texinfo.vecs[0][0], texinfo.vecs[0][1], texinfo.vecs[0][2]);
  frame.bitangent = dvec3(texinfo.vecs[1][0], texinfo.vecs[1][1], texinfo.vecs[1][2]);
  frame.origin = frameOrigin(plane, frame.tangent, frame.bitangent, texinfo.vecs[0][3], texinfo.vecs[1][3]);
  return frame;
}

bool hasVolume(const CompiledBrush& brush) {
  for (const CompiledSide& side : brush.sides) {
    double deepest = 0.0;
    for (const CompiledSide& other : brush.sides)
      for (const dvec3& p : other.winding) deepest = std::max(deepest, -side.plane.distanceTo(p));
    if (deepest < kOnEpsilon) return false;
  }
  return !brush.sides.empty();
}

std::vector<CompiledBrush> hullBrushes(const BspFile& bsp, size_t modelIndex) {
  const Model& model = bsp.models.at(modelIndex);
  std::vector<CompiledBrush> brushes;
  if (bsp.nodes.empty()) return brushes;
  const CoplanarIndex faces = modelFaceIndex(bsp, model);

  // Depth-first over the tree with an explicit stack: a corrupt file may nest deeply, and each
  // node may be entered only once (a node reached twice means a cycle or a shared subtree).
  struct Pending {
    int32_t child;
    Cell cell;
  };
  std::vector<Pending> stack;
  stack.push_back({model.headNode[0], boundingCell(model)});
  std::vector<bool> visited(bsp.nodes.size(), false);
  while (!stack.empty()) {
    Pending item = std::move(stack.back());
    stack.pop_back();
    if (item.child < 0) {
      const Leaf& leaf = bsp.leafs[static_cast<size_t>(-1 - int64_t{item.child})];
      if (leaf.contents == quake::q1::CONTENTS_EMPTY || item.cell.size() < 4) continue;
      std::vector<Cell> pieces;
      splitByTexture(std::move(item.cell), bsp, faces, 0, pieces);
      for (Cell& piece : pieces) {
        if (piece.size() < 4) continue;
        CompiledBrush brush;
        brush.contents = leaf.contents;
        for (CellSide& side : piece) {
          CompiledSide out;
          out.plane = side.plane;
          out.winding = std::move(side.winding);
          brush.sides.push_back(std::move(out));
        }
        texturizeQuake1Sides(bsp, faces, brush);
        brushes.push_back(std::move(brush));
      }
      continue;
    }
    const size_t nodeIndex = static_cast<size_t>(item.child);
    if (visited[nodeIndex]) failTree(bsp, "nodes", fmt::format("node {} is reached twice from model {} (a cycle)", nodeIndex, modelIndex));
    visited[nodeIndex] = true;
    const Node& node = bsp.nodes[nodeIndex];
    CellSplit split = splitCell(item.cell, toPlane(bsp.planes[static_cast<size_t>(node.plane)]));
    if (!split.frontEmpty) stack.push_back({node.children[0], std::move(split.front)});
    if (!split.backEmpty) stack.push_back({node.children[1], std::move(split.back)});
  }
  std::vector<CompiledBrush> slabs = slabsForUncoveredFaces(bsp, model, brushes);
  std::move(slabs.begin(), slabs.end(), std::back_inserter(brushes));
  return brushes;
}

std::optional<std::vector<CompiledBrush>> brushListBrushes(const BspFile& bsp, size_t modelIndex) {
  const BspxLump* lump = bsp.findBspx("BRUSHLIST");
  if (!lump) return std::nullopt;
  const auto& bytes = lump->bytes;
  quake::LittleEndianReader reader(bytes);
  auto fail = [&](const std::string& message) {
    throw ImportError(
        Diagnostic{Severity::Error, bsp.path, 0, 0, fmt::format("lump 'BSPX BRUSHLIST': {} (at byte {})", message, reader.position())});
  };
  // Checked here too, so that a truncated lump is an error naming the file and the lump.
  auto need = [&](size_t n) {
    if (reader.remaining() < n) fail("truncated");
  };
  auto u16 = [&] {
    need(2);
    return reader.u16();
  };
  auto i32 = [&] {
    need(4);
    return reader.i32();
  };
  auto f32 = [&] {
    need(4);
    return reader.f32();
  };

  // Layout (ericw-tools bspxfile): per model { int32 version = 1, modelnum, numbrushes,
  // numplanes; per brush { float mins[3], maxs[3]; int16 contents; uint16 numplanes;
  // numplanes x { float normal[3], dist } } }. Each brush lists only its non-axial planes; the
  // axial ones are its bounds.
  const CoplanarIndex faces = modelFaceIndex(bsp, bsp.models.at(modelIndex));
  while (reader.remaining() > 0) {
    const int32_t version = i32();
    if (version != 1) fail(fmt::format("unsupported version {}", version));
    const int32_t model = i32();
    const int32_t brushCount = i32();
    i32(); // total plane count, implied by the brushes
    if (brushCount < 0) fail(fmt::format("negative brush count {}", brushCount));
    std::vector<CompiledBrush> brushes;
    for (int32_t b = 0; b < brushCount; ++b) {
      dvec3 lo, hi;
      for (int k = 0; k < 3; ++k) lo[k] = f32();
      for (int k = 0; k < 3; ++k) hi[k] = f32();
      const int32_t contents = static_cast<int16_t>(u16());
      const uint16_t planeCount = u16();
      if (planeCount > 1024) fail(fmt::format("brush {} of model {} has {} planes", b, model, planeCount));
      std::vector<Plane> planes = axialBoxPlanes(lo, hi);
      for (uint16_t p = 0; p < planeCount; ++p) {
        dvec3 n;
        for (int k = 0; k < 3; ++k) n[k] = f32();
        planes.push_back({n, static_cast<double>(f32())});
      }
      if (model != static_cast<int32_t>(modelIndex)) continue;
      CompiledBrush brush;
      brush.contents = contents;
      brush.sides = sidesFromPlanes(planes);
      if (brush.sides.size() < 4) continue;
      texturizeQuake1Sides(bsp, faces, brush);
      brushes.push_back(std::move(brush));
    }
    if (model == static_cast<int32_t>(modelIndex)) return brushes;
  }
  return std::nullopt;
}

std::vector<CompiledBrush> quake2Brushes(const BspFile& bsp, size_t modelIndex) {
  const Model& model = bsp.models.at(modelIndex);
  std::vector<CompiledBrush> brushes;
  if (bsp.nodes.empty()) return brushes;

  // Quake 2 models do not list their brushes: collect those of the leafs under the head node.
  std::vector<int32_t> brushIndices;
  std::vector<bool> taken(bsp.brushes.size(), false);
  std::vector<bool> visited(bsp.nodes.size(), false), leafRead(bsp.leafs.size(), false);
  std::vector<int32_t> stack{model.headNode[0]};
  while (!stack.empty()) {
    const int32_t child = stack.back();
    stack.pop_back();
    if (child < 0) {
      // qbsp3 points every solid node child at the one leaf 0, and a corrupt tree may name any
      // leaf from thousands of nodes: its brush list is read once.
      const size_t leafIndex = static_cast<size_t>(-1 - int64_t{child});
      if (leafRead[leafIndex]) continue;
      leafRead[leafIndex] = true;
      const Leaf& leaf = bsp.leafs[leafIndex];
      for (int32_t i = 0; i < leaf.leafBrushCount; ++i) {
        const int32_t b = bsp.leafBrushes[static_cast<size_t>(leaf.firstLeafBrush + i)];
        if (!taken[static_cast<size_t>(b)]) {
          taken[static_cast<size_t>(b)] = true;
          brushIndices.push_back(b);
        }
      }
      continue;
    }
    if (visited[static_cast<size_t>(child)])
      failTree(bsp, "nodes", fmt::format("node {} is reached twice from model {} (a cycle)", child, modelIndex));
    visited[static_cast<size_t>(child)] = true;
    for (int32_t c : bsp.nodes[static_cast<size_t>(child)].children) stack.push_back(c);
  }
  std::sort(brushIndices.begin(), brushIndices.end()); // file order, as qbsp wrote them

  for (int32_t b : brushIndices) {
    const Brush& source = bsp.brushes[static_cast<size_t>(b)];
    CompiledBrush brush;
    brush.contents = source.contents;
    std::vector<const BrushSide*> from;
    brush.sides = sidesOfStoredBrush(bsp, source, from);
    if (brush.sides.size() < 4) continue;
    for (size_t k = 0; k < brush.sides.size(); ++k) {
      CompiledSide& side = brush.sides[k];
      const int32_t t = from[k]->texinfo;
      if (t >= 0) {
        const TexInfo& texinfo = bsp.texinfo[static_cast<size_t>(t)];
        side.texture = texinfo.texture;
        side.frame = texinfoFrame(texinfo, side.plane);
        side.surface = SurfaceAttributes{source.contents, texinfo.flags, static_cast<double>(texinfo.value)};
        side.hasSurface = true;
      } else {
        side.texture = "e1u1/skip"; // what the reference decompiler names Quake 2's hidden sides
        side.frame = paraxialFrame(side.plane);
        side.surface = SurfaceAttributes{source.contents, 0, 0.0};
      }
    }
    brushes.push_back(std::move(brush));
  }
  return brushes;
}

namespace {

// Quake 3: the draw triangles of one model, for finding the one lying on a brush side.
struct DrawTriangle {
  std::array<uint32_t, 3> vertices; // into BspFile::drawVertices
};

std::vector<DrawTriangle> modelTriangles(const BspFile& bsp, const Model& model, CoplanarIndex& index) {
  std::vector<DrawTriangle> triangles;
  for (int32_t i = 0; i < model.faceCount; ++i) {
    const Surface& s = bsp.surfaces[static_cast<size_t>(model.firstFace + i)];
    // Patches are curved and flares are sprites: only flat geometry can lie on a brush side.
    if (s.type != SurfaceType::Planar && s.type != SurfaceType::TriangleSoup) continue;
    for (int32_t k = 0; k + 2 < s.indexCount; k += 3) {
      DrawTriangle t;
      for (int c = 0; c < 3; ++c)
        t.vertices[c] = static_cast<uint32_t>(s.firstVertex + bsp.drawIndices[static_cast<size_t>(s.firstIndex + k + c)]);
      const DrawVertex& a = bsp.drawVertices[t.vertices[0]];
      const DrawVertex& b = bsp.drawVertices[t.vertices[1]];
      const DrawVertex& c = bsp.drawVertices[t.vertices[2]];
      dvec3 n = glm::cross(dvec3(b.position - a.position), dvec3(c.position - a.position));
      const double len = glm::length(n);
      if (len < 1e-6) continue; // degenerate
      n /= len;
      // The winding order says little across compilers; the vertex normals say which way the
      // surface faces.
      if (glm::dot(n, dvec3(a.normal + b.normal + c.normal)) < 0.0) n = -n;
      index.add({n, glm::dot(n, dvec3(a.position))}, {dvec3(a.position), dvec3(b.position), dvec3(c.position)},
                static_cast<uint32_t>(triangles.size()));
      triangles.push_back(t);
    }
  }
  return triangles;
}

// The frame, in texture units, that reproduces the triangle's st on the side's plane.
std::optional<TextureFrame> triangleFrame(const BspFile& bsp, const DrawTriangle& t, const Plane& plane) {
  const DrawVertex& a = bsp.drawVertices[t.vertices[0]];
  const DrawVertex& b = bsp.drawVertices[t.vertices[1]];
  const DrawVertex& c = bsp.drawVertices[t.vertices[2]];
  const dvec3 e1 = dvec3(b.position - a.position), e2 = dvec3(c.position - a.position);
  // Rows e1, e2, n: the in-plane vector whose dot products with the edges give the st deltas.
  const glm::dmat3 m = glm::transpose(glm::dmat3(e1, e2, plane.normal));
  if (std::abs(glm::determinant(m)) < 1e-9) return std::nullopt;
  const glm::dmat3 inv = glm::inverse(m);
  TextureFrame frame;
  frame.tangent = inv * dvec3(b.st.x - a.st.x, c.st.x - a.st.x, 0.0);
  frame.bitangent = inv * dvec3(b.st.y - a.st.y, c.st.y - a.st.y, 0.0);
  const dvec3 p0(a.position);
  frame.origin =
      frameOrigin(plane, frame.tangent, frame.bitangent, a.st.x - glm::dot(p0, frame.tangent), a.st.y - glm::dot(p0, frame.bitangent));
  return frame;
}

} // namespace

std::vector<CompiledBrush> quake3Brushes(const BspFile& bsp, size_t modelIndex) {
  const Model& model = bsp.models.at(modelIndex);
  CoplanarIndex index;
  const std::vector<DrawTriangle> triangles = modelTriangles(bsp, model, index);
  std::vector<CompiledBrush> brushes;
  for (int32_t i = 0; i < model.brushCount; ++i) {
    const Brush& source = bsp.brushes[static_cast<size_t>(model.firstBrush + i)];
    CompiledBrush brush;
    brush.contents = bsp.shaders[static_cast<size_t>(source.shader)].contentFlags;
    std::vector<const BrushSide*> from;
    brush.sides = sidesOfStoredBrush(bsp, source, from);
    if (brush.sides.size() < 4) continue;
    for (size_t k = 0; k < brush.sides.size(); ++k) {
      CompiledSide& side = brush.sides[k];
      const Shader& shader = bsp.shaders[static_cast<size_t>(from[k]->shader)];
      side.texture = shader.name;
      side.surface = SurfaceAttributes{shader.contentFlags, shader.surfaceFlags, 0.0};
      std::optional<TextureFrame> frame;
      if (const auto t = index.bestOverlap(side.plane, side.winding)) frame = triangleFrame(bsp, triangles[*t], side.plane);
      if (frame) {
        side.frame = *frame;
        side.frameInTextureUnits = true;
        side.hasSurface = true;
      } else {
        side.frame = paraxialFrame(side.plane);
      }
    }
    brushes.push_back(std::move(brush));
  }
  return brushes;
}

} // namespace bt::bsp
