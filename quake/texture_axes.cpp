#include "quake/texture_axes.h"

#include <glm/geometric.hpp>

#include <array>

namespace bt::quake {

namespace {

using glm::dvec3;

// qbsp's baseaxis: {normal, s axis, t axis} for floor, ceiling, west, east, south, north.
constexpr std::array<std::array<dvec3, 3>, 6> kBaseAxis{{
    {dvec3(0, 0, 1), dvec3(1, 0, 0), dvec3(0, -1, 0)},
    {dvec3(0, 0, -1), dvec3(1, 0, 0), dvec3(0, -1, 0)},
    {dvec3(1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, -1)},
    {dvec3(-1, 0, 0), dvec3(0, 1, 0), dvec3(0, 0, -1)},
    {dvec3(0, 1, 0), dvec3(1, 0, 0), dvec3(0, 0, -1)},
    {dvec3(0, -1, 0), dvec3(1, 0, 0), dvec3(0, 0, -1)},
}};

} // namespace

TextureAxes textureAxisFromPlane(const dvec3& normal) {
  // qbsp starts from 0 and axis 0, so a degenerate normal gets the floor's axes.
  double best = 0.0;
  size_t bestAxis = 0;
  for (size_t i = 0; i < kBaseAxis.size(); ++i) {
    const double d = glm::dot(normal, kBaseAxis[i][0]);
    if (d > best) {
      best = d;
      bestAxis = i;
    }
  }
  return {kBaseAxis[bestAxis][1], kBaseAxis[bestAxis][2], kBaseAxis[bestAxis][0]};
}

} // namespace bt::quake
