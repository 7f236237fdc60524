#include "viewer/fly_camera.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>

namespace bt {

FlyCamera::FlyCamera(const glm::dvec3& position_, double pitch_, double yaw_)
    : position(position_), pitch(std::clamp(pitch_, -89.0, 89.0)), yaw(std::fmod(std::fmod(yaw_, 360.0) + 360.0, 360.0)) {}

glm::dvec3 FlyCamera::forward() const {
  const double p = glm::radians(pitch), y = glm::radians(yaw);
  // Quake: positive pitch looks down, so z goes with -sin(pitch).
  return {std::cos(p) * std::cos(y), std::cos(p) * std::sin(y), -std::sin(p)};
}

glm::dvec3 FlyCamera::rightVector() const {
  const double y = glm::radians(yaw);
  return {std::sin(y), -std::cos(y), 0.0};
}

bool FlyCamera::update(const FlyInput& in, double seconds) {
  bool changed = false;

  if (in.looking && (in.mouseDx != 0.0 || in.mouseDy != 0.0)) {
    yaw = std::fmod(std::fmod(yaw - in.mouseDx * lookDegreesPerPixel, 360.0) + 360.0, 360.0);
    pitch = std::clamp(pitch + in.mouseDy * lookDegreesPerPixel, -89.0, 89.0);
    changed = true;
  }

  // TrenchBroom: the wheel while looking scales the fly speed instead of moving.
  if (in.wheel != 0.0) {
    if (in.looking) {
      speed = std::clamp(speed * std::pow(1.25, in.wheel), kMinSpeed, kMaxSpeed);
    } else {
      position += forward() * (in.wheel * wheelStep * (in.fast ? fastFactor : 1.0));
      changed = true;
    }
  }

  glm::dvec3 move{0.0};
  if (in.forward) move += forward();
  if (in.back) move -= forward();
  if (in.right) move += rightVector();
  if (in.left) move -= rightVector();
  if (in.up) move.z += 1.0;
  if (in.down) move.z -= 1.0;
  if (glm::dot(move, move) > 0.0 && seconds > 0.0) {
    position += glm::normalize(move) * (speed * (in.fast ? fastFactor : 1.0) * seconds);
    changed = true;
  }
  return changed;
}

} // namespace bt
