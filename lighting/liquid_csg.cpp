#include "lighting/liquid_csg.h"

#include "lighting/liquids.h"
#include "lighting/qbsp_faces.h"
#include "lighting/render_scene.h"
#include "quake/entity_keys.h"
#include "shaders/liquid_csg_constants.glsl" // the tolerances, shared with shaders/visible.glsl

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

namespace {

constexpr double kOnPlane = BT_LIQUID_CSG_ON_PLANE;
static_assert(kOnPlane == kOnPlaneEpsilon, "the rule's tolerance is qbsp_faces.h's");

// The contents qbsp gives a liquid brush: teleporters are water to the compiler (only the
// engine tells them apart, by name).
enum class Contents : uint8_t { None, Water, Slime, Lava };

Contents liquidContents(const Face& face) {
  switch (liquidKind(face.texture, face.surface ? &*face.surface : nullptr)) {
  case LiquidKind::Slime: return Contents::Slime;
  case LiquidKind::Lava: return Contents::Lava;
  default: return Contents::Water;
  }
}

// Each world brush's liquid contents (None for solids and brush entities): that of its first face
// classified as liquid. Faces without surface attributes are classified once per material (a
// texture name says it all), which keeps this to a few hundred names on the largest levels.
std::vector<Contents> brushLiquids(const Scene& scene) {
  std::vector<Contents> kinds(scene.brushes.size(), Contents::None);
  const Game game = gameOf(scene);
  std::vector<int8_t> materialLiquid(scene.materials.size(), -1); // unknown, no, yes
  const auto liquid = [&](const Face& face) {
    if (face.surface || face.material >= materialLiquid.size())
      return (classifyTexture(face.texture, face.surface, game) & kFaceLiquid) != 0;
    int8_t& known = materialLiquid[face.material];
    if (known < 0) known = (classifyTexture(face.texture, std::nullopt, game) & kFaceLiquid) != 0;
    return known > 0;
  };
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    const Brush& brush = scene.brushes[b];
    if (brush.entity >= scene.entities.size() || !mergedIntoWorld(scene.entities[brush.entity].classname())) continue;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
      if (liquid(scene.faces[f])) {
        kinds[b] = liquidContents(scene.faces[f]);
        break;
      }
  }
  return kinds;
}

// Boxes that overlap or touch, within the on-plane tolerance.
bool reach(const Bounds& a, const Bounds& b) {
  for (int i = 0; i < 3; ++i)
    if (a.min[i] > b.max[i] + kOnPlaneEpsilon || b.min[i] > a.max[i] + kOnPlaneEpsilon) return false;
  return true;
}

bool samePlane(const Plane& a, const Plane& b) {
  return glm::dot(a.normal, b.normal) > 1.0 - BT_LIQUID_CSG_NORMAL && std::abs(a.dist - b.dist) <= kOnPlane;
}

enum class Holds { No, Touching, Inside };

// How a side of a brush lies against the plane of a face: in it facing the same way, in it
// facing the other way, or across it (then the point decides). What holds() asks of a side
// before the point, hence what LiquidCsg::against() answers once per face and brush.
enum class SideAgainst { Same, Opposite, Across };
SideAgainst sideAgainst(const Plane& side, const Plane& plane) {
  if (samePlane(side, plane)) return SideAgainst::Same;
  if (samePlane(side, plane.flipped())) return SideAgainst::Opposite;
  return SideAgainst::Across;
}

// Where `p`, on face plane `plane` of another brush, lies against `brush`: inside it (its
// boundary included, except where the face lies in one of its sides facing the same way: two
// coplanar outer faces, of which the tracer's tie rule shows the later), against one of its sides
// that the face looks into (two brushes touching there), or not in it.
Holds holds(const Scene& scene, const Brush& brush, const Plane& plane, const dvec3& p) {
  bool touching = false;
  for (uint32_t k = brush.firstFace; k < brush.firstFace + brush.faceCount; ++k) {
    switch (sideAgainst(scene.faces[k].plane, plane)) {
    case SideAgainst::Same: return Holds::No;
    case SideAgainst::Opposite: touching = true; break;
    case SideAgainst::Across:
      if (scene.faces[k].plane.distanceTo(p) > kOnPlane) return Holds::No;
      break;
    }
  }
  return touching ? Holds::Touching : Holds::Inside;
}

// Whether the level's liquids are still to be merged: a .map's. A .bsp's brushes come out of
// the compiler: a Quake 1 or Half-Life level's are the cells of its tree, merged already, and a
// Quake 2 level's sides carry what qbsp kept of them (a side it removed is hidden, one it kept is
// drawn, _noclipfaces included). q3map2 has no such rule.
bool mapperLiquids(const Scene& scene) {
  if (gameOf(scene) == Game::Quake3) return false;
  const std::string_view f = scene.format;
  return f != "bsp29" && f != "bsp2" && f != "2psb" && f != "bsp30" && f != "ibsp38";
}

