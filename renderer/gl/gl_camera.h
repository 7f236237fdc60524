// The pinhole camera as the GL tracer's shaders take it (GpuCamera), from Quake's view angles.
#pragma once

#include <glm/vec3.hpp>

namespace bt::gl {

// right and up are scaled by tan(fov / 2) along their axis: the ray through pixel centre (x, y)
// of a w by h image, y counted from the top, is
// forward + (2 (x + 0.5) / w - 1) right + (1 - 2 (y + 0.5) / h) up, normalised.
struct CameraBasis {
  glm::vec3 origin{0.0f};
  glm::vec3 forward{1.0f, 0.0f, 0.0f};
  glm::vec3 right{0.0f, -1.0f, 0.0f};
  glm::vec3 up{0.0f, 0.0f, 1.0f};

  // Quake's view angles in degrees (pitch positive looks down, yaw counter-clockwise from +X,
  // roll), axes as Quake's AngleVectors like renderer/camera.h's Camera, and a horizontal field of
  // view (Quake's default 90) for a width by height image.
  static CameraBasis fromQuakeAngles(const glm::vec3& origin, float pitch, float yaw, float roll, int width, int height,
                                     float horizontalFovDegrees = 90.0f);
};

} // namespace bt::gl
