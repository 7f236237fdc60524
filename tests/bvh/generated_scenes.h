// Scenes built in code for the BVH tests and benchmarks: brushes given as planes, with
// windings, bounds and texture frames computed the way an importer would.
#pragma once

#include "scene/scene.h"
#include "tests/support/scene_builder.h"

#include <cstdint>
#include <span>
#include <vector>

namespace bt::test {

// Appends the convex brush bounded by `planes` (normals pointing out) to the worldspawn of
// `scene` (created if the scene has no entity), every face of material `texture` (added if the
// scene has none of that name), as tests/support/scene_builder.h makes it: bounds from the
// windings. A box's faces are -X, +X, -Y, +Y, -Z, +Z. Returns the brush index.
uint32_t addBrush(Scene& scene, std::span<const Plane> planes, const char* texture = "wall");
uint32_t addBox(Scene& scene, const dvec3& min, const dvec3& max, const char* texture = "wall");

// A level-like scene: a 3D grid of 256-unit rooms, each with floor and ceiling slabs, walls
// with door gaps, an octagonal pillar, a ramp and crates; about `brushCount` brushes in all.
// openPoints are points in empty space (room interiors), where cameras and rays start.
struct GeneratedLevel {
  Scene scene;
  std::vector<dvec3> openPoints;
};
GeneratedLevel generateLevel(int brushCount, uint32_t seed);

// `count` brushes scattered in a cube of side `extent`: boxes of many sizes (some sharing
// faces with a neighbour) and random convex polytopes with slanted planes. Brushes overlap.
Scene generateRandomBrushes(int count, uint32_t seed, double extent = 2048.0);

} // namespace bt::test
