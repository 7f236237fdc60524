#include "renderer/cpu/camera.h"

#include "renderer/cpu/lights.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <regex>

namespace bt {

std::optional<CameraPose> parseCameraPose(std::string_view text) {
  static const std::regex pattern(
      R"(\s*\(\s*(\S+)\s+(\S+)\s+(\S+)\s*\)\s*(\S+)\s+(\S+)\s+(\S+)\s*)");
  std::cmatch m;
  const std::string s(text);
  if (!std::regex_match(s.c_str(), m, pattern)) return std::nullopt;
  float v[6];
  for (int i = 0; i < 6; ++i) {
    auto f = parseFloat(m[i + 1].str());
    if (!f) return std::nullopt;
    v[i] = *f;
  }
  CameraPose pose;
  pose.origin = {v[0], v[1], v[2]};
  pose.pitch = v[3];
  pose.yaw = v[4];
  pose.roll = v[5];
  pose.source = "--camera";
  return pose;
}

std::string formatCameraPose(const CameraPose& p) {
  return fmt::format("({:g} {:g} {:g}) {:g} {:g} {:g}", p.origin.x, p.origin.y, p.origin.z, p.pitch, p.yaw, p.roll);
}

CameraPose defaultCameraPose(const Scene& scene) {
  for (const Entity& e : scene.entities) {
    if (e.classname() != "info_intermission") continue;
    auto origin = parseVec3(e.value("origin"));
    if (!origin) continue;
    CameraPose pose;
    pose.origin = *origin;
    if (auto mangle = parseVec3(e.value("mangle"))) { // pitch yaw roll, as the engine reads it
      pose.pitch = mangle->x;
      pose.yaw = mangle->y;
      pose.roll = mangle->z;
    }
    pose.source = "info_intermission";
    return pose;
  }
  for (const Entity& e : scene.entities) {
    if (e.classname() != "info_player_start") continue;
    auto origin = parseVec3(e.value("origin"));
    if (!origin) continue;
    constexpr float kEyeHeight = 22.0f; // Quake's view offset above the player origin
    CameraPose pose;
    pose.origin = *origin + glm::vec3(0.0f, 0.0f, kEyeHeight);
    pose.yaw = parseFloat(e.value("angle")).value_or(0.0f);
    pose.source = "info_player_start";
    return pose;
  }
  CameraPose pose;
  pose.source = "whole map";
  if (scene.bounds.empty()) return pose;
  // From above the (min x, min y) corner, looking at the centre, far enough to see it all.
  const glm::vec3 center = glm::vec3(scene.bounds.center());
  const glm::vec3 extent = glm::vec3(scene.bounds.extent());
  const float radius = 0.5f * glm::length(extent);
  const glm::vec3 dir = glm::normalize(glm::vec3(1.0f, 1.0f, -0.8f));
  pose.origin = center - dir * radius * 1.6f;
  pose.yaw = glm::degrees(std::atan2(dir.y, dir.x));
  pose.pitch = glm::degrees(std::asin(-dir.z));
  return pose;
}

Camera::Camera(const CameraPose& pose, int width, int height, float horizontalFovDegrees)
    : origin_(pose.origin), width_(width), height_(height) {
  const float pitch = glm::radians(pose.pitch), yaw = glm::radians(pose.yaw), roll = glm::radians(pose.roll);
  // Quake's AngleVectors (mathlib.c): at zero angles forward = +X, right = -Y, up = +Z.
  const float sp = std::sin(pitch), cp = std::cos(pitch);
  const float sy = std::sin(yaw), cy = std::cos(yaw);
  const float sr = std::sin(roll), cr = std::cos(roll);
  forward_ = {cp * cy, cp * sy, -sp};
  right_ = {-sr * sp * cy + cr * sy, -sr * sp * sy - cr * cy, -sr * cp};
  up_ = {cr * sp * cy + sr * sy, cr * sp * sy - sr * cy, cr * cp};
  tanHalfX_ = std::tan(glm::radians(horizontalFovDegrees) * 0.5f);
  tanHalfY_ = tanHalfX_ * float(height) / float(std::max(width, 1));
}

Ray Camera::ray(float x, float y) const {
  const float ndcX = (2.0f * x / float(width_) - 1.0f) * tanHalfX_;
  const float ndcY = (1.0f - 2.0f * y / float(height_)) * tanHalfY_;
  Ray r;
  r.origin = origin_;
  r.direction = glm::normalize(forward_ + ndcX * right_ + ndcY * up_);
  return r;
}

} // namespace bt
