#include "renderer/camera.h"

#include "lighting/game_rules.h"
#include "lighting/lights.h"
#include "lighting/render_scene.h"
#include "quake/entity_keys.h"
#include "quake/view_angles.h"

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <vector>

namespace bt {

namespace {

// Whitespace-separated numbers; nullopt when any word is not one.
std::optional<std::vector<float>> numbersIn(std::string_view text) {
  const auto numbers = quake::parseNumbers(text);
  if (!numbers) return std::nullopt;
  std::vector<float> out;
  for (double n : *numbers) {
    if (!std::isfinite(float(n))) return std::nullopt;
    out.push_back(float(n));
  }
  return out;
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

namespace {

// Where a game puts the eye, per classname, in the order brushtrace prefers them: the level's
// intermission view first (what the game shows at the end of the level: usually an overview),
// then the single-player start, then deathmatch spawns. `height` is added to the entity origin:
// the spawn functions' origin offset plus the player's view height (README, "Default camera").
struct EyePoint {
  std::string_view classname;
  float height;
};

std::vector<EyePoint> eyePoints(Game game) {
  switch (game) {
  case Game::Quake: // client.qc PutClientInServer: view_ofs '0 0 22'
    return {{"info_intermission", 0.0f}, {"info_player_start", 22.0f}, {"info_player_deathmatch", 22.0f}, {"info_player_coop", 22.0f}};
  case Game::HalfLife: // player.cpp CBasePlayer::Spawn: spot + (0 0 1), view_ofs VEC_VIEW (0 0 28)
    return {{"info_player_start", 29.0f}, {"info_player_deathmatch", 29.0f}};
  case Game::Quake2: // p_client.c SelectSpawnPoint: origin[2] += 9; PutClientInServer: viewheight 22
    return {
        {"info_player_intermission", 0.0f}, {"info_player_start", 31.0f}, {"info_player_deathmatch", 31.0f}, {"info_player_coop", 31.0f}};
  case Game::Quake3: // g_client.c SelectSpawnPoint: origin[2] += 9; DEFAULT_VIEWHEIGHT 26
    return {{"info_player_intermission", 0.0f},
            {"info_human_intermission", 0.0f},
            {"info_alien_intermission", 0.0f},
            {"info_player_start", 35.0f},
            {"info_player_deathmatch", 35.0f}}; // the second and third: Unvanquished
  }
  return {};
}

// The entity's view angles as the games' spawn code reads them: `mangle` (Quake's
// info_intermission), else `angles` (pitch yaw roll), else `angle` as the yaw.
void readAngles(const Entity& e, CameraPose& pose) {
  auto angles = quake::parseVec3(e.value("mangle"));
  if (!angles) angles = quake::parseVec3(e.value("angles"));
  if (angles) {
    pose.pitch = angles->x;
    pose.yaw = angles->y;
    pose.roll = angles->z;
  } else if (auto yaw = quake::parseFloat(e.value("angle")); yaw && *yaw >= 0.0f) { // -1/-2 mean up/down
    pose.yaw = *yaw;
  }
}

// Quake 3 g_main.c FindIntermissionPoint: an intermission point with a target looks at it.
void aimAtTarget(const Scene& scene, const Entity& e, CameraPose& pose) {
  const std::string_view target = e.value("target");
  if (target.empty()) return;
  for (const Entity& t : scene.entities) {
    if (t.value("targetname") != target) continue;
    const auto at = quake::parseVec3(t.value("origin"));
    if (!at) return;
    const glm::vec3 d = *at - pose.origin;
    if (glm::length(d) <= 0.0f) return;
    pose.yaw = glm::degrees(std::atan2(d.y, d.x));
    pose.pitch = -glm::degrees(std::atan2(d.z, std::sqrt(d.x * d.x + d.y * d.y))); // positive looks down
    pose.roll = 0.0f;
    return;
  }
}

// How far above a level's bounds an eye still counts as in the level: a player standing on its top.
constexpr double kEyeAboveTheTop = 64.0;

// The faces the game never draws: hidden textures and the entities it hides (render_scene.h).
std::vector<bool> undrawnFaces(const Scene& scene) {
  const Game game = gameOf(scene);
  std::vector<bool> hidden(scene.faces.size());
  for (const Brush& brush : scene.brushes) {
    const bool entityHidden = brush.entity < scene.entities.size() && gameHidesEntity(scene.entities[brush.entity], game);
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount; ++f)
      hidden[f] = entityHidden || (classifyTexture(scene.faces[f].texture, scene.faces[f].surface, game) & kFaceHidden);
  }
  for (const Mesh& mesh : scene.meshes) {
    const bool entityHidden = mesh.entity < scene.entities.size() && gameHidesEntity(scene.entities[mesh.entity], game);
    for (uint32_t f = mesh.firstFace; f < mesh.firstFace + mesh.faceCount; ++f)
      hidden[f] = entityHidden || (classifyTexture(scene.faces[f].texture, scene.faces[f].surface, game) & kFaceHidden);
  }
  return hidden;
}

// The distance to the first drawn face along a ray, stepping past hidden faces and the far
// sides of brushes the ray starts in; nullopt when it leaves the level.
std::optional<float> drawnHitDistance(const TraceScene& tracer, const std::vector<bool>& hidden, Ray ray) {
  for (int i = 0; i < BT_MAX_SKIPS; ++i) {
    const std::optional<Hit> hit = tracer.closestHit(ray);
    if (!hit) return std::nullopt;
    if (!hit->inside && !hidden[hit->face]) return hit->t;
    ray.tMin = continueRayAfter(hit->t);
  }
  return std::nullopt;
}

bool insideSolid(const Scene& scene, const std::vector<BrushContents>& contents, const dvec3& p) {
  for (size_t b = 0; b < scene.brushes.size(); ++b) {
    const Brush& brush = scene.brushes[b];
    if (contents[b] != BrushContents::Solid) continue;
    bool inside = true;
    for (uint32_t f = brush.firstFace; inside && f < brush.firstFace + brush.faceCount; ++f)
      inside = scene.faces[f].plane.distanceTo(p) < 0.0;
    if (inside) return true;
  }
  return false;
}

// The most open of eight horizontal directions at `origin`, level, 45 degrees or straight down: the one
// whose first drawn face is farthest; nullopt when none sees a drawn face.
std::optional<CameraPose> mostOpenView(const TraceScene& tracer, const std::vector<bool>& hidden, const glm::vec3& origin) {
  std::optional<CameraPose> best;
  float farthest = 0.0f;
  for (float pitch : {0.0f, 45.0f, 89.0f})
    for (int k = 0; k < 8; ++k) {
      CameraPose pose;
      pose.origin = origin;
      pose.pitch = pitch;
      pose.yaw = 45.0f * float(k);
      const glm::vec3 dir = Camera(pose, 1, 1).forward();
      const float d = drawnHitDistance(tracer, hidden, Ray{origin, 0.0f, dir}).value_or(0.0f);
      if (d > farthest) farthest = d, best = pose;
    }
  return best;
}

// A level without spawn points (compiler test maps): a point of a grid over its bounds in no
// solid brush, the nearest to the centre that drawn faces close in on all six axis directions
// (else, in a level that closes in nowhere, the nearest that sees any drawn face), looking
// along its most open view.
std::optional<CameraPose> insideCameraPose(const Scene& scene) {
  if (scene.bounds.empty()) return std::nullopt;
  const std::vector<bool> hidden = undrawnFaces(scene);
  BvhBuildOptions bvh;
  bvh.includeBrush.assign(scene.brushes.size(), false);
  for (size_t b = 0; b < scene.brushes.size(); ++b)
    for (uint32_t f = scene.brushes[b].firstFace; f < scene.brushes[b].firstFace + scene.brushes[b].faceCount; ++f)
      if (!hidden[f]) bvh.includeBrush[b] = true;
  for (const Mesh& mesh : scene.meshes) bvh.includeMesh.push_back(mesh.faceCount > 0 && !hidden[mesh.firstFace]);
  const TraceScene tracer = TraceScene::build(scene, bvh);
  const std::vector<BrushContents> contents = brushContents(scene);
  // The grid reaches a player's eye height above the top, where a level that is only a floor is seen.
  constexpr int kGrid = 7;
  const dvec3 extent = scene.bounds.extent() + dvec3(0.0, 0.0, kEyeAboveTheTop);
  std::vector<dvec3> points;
  for (int i = 0; i < kGrid * kGrid * kGrid; ++i)
    points.push_back(scene.bounds.min +
                     extent * dvec3((i % kGrid + 0.5) / kGrid, (i / kGrid % kGrid + 0.5) / kGrid, (i / kGrid / kGrid + 0.5) / kGrid));
  const dvec3 centre = scene.bounds.center();
  std::stable_sort(points.begin(), points.end(),
                   [&](const dvec3& a, const dvec3& b) { return glm::length(a - centre) < glm::length(b - centre); });
  std::erase_if(points, [&](const dvec3& p) { return insideSolid(scene, contents, p); });
  auto closedIn = [&](const glm::vec3& origin) {
    for (int axis = 0; axis < 6; ++axis) {
      glm::vec3 dir(0.0f);
      dir[axis / 2] = axis % 2 ? -1.0f : 1.0f;
      if (!drawnHitDistance(tracer, hidden, Ray{origin, 0.0f, dir})) return false;
    }
    return true;
  };
  for (bool mustBeClosed : {true, false})
    for (const dvec3& p : points)
      if (!mustBeClosed || closedIn(glm::vec3(p)))
        if (auto pose = mostOpenView(tracer, hidden, glm::vec3(p))) {
          pose->source = "inside the level";
          return pose;
        }
  return std::nullopt;
}

// Whether a ray enters a brush from outside through a face that is not hidden (one ray: every
// brush is tried, no BVH is built).
bool seesDrawnFace(const Scene& scene, const std::vector<bool>& hidden, const glm::vec3& origin, const glm::vec3& dir) {
  const dvec3 o(origin), d(dir);
  for (const Brush& brush : scene.brushes) {
    double enter = 0.0, exit = std::numeric_limits<double>::infinity();
    uint32_t entryFace = kNoFace;
    for (uint32_t f = brush.firstFace; f < brush.firstFace + brush.faceCount && enter <= exit; ++f) {
      const Plane& plane = scene.faces[f].plane;
      const double distance = plane.distanceTo(o), along = glm::dot(plane.normal, d);
      if (along == 0.0) {
        if (distance > 0.0) exit = -1.0; // parallel and in front: the ray misses the brush
      } else if (along < 0.0) {
        if (-distance / along > enter) enter = -distance / along, entryFace = f;
      } else {
        exit = std::min(exit, -distance / along);
      }
    }
    if (entryFace != kNoFace && enter <= exit && !hidden[entryFace]) return true;
  }
  return false;
}

// Compiler test maps put their player start anywhere, even outside the level or in a wall: such
// a spawn is no view of the level. In the bounds, or above them by a player's eye height (a
// level that is only a floor), and in no solid brush.
bool withinLevel(const Scene& scene, const glm::vec3& eye) {
  const dvec3 p(eye);
  for (int a = 0; a < 3; ++a)
    if (!(p[a] > scene.bounds.min[a] && p[a] < scene.bounds.max[a] + (a == 2 ? kEyeAboveTheTop : 0.0))) return false;
  return !insideSolid(scene, brushContents(scene), p);
}

// A spawn point above a level that is only a floor (compiler test maps) looks into the void:
// the view then turns down (then up), and failing that around, until it sees the level.
CameraPose facingTheLevel(const Scene& scene, CameraPose pose) {
  const std::vector<bool> hidden = undrawnFaces(scene);
  auto sees = [&](const CameraPose& p) { return seesDrawnFace(scene, hidden, p.origin, Camera(p, 1, 1).forward()); };
  if (sees(pose)) return pose;
  for (float turn : {0.0f, 90.0f, 180.0f, 270.0f})
    for (float pitch : {15.0f, 30.0f, 45.0f, 60.0f, 75.0f, 89.0f, -30.0f, -60.0f, -89.0f}) {
      CameraPose p = pose;
      p.yaw += turn;
      p.pitch = pitch;
      if (sees(p)) {
        p.source += ", turned to face the level";
        return p;
      }
    }
  return pose;
}

std::optional<CameraPose> gameCamera(const Scene& scene) {
  const Game game = gameOf(scene);
  for (const EyePoint& eye : eyePoints(game)) {
    // Quake 2's single player starts at the info_player_start without a targetname.
    const Entity* found = nullptr;
    for (const Entity& e : scene.entities) {
      if (e.classname() != eye.classname || !quake::parseVec3(e.value("origin"))) continue;
      if (!found || (found->find("targetname") && !e.find("targetname"))) found = &e;
    }
    if (!found) continue;
    CameraPose pose;
    pose.origin = *quake::parseVec3(found->value("origin")) + glm::vec3(0.0f, 0.0f, eye.height);
    readAngles(*found, pose);
    if (game == Game::Quake3 && eye.height == 0.0f) aimAtTarget(scene, *found, pose);
    pose.source = std::string(eye.classname);
    return pose;
  }
  return std::nullopt;
}

} // namespace

CameraPose defaultCameraPose(const Scene& scene) {
  if (auto pose = gameCamera(scene); pose && withinLevel(scene, pose->origin)) return facingTheLevel(scene, *pose);
  if (auto pose = insideCameraPose(scene)) return *pose;
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

std::vector<CameraPose> spawnCameraPoses(const Scene& scene) {
  const Game game = gameOf(scene);
  std::vector<CameraPose> poses;
  for (const EyePoint& eye : eyePoints(game))
    for (const Entity& e : scene.entities) {
      const auto origin = quake::parseVec3(e.value("origin"));
      if (e.classname() != eye.classname || !origin) continue;
      CameraPose pose;
      pose.origin = *origin + glm::vec3(0.0f, 0.0f, eye.height);
      readAngles(e, pose);
      if (game == Game::Quake3 && eye.height == 0.0f) aimAtTarget(scene, e, pose);
      pose.source = fmt::format("{} (line {})", eye.classname, e.line);
      if (withinLevel(scene, pose.origin)) poses.push_back(pose);
    }
  return poses;
}

Camera::Camera(const CameraPose& pose, int width, int height, float horizontalFovDegrees)
    : origin_(pose.origin), width_(width), height_(height) {
  const quake::ViewVectors view = quake::angleVectors(pose.pitch, pose.yaw, pose.roll);
  forward_ = view.forward;
  right_ = view.right;
  up_ = view.up;
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

std::optional<glm::vec3> Camera::project(const glm::vec3& point) const {
  const glm::vec3 d = point - origin_;
  const float depth = glm::dot(d, forward_);
  if (!(depth > 1e-3f)) return std::nullopt;
  const float ndcX = glm::dot(d, right_) / (depth * tanHalfX_), ndcY = glm::dot(d, up_) / (depth * tanHalfY_);
  return glm::vec3((ndcX + 1.0f) * 0.5f * float(width_), (1.0f - ndcY) * 0.5f * float(height_), depth);
}

} // namespace bt
