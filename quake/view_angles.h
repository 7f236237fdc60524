// Quake's view angles, as the engines turn them into a view.
#pragma once

#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace bt::quake {

struct ViewVectors {
  glm::vec3 forward;
  glm::vec3 right;
  glm::vec3 up;
};

// Quake's AngleVectors (mathlib.c), angles in degrees: at zero angles forward = +X, right = -Y,
// up = +Z; positive pitch looks down, positive yaw turns left (towards +Y), roll turns about
// forward. Every engine of the family (Half-Life, Quake 2, Quake 3) keeps it.
inline ViewVectors angleVectors(float pitchDegrees, float yawDegrees, float rollDegrees) {
  const float pitch = glm::radians(pitchDegrees), yaw = glm::radians(yawDegrees), roll = glm::radians(rollDegrees);
  const float sp = std::sin(pitch), cp = std::cos(pitch);
  const float sy = std::sin(yaw), cy = std::cos(yaw);
  const float sr = std::sin(roll), cr = std::cos(roll);
  return {
      {cp * cy, cp * sy, -sp},
      {-sr * sp * cy + cr * sy, -sr * sp * sy - cr * cy, -sr * cp},
      {cr * sp * cy + sr * sy, cr * sp * sy - sr * cy, cr * cp},
  };
}

} // namespace bt::quake
