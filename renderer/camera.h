// The pinhole camera, in Quake's view-angle convention: pitch positive looks down, yaw turns
// counter-clockwise from +X seen from above, roll tilts right; 90 degrees horizontal field of
// view like Quake's default `fov`.
#pragma once

#include "bvh/trace_scene.h" // Ray
#include "scene/scene.h"

#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <vector>

namespace bt {

struct CameraPose {
  glm::vec3 origin{0.0f};
  float pitch = 0.0f; // degrees
  float yaw = 0.0f;
  float roll = 0.0f;
  std::string source; // where it came from: "info_intermission", "--camera", ...
};

// "(x y z) pitch yaw roll", Quake's console line "setpos x y z pitch yaw roll" or Source's
// "setpos x y z;setang pitch yaw roll", roll optional in each (0); nullopt when malformed.
std::optional<CameraPose> parseCameraPose(std::string_view text);
std::string formatCameraPose(const CameraPose& pose);

// Where the level's game puts the eye (README, "Default camera"): its intermission view, else
// its player start, else a deathmatch spawn; a level with none of them gets a point of empty
// space inside it, else (nothing closes in anywhere) a view of the whole map from one corner.
CameraPose defaultCameraPose(const Scene& scene);
// Every spawn point and intermission view of the level's game that lies within its bounds, in
// the order defaultCameraPose() prefers them and then file order, each at its eye height and
// angles: the further views a batch renders beside the default one.
std::vector<CameraPose> spawnCameraPoses(const Scene& scene);

class Camera {
public:
  Camera(const CameraPose& pose, int width, int height, float horizontalFovDegrees = 90.0f);
  // Ray through image point (x, y) in pixels, (0, 0) the top-left corner.
  Ray ray(float x, float y) const;
  // The inverse of ray(): the image point (pixels) a world point lies on, with its distance
  // along forward() in z; nullopt for a point not in front of the camera.
  std::optional<glm::vec3> project(const glm::vec3& point) const;
  glm::vec3 forward() const { return forward_; }

private:
  glm::vec3 origin_, forward_, right_, up_;
  float tanHalfX_, tanHalfY_;
  int width_, height_;
};

} // namespace bt
