#include "renderer/gl/gl_camera.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt::gl {

CameraBasis CameraBasis::fromQuakeAngles(const glm::vec3& origin, float pitch, float yaw, float roll, int width, int height,
                                         float horizontalFovDegrees) {
  const float p = glm::radians(pitch), y = glm::radians(yaw), r = glm::radians(roll);
  const float sp = std::sin(p), cp = std::cos(p), sy = std::sin(y), cy = std::cos(y), sr = std::sin(r), cr = std::cos(r);
  const float tanHalfX = std::tan(glm::radians(horizontalFovDegrees) * 0.5f);
  const float tanHalfY = tanHalfX * static_cast<float>(height) / static_cast<float>(std::max(width, 1));
  CameraBasis c;
  c.origin = origin;
  // Quake's AngleVectors (mathlib.c): at zero angles forward = +X, right = -Y, up = +Z.
  c.forward = {cp * cy, cp * sy, -sp};
  c.right = glm::vec3(-sr * sp * cy + cr * sy, -sr * sp * sy - cr * cy, -sr * cp) * tanHalfX;
  c.up = glm::vec3(cr * sp * cy + sr * sy, cr * sp * sy - sr * cy, cr * cp) * tanHalfY;
  return c;
}

} // namespace bt::gl
