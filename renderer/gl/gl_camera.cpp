#include "renderer/gl/gl_camera.h"

#include "quake/view_angles.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt::gl {

CameraBasis CameraBasis::fromQuakeAngles(const glm::vec3& origin, float pitch, float yaw, float roll, int width, int height,
                                         float horizontalFovDegrees) {
  const float tanHalfX = std::tan(glm::radians(horizontalFovDegrees) * 0.5f);
  const float tanHalfY = tanHalfX * static_cast<float>(height) / static_cast<float>(std::max(width, 1));
  const quake::ViewVectors v = quake::angleVectors(pitch, yaw, roll);
  CameraBasis c;
  c.origin = origin;
  c.forward = v.forward;
  c.right = v.right * tanHalfX;
  c.up = v.up * tanHalfY;
  return c;
}

} // namespace bt::gl
