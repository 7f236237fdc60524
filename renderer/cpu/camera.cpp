#include "renderer/cpu/camera.h"

#include "renderer/cpu/lights.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <sstream>
#include <vector>

namespace bt {

namespace {

// Whitespace-separated numbers; nullopt when any word is not one.
std::optional<std::vector<float>> numbersIn(std::string_view text) {
  std::vector<float> numbers;
  std::istringstream words{std::string(text)};
  for (std::string word; words >> word;) {
    const auto f = parseFloat(word);
    if (!f) return std::nullopt;
    numbers.push_back(*f);
  }
  return numbers;
}

// `rest` after the word `name` when `text` starts with it, else nullopt.
std::optional<std::string_view> afterWord(std::string_view text, std::string_view name) {
  const size_t start = text.find_first_not_of(" \t");
  if (start == std::string_view::npos || text.substr(start, name.size()) != name) return std::nullopt;
  text.remove_prefix(start + name.size());
  if (!text.empty() && text.front() != ' ' && text.front() != '\t') return std::nullopt;
  return text;
}

// Quake's console forms: `setpos x y z pitch yaw [roll]` (QuakeSpasm, ironwail) and the Source
// engine's `getpos` line `setpos x y z;setang pitch yaw [roll]`.
std::optional<std::vector<float>> parseSetpos(std::string_view text) {
  const auto rest = afterWord(text, "setpos");
  if (!rest) return std::nullopt;
  const size_t semicolon = rest->find(';');
  if (semicolon == std::string_view::npos) return numbersIn(*rest);
  auto position = numbersIn(rest->substr(0, semicolon));
  const auto angleText = afterWord(rest->substr(semicolon + 1), "setang");
  if (!position || position->size() != 3 || !angleText) return std::nullopt;
  const auto angles = numbersIn(*angleText);
  if (!angles) return std::nullopt;
  position->insert(position->end(), angles->begin(), angles->end());
  return position;
}

// "(x y z) pitch yaw [roll]", as formatCameraPose writes it.
std::optional<std::vector<float>> parseParenthesised(std::string_view text) {
  const size_t open = text.find_first_not_of(" \t");
  const size_t close = text.find(')');
  if (open == std::string_view::npos || text[open] != '(' || close == std::string_view::npos) return std::nullopt;
  auto position = numbersIn(text.substr(open + 1, close - open - 1));
  const auto angles = numbersIn(text.substr(close + 1));
  if (!position || position->size() != 3 || !angles) return std::nullopt;
  position->insert(position->end(), angles->begin(), angles->end());
  return position;
}

} // namespace

std::optional<CameraPose> parseCameraPose(std::string_view text) {
  auto v = parseSetpos(text);
  if (!v) v = parseParenthesised(text);
  // x y z pitch yaw, and roll where given: the consoles print the camera without it.
  if (!v || v->size() < 5 || v->size() > 6) return std::nullopt;
  CameraPose pose;
  pose.origin = {(*v)[0], (*v)[1], (*v)[2]};
  pose.pitch = (*v)[3];
  pose.yaw = (*v)[4];
  pose.roll = v->size() == 6 ? (*v)[5] : 0.0f;
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
