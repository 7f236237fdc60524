// What qbsp's CSG leaves of liquid faces where liquid brushes overlap, as a rule on ray hits.
//
// ericw-tools qbsp (2.0.0-alpha11, the oracle's compiler) merges overlapping liquids of one
// kind: the parts of a liquid brush's faces inside, or against, another liquid brush of the same
// contents are not compiled (q1_csg_water_eats_water: a water brush inside another leaves no
// face; the face between two touching water brushes goes, q2_csg_water_water_current90). Where
// liquids of different kinds overlap, both keep their faces, each compiled from both sides as
// every liquid face is ("mirrored inside"): q1_water_slime_zfighting's water side inside the
// slime is drawn, seen from the slime. The kinds are the contents: water (any other `*` name,
// teleporters too), slime, lava; Quake 2 by contents bits.
//
// The tracers intersect whole brushes, so the rule is applied per hit rather than by cutting
// polygons: a hit on a liquid face whose brush overlaps other liquid brushes (LiquidCsg::reaches)
//  - entering its brush: is not drawn where the point lies inside, or on the far side of a
//    touching face of, another liquid brush of the same kind;
//    Where such a hit lies on an edge of its brush (the tracer's tie went to the removed face),
//    the face qbsp keeps at that point stands in (keptFaceAt): the top of two touching pools;
//  - leaving its brush (a hit the tracer otherwise passes): is drawn, facing the ray, where the
//    ray goes on inside a liquid brush of another kind and no liquid brush of its own kind holds
//    the point. (Elsewhere the tracers draw no liquid face from inside, although qbsp mirrors
//    them all: a known gap of both tracers, older than this rule.)
// Only a .map's brushes that qbsp merges into the world count (each brush entity is a model
// compiled apart; a .bsp's brushes carry the compiler's result already), and a brush entity with
// `_noclipfaces 1` clips no liquid of its own kind. Quake 3 levels are left alone. A level
// without overlapping liquids has no entries, and its hits take no extra test. The GL tracer
// applies the same rule (shaders/visible.glsl, compiled in only for levels with entries), from
// the table renderer/gl/gl_lighting.cpp packs of others().
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace bt {

class LiquidCsg {
public:
  LiquidCsg() = default;
  // The liquid kind of a brush is that of its first face classified as liquid.
  explicit LiquidCsg(const Scene& scene);

  // Whether other liquid brushes reach `face`'s brush: only then can the rule change a hit on it.
  bool reaches(uint32_t face) const { return face + 1 < first_.size() && first_[face] != first_[face + 1]; }

  // Whether a hit on liquid face `face` at `p` is drawn: entering its brush (`leaving` false),
  // or leaving it. Only for faces that reaches().
  bool drawn(const Scene& scene, uint32_t face, const dvec3& p, bool leaving) const;

  // For an entering hit that drawn() removes: a face that qbsp keeps at the same point `p`, of
  // the hit's brush or of the liquid brushes that reach it, that a ray along `dir` enters there
  // (the hit lies on an edge, where the tracer's tie went to the removed face); the later in the
  // file, as the tracer's tie rule picks. None in the middle of a removed face.
  std::optional<uint32_t> keptFaceAt(const Scene& scene, const std::vector<uint32_t>& faceFlags, uint32_t face, const dvec3& p,
                                     const dvec3& dir) const;

  bool empty() const { return others_.empty(); }

  // What drawn() asks of `brush` for a point on `face`'s plane, less the point: `never` where a
  // side lies in that plane facing the same way (the brush holds no point of the face), else
  // whether a side lies in it facing the other way (the brush can only touch the face), and the
  // sides whose half-spaces the point must lie in. The GL tracer's table stores these, so that
  // its rule tests the point alone (renderer/gl/gl_lighting.h liquidCsgTable).
  struct Against {
    bool never = false;
    bool touching = false;
    std::vector<uint32_t> sides;
  };
  static Against against(const Scene& scene, uint32_t face, uint32_t brush);

  // A liquid brush that reaches a face's brush (a Scene::brushes index), and whether it is of
  // the face's kind (merged with it) or of another (kept apart).
  struct Other {
    uint32_t brush;
    bool sameKind;
  };
  // The liquid brushes that reach `face`'s brush; empty where reaches() is false.
  std::span<const Other> others(uint32_t face) const {
    if (!reaches(face)) return {};
    return std::span<const Other>(others_).subspan(first_[face], first_[face + 1] - first_[face]);
  }

private:
  // Per scene face, [first_[f], first_[f + 1]) of others_; empty when no liquid brushes overlap.
  std::vector<uint32_t> first_;
  std::vector<Other> others_;
};

} // namespace bt
