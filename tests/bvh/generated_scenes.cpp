#include "tests/bvh/generated_scenes.h"
#include "scene/winding.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

namespace bt::test {
namespace {

Plane planeThrough(const dvec3& normal, const dvec3& point) {
  const dvec3 n = glm::normalize(normal);
  return {n, glm::dot(n, point)};
}

std::vector<Plane> boxPlanes(const dvec3& min, const dvec3& max) {
  return {{{-1, 0, 0}, -min.x}, {{1, 0, 0}, max.x}, {{0, -1, 0}, -min.y}, {{0, 1, 0}, max.y}, {{0, 0, -1}, -min.z}, {{0, 0, 1}, max.z}};
}

// A prism with a regular polygon as its cross-section, standing on the XY plane.
std::vector<Plane> prismPlanes(const dvec3& centre, double radius, double zMin, double zMax, int sides) {
  std::vector<Plane> planes{{{0, 0, -1}, -zMin}, {{0, 0, 1}, zMax}};
  for (int i = 0; i < sides; ++i) {
    const double angle = 2.0 * std::numbers::pi * (i + 0.5) / sides;
    const dvec3 n(std::cos(angle), std::sin(angle), 0.0);
    planes.push_back({n, glm::dot(n, centre) + radius});
  }
  return planes;
}

} // namespace

uint32_t addBrush(Scene& scene, std::span<const Plane> planes, const char* texture) {
  if (scene.entities.empty()) scene.entities.push_back({1, {{"classname", "worldspawn"}}, 0, 0});
  if (scene.materials.empty() || !scene.findMaterial(texture)) scene.materials.push_back({.name = texture});
  const uint32_t brush = addBrush(scene, planes, {.material = *scene.findMaterial(texture), .texture = texture});
  scene.entities[0].brushCount = static_cast<uint32_t>(scene.brushes.size());
  return brush;
}

uint32_t addBox(Scene& scene, const dvec3& min, const dvec3& max, const char* texture) {
  const std::vector<Plane> planes = boxPlanes(min, max);
  return addBrush(scene, planes, texture);
}

GeneratedLevel generateLevel(int brushCount, uint32_t seed) {
  // About 12 brushes per room (see below).
  const int rooms = std::max(1, brushCount / 12);
  const int levels = std::max(1, static_cast<int>(std::cbrt(rooms) / 2));
  const int side = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(rooms) / levels))));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto snap = [](double x) { return std::round(x / 8.0) * 8.0; }; // mappers work on an 8-unit grid

  GeneratedLevel level;
  Scene& scene = level.scene;
  constexpr double kRoom = 256.0, kSlab = 16.0, kWall = 16.0, kHeight = 192.0;
  int made = 0;
  for (int z = 0; z < levels && made < rooms; ++z)
    for (int y = 0; y < side && made < rooms; ++y)
      for (int x = 0; x < side && made < rooms; ++x, ++made) {
        const dvec3 o(x * kRoom, y * kRoom, z * (kHeight + 2 * kSlab));
        const double top = o.z + kSlab + kHeight;
        addBox(scene, o, o + dvec3(kRoom, kRoom, kSlab), "floor");                       // 1
        addBox(scene, {o.x, o.y, top}, {o.x + kRoom, o.y + kRoom, top + kSlab}, "ceil"); // 2
        // West and south walls with a door gap; the neighbours' walls close the other sides.
        const double door = snap(64 + unit(rng) * 96);
        addBox(scene, {o.x, o.y + kWall, o.z + kSlab}, {o.x + kWall, o.y + door, top});      // 3
        addBox(scene, {o.x, o.y + door + 64, o.z + kSlab}, {o.x + kWall, o.y + kRoom, top}); // 4
        addBox(scene, {o.x, o.y, o.z + kSlab}, {o.x + door, o.y + kWall, top});              // 5
        addBox(scene, {o.x + door + 64, o.y, o.z + kSlab}, {o.x + kRoom, o.y + kWall, top}); // 6
        // An octagonal pillar and a ramp: the slanted planes.
        // In one of the four quarters away from the room's centre, where openPoints lie.
        const dvec3 pillar(o.x + (unit(rng) < 0.5 ? 64 : 192), o.y + (unit(rng) < 0.5 ? 64 : 192), 0);
        const std::vector<Plane> octagon = prismPlanes(pillar, 12 + unit(rng) * 12, o.z + kSlab, top, 8);
        addBrush(scene, octagon, "pillar"); // 7
        const double rampX = o.x + snap(24 + unit(rng) * 128), rampY = o.y + snap(24 + unit(rng) * 128);
        std::vector<Plane> ramp = boxPlanes({rampX, rampY, o.z + kSlab}, {rampX + 96, rampY + 64, o.z + kSlab + 48});
        ramp[5] = planeThrough({-48, 0, 96}, {rampX, rampY, o.z + kSlab}); // slope up along +X
        addBrush(scene, ramp, "ramp");                                     // 8
        for (int c = 0; c < 4; ++c) {                                      // 9..12: crates, some stacked
          const double size = snap(16 + unit(rng) * 32);
          const double cx = o.x + snap(24 + unit(rng) * (kRoom - 48 - size));
          const double cy = o.y + snap(24 + unit(rng) * (kRoom - 48 - size));
          const double cz = o.z + kSlab + (c == 3 ? size : 0.0);
          addBox(scene, {cx, cy, cz}, {cx + size, cy + size, cz + size}, "crate");
        }
        level.openPoints.push_back(o + dvec3(kRoom * 0.5 + 7.3, kRoom * 0.5 - 11.1, kSlab + 120.0));
      }
  return level;
}

Scene generateRandomBrushes(int count, uint32_t seed, double extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto point = [&] { return dvec3(unit(rng), unit(rng), unit(rng)) * extent; };
  auto direction = [&] {
    dvec3 d;
    do d = dvec3(unit(rng), unit(rng), unit(rng)) * 2.0 - 1.0;
    while (glm::dot(d, d) > 1.0 || glm::dot(d, d) < 1e-4);
    return glm::normalize(d);
  };

  Scene scene;
  while (static_cast<int>(scene.brushes.size()) < count) {
    const double kind = unit(rng);
    // Sizes spread over two orders of magnitude, as in real maps (trim to whole rooms).
    const dvec3 size = dvec3(std::exp(unit(rng) * 4.0), std::exp(unit(rng) * 4.0), std::exp(unit(rng) * 4.0)) * 4.0;
    const dvec3 min = glm::round(point());
    if (kind < 0.45) {
      addBox(scene, min, min + glm::round(size) + 1.0);
    } else if (kind < 0.6) {
      // A box and a neighbour sharing its +X face exactly.
      const dvec3 max = min + glm::round(size) + 1.0;
      addBox(scene, min, max);
      addBox(scene, {max.x, min.y, min.z}, {max.x + 16.0, max.y, max.z});
    } else {
      // A box cut by up to five random planes through points near its centre.
      const dvec3 max = min + size;
      std::vector<Plane> planes = boxPlanes(min, max);
      const int cuts = 1 + static_cast<int>(unit(rng) * 5);
      for (int c = 0; c < cuts; ++c) {
        const dvec3 n = direction();
        const dvec3 centre = (min + max) * 0.5;
        const dvec3 through = centre + n * (0.1 + 0.3 * unit(rng)) * glm::length(size) * 0.5;
        planes.push_back(planeThrough(n, through));
      }
      addBrush(scene, planes, "slanted");
    }
  }
  return scene;
}

} // namespace bt::test
