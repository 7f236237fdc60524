// Brushes built in code for the test suites and benchmarks: faces with their planes, windings,
// Quake's axial texture frames and the brush's bounds, as an importer makes them.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace bt::test {

// What every face of a brush gets, and the entity the brush belongs to (whose brush count is the
// caller's to keep).
struct BrushFaces {
  uint32_t material = 0;
  std::string texture; // the faces' texture name
  uint32_t entity = 0;
};

// How addBrush() makes a face's winding: a square of half-side `radius` on its plane, clipped by
// every other plane with `epsilon`, as qbsp does. The suites' scenes were written with different
// values, which each keeps so that no scene changes.
struct WindingClip {
  double radius = 1 << 20;
  double epsilon = 1e-7;
};

// Appends the convex brush bounded by `planes` (normals out): a face per plane, in their order
// (with an empty winding for a redundant plane), each with Quake's axial texture frame (qbsp's
// base axes for an unrotated, unscaled texture). Its bounds are `bounds` where given, else those
// of its windings. Returns the brush's index.
uint32_t addBrush(Scene& scene, std::span<const Plane> planes, const BrushFaces& faces, const WindingClip& clip = {},
                  const std::optional<Bounds>& bounds = std::nullopt);

// Appends the axial box [min, max]: faces -X, +X, -Y, +Y, -Z, +Z, each winding the face's
// rectangle, counter-clockwise seen from outside, with exact corners. Returns the brush's index.
uint32_t addBox(Scene& scene, const dvec3& min, const dvec3& max, const BrushFaces& faces);

} // namespace bt::test