// qbsp's _noclipfaces: a brush entity's brushes with the key clip no brush of their own contents.
bool clipsSameContents(const Scene& scene, const Brush& brush) {
  return brush.entity >= scene.entities.size() || quake::EntityKeys(scene.entities[brush.entity]).integer("_noclipfaces", 0) == 0;
}

} // namespace

LiquidCsg::LiquidCsg(const Scene& scene) {
  if (!mapperLiquids(scene)) return;
  const std::vector<Contents> kinds = brushLiquids(scene);
  std::vector<uint32_t> liquids;
  for (uint32_t b = 0; b < kinds.size(); ++b)
    if (kinds[b] != Contents::None) liquids.push_back(b);
  if (liquids.size() < 2) return;
  // Pairs whose boxes reach each other: a sweep along x.
  std::sort(liquids.begin(), liquids.end(),
            [&](uint32_t a, uint32_t b) { return scene.brushes[a].bounds.min.x < scene.brushes[b].bounds.min.x; });
  std::vector<std::vector<Other>> byBrush(scene.brushes.size());
  for (size_t i = 0; i < liquids.size(); ++i) {
    const Bounds& a = scene.brushes[liquids[i]].bounds;
    for (size_t j = i + 1; j < liquids.size() && scene.brushes[liquids[j]].bounds.min.x <= a.max.x + kOnPlaneEpsilon; ++j) {
      if (!reach(a, scene.brushes[liquids[j]].bounds)) continue;
      const uint32_t bi = liquids[i], bj = liquids[j];
      const bool same = kinds[bi] == kinds[bj];
      if (!same || clipsSameContents(scene, scene.brushes[bj])) byBrush[bi].push_back({bj, same});
      if (!same || clipsSameContents(scene, scene.brushes[bi])) byBrush[bj].push_back({bi, same});
    }
  }
  first_.assign(scene.faces.size() + 1, 0);
  for (uint32_t f = 0; f < scene.faces.size(); ++f) {
    first_[f] = uint32_t(others_.size());
    const uint32_t b = scene.faces[f].brush;
    if (b < byBrush.size() && kinds[b] != Contents::None) others_.insert(others_.end(), byBrush[b].begin(), byBrush[b].end());
  }
  first_.back() = uint32_t(others_.size());
  if (others_.empty()) first_.clear();
}

bool LiquidCsg::drawn(const Scene& scene, uint32_t face, const dvec3& p, bool leaving) const {
  const Plane& plane = scene.faces[face].plane;
  bool inOtherKind = false;
  for (uint32_t i = first_[face]; i < first_[face + 1]; ++i) {
    const Holds h = holds(scene, scene.brushes[others_[i].brush], plane, p);
    if (h == Holds::No) continue;
    if (others_[i].sameKind) return false; // merged into one volume: no face here
    inOtherKind |= h == Holds::Inside;
  }
  return !leaving || inOtherKind;
}

LiquidCsg::Against LiquidCsg::against(const Scene& scene, uint32_t face, uint32_t brush) {
  const Plane& plane = scene.faces[face].plane;
  const Brush& b = scene.brushes[brush];
  Against a;
  for (uint32_t k = b.firstFace; k < b.firstFace + b.faceCount; ++k) {
    switch (sideAgainst(scene.faces[k].plane, plane)) {
    case SideAgainst::Same: return Against{.never = true};
    case SideAgainst::Opposite: a.touching = true; break;
    case SideAgainst::Across: a.sides.push_back(k); break;
    }
  }
  return a;
}

std::optional<uint32_t> LiquidCsg::keptFaceAt(const Scene& scene, const std::vector<uint32_t>& faceFlags, uint32_t face, const dvec3& p,
                                              const dvec3& dir) const {
  std::optional<uint32_t> kept;
  const auto consider = [&](uint32_t b) {
    const Brush& brush = scene.brushes[b];
    for (uint32_t k = brush.firstFace; k < brush.firstFace + brush.faceCount; ++k)
      if (scene.faces[k].plane.distanceTo(p) > kOnPlane) return; // p is not on this brush
    for (uint32_t k = brush.firstFace; k < brush.firstFace + brush.faceCount; ++k) {
      const Plane& plane = scene.faces[k].plane;
      if (k == face || (faceFlags[k] & kFaceHidden) || std::abs(plane.distanceTo(p)) > kOnPlane || glm::dot(plane.normal, dir) >= 0.0)
        continue;
      if ((!kept || k > *kept) && (!reaches(k) || drawn(scene, k, p, false))) kept = k;
    }
  };
  consider(scene.faces[face].brush);
  for (uint32_t i = first_[face]; i < first_[face + 1]; ++i) consider(others_[i].brush);
  return kept;
}

} // namespace bt
