#pragma once

#include <glm/vec3.hpp>

namespace bt::quake {

// The paraxial texture axes of QuakeEd's table (qbsp's baseaxis): the s and t axes a Standard
// face projects onto, and the table normal it snaps to.
struct TextureAxes {
  glm::dvec3 s;
  glm::dvec3 t;
  glm::dvec3 snappedNormal;
};

// qbsp's TextureAxisFromPlane: the first of floor, ceiling, west, east, south, north whose
// normal has a strictly greater dot product with `normal` than every earlier one (a tie keeps
// the earlier entry: qbsp's default, not its -newaxis option). Both the .map importer and the
// .bsp importer (faces without texinfo axes) use it, so they agree at near-ties.
TextureAxes textureAxisFromPlane(const glm::dvec3& normal);

} // namespace bt::quake
