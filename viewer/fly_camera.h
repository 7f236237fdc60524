// The viewer's camera controller, with TrenchBroom's fly-mode bindings so that mappers need
// no new habits: right-drag looks, WASD moves, Q/E (or Space/C) go down/up, the wheel moves
// forward, the wheel while right-dragging changes the speed, Shift is fast. There is no roll.
//
// Angles follow Quake's view-angle convention: yaw 0 looks along +X, 90 along +Y; positive
// pitch looks down (as in `mangle` and the engine's cl.viewangles), in degrees.
#pragma once

#include <glm/vec3.hpp>

namespace bt {

struct FlyInput {
  bool forward = false, back = false, left = false, right = false;
  bool up = false, down = false;
  bool fast = false;    // Shift
  bool looking = false; // right mouse button held
  double mouseDx = 0.0; // pixels since the last frame
  double mouseDy = 0.0;
  double wheel = 0.0; // notches since the last frame, positive away from the user
};

class FlyCamera {
public:
  FlyCamera() = default;
  FlyCamera(const glm::dvec3& position, double pitch, double yaw);

  // Applies one frame of input. Returns true when the view changed (the tracer restarts).
  bool update(const FlyInput& input, double seconds);

  glm::dvec3 forward() const;
  glm::dvec3 rightVector() const; // in the horizontal plane: no roll

  glm::dvec3 position{0.0};
  double pitch = 0.0;   // degrees, clamped to ±89 so the view never flips
  double yaw = 0.0;     // degrees, kept in [0, 360)
  double speed = 320.0; // units per second (Quake's run speed)
  double lookDegreesPerPixel = 0.2;
  double wheelStep = 32.0; // units per wheel notch
  double fastFactor = 4.0;
  static constexpr double kMinSpeed = 16.0;
  static constexpr double kMaxSpeed = 8192.0;
};

} // namespace bt
