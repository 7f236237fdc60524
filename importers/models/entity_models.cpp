#include "importers/models/entity_models.h"

#include "importers/game/game_install.h"
#include "importers/models/model_files.h"
#include "importers/models/model_tables.h"
#include "quake/entity_keys.h"
#include "quake/view_angles.h"
#include "scene/names.h"

#include <glm/mat3x3.hpp>

#include <filesystem>
#include <map>

namespace bt::models {
namespace {

bool isModelFile(std::string_view path) {
  const std::string ext = lowercase(std::filesystem::path(std::string(path)).extension().string());
  return ext == ".mdl" || ext == ".md2" || ext == ".md3" || ext == ".bsp";
}

// Where the model's axes go: forward, left, up of the entity's angles. Quake 3 and misc_model
// read "angles" (pitch yaw roll), else the yaw "angle", as the games' spawn code does
// (G_SetMovedir, q3map2's misc_model). Quake's GL renderer turns an alias model's pitch the other
// way (R_RotateForEntity's -angles[PITCH]), which its brush models undo.
glm::dmat3 placementAxes(const Entity& e, bool aliasPitchFlipped) {
  const quake::EntityKeys keys(e);
  glm::vec3 angles(0.0f);
  if (const auto a = keys.vec3("angles"))
    angles = *a;
  else
    angles.y = keys.number("angle", 0.0f);
  if (aliasPitchFlipped) angles.x = -angles.x;
  const quake::ViewVectors v = quake::angleVectors(angles.x, angles.y, angles.z);
  return glm::dmat3(glm::dvec3(v.forward), -glm::dvec3(v.right), glm::dvec3(v.up));
}

// q3map2's misc_model scale: modelscale_vec (per axis), else modelscale, else 1.
glm::dvec3 placementScale(const Entity& e) {
  if (e.classname() != "misc_model") return glm::dvec3(1.0);
  const quake::EntityKeys keys(e);
  if (const auto v = keys.vec3("modelscale_vec")) return glm::dvec3(*v);
  return glm::dvec3(keys.number("modelscale", 1.0f));
}

void place(const LoadedModel& model, uint32_t entity, const glm::dmat3& axes, const glm::dvec3& scale, const dvec3& origin, Scene& scene) {
  for (const ModelPart& part : model.parts) {
    scene.meshes.push_back(Mesh{scene.entities[entity].line, entity, MeshKind::Model, uint32_t(scene.faces.size()), 0, {}});
    auto moved = [&](MeshVertex v) {
      v.position = origin + axes * (v.position * scale);
      return v;
    };
    for (size_t k = 0; k + 2 < part.corners.size(); k += 3)
      scene.addMeshTriangle(moved(part.corners[k]), moved(part.corners[k + 1]), moved(part.corners[k + 2]), part.faceTemplate);
    if (scene.meshes.back().faceCount == 0) scene.meshes.pop_back();
  }
}

std::string_view gameName(const game::GameInstall& install, const Scene& scene, const ImportOptions& options) {
  if (install.profile) return install.profile->name;
  if (!options.textures.game.game.empty()) return options.textures.game.game;
  const game::GameProfile* p = game::profileForFormat(scene.format);
  return p ? p->name : std::string_view{};
}

// Any point entity that could show a model, under any game's table: the install is opened only then.
bool anyCandidate(const Scene& scene) {
  for (const Entity& e : scene.entities)
    if (e.brushCount == 0)
      for (const char* game : {"quake", "quake2", "quake3"})
        if (!entityModel(e, game).path.empty()) return true;
  return false;
}

constexpr std::string_view kNotDrawn = " not drawn: ";

void noteMissing(Scene& scene, const std::map<std::string, int>& missing, bool haveInstall) {
  if (missing.empty()) return;
  int count = 0;
  std::string names;
  for (const auto& [path, n] : missing) {
    count += n;
    if (names.size() < 200) names += (names.empty() ? "" : ", ") + path + (n > 1 ? " x" + std::to_string(n) : "");
  }
  scene.diagnostics.push_back(
      {Severity::Note, scene.sourcePath, 0, 0,
       std::to_string(count) + " entity model" + (count == 1 ? "" : "s") +
           " not drawn: " + (haveInstall ? "not in the game's files (" : "no game install holds them (--game, --basedir; ") + names + ")"});
}

} // namespace

EntityModel entityModel(const Entity& entity, std::string_view game) {
  const quake::EntityKeys keys(entity);
  const std::string_view model = keys.string("model");
  if (!model.empty() && isModelFile(model)) return {std::string(model), keys.integer("skin", 0)};
  if (const ClassModel* c = findClassModel(game, entity.classname(), keys.integer("spawnflags", 0)))
    return {std::string(c->model), c->skin};
  return {};
}

const Diagnostic* missingModelsNote(const Scene& scene) {
  for (const Diagnostic& d : scene.diagnostics)
    if (d.severity == Severity::Note && d.message.find(" entity model") != std::string::npos &&
        d.message.find(kNotDrawn) != std::string::npos)
      return &d;
  return nullptr;
}

void addEntityModels(Scene& scene, const std::string& levelPath, const ImportOptions& options) {
  if (!anyCandidate(scene)) return; // brush-only levels pay nothing
  const game::GameInstall install = game::openGameInstall(options.textures.game, levelPath, scene.format);
  const std::string_view game = gameName(install, scene, options);
  std::map<std::string, std::optional<LoadedModel>> loaded; // by path and skin
  std::map<std::string, int> missing;
  const uint32_t entities = uint32_t(scene.entities.size());
  for (uint32_t i = 0; i < entities; ++i) {
    const Entity& e = scene.entities[i];
    if (e.brushCount != 0) continue;
    const EntityModel m = entityModel(e, game);
    if (m.path.empty()) continue;
    const std::string key = m.path + "#" + std::to_string(m.skin);
    if (!loaded.contains(key)) {
      try {
        loaded[key] = install.files.empty() ? std::nullopt : loadModel(install, m.path, m.skin, options, scene);
      } catch (const ImportError& error) {
        scene.diagnostics.push_back(
            {Severity::Warning, error.diagnostic().file, 0, 0, "entity model not drawn: " + error.diagnostic().message});
        loaded[key] = LoadedModel{};
      }
    }
    if (!loaded[key]) {
      ++missing[m.path];
      continue;
    }
    const Entity& placed = scene.entities[i];
    const dvec3 origin(quake::EntityKeys(placed).vec3("origin").value_or(glm::vec3(0.0f)));
    const bool aliasPitch = game == "quake" && lowercase(std::filesystem::path(m.path).extension().string()) == ".mdl";
    place(*loaded[key], i, placementAxes(placed, aliasPitch), placementScale(placed), origin, scene);
  }
  noteMissing(scene, missing, !install.files.empty());
}

} // namespace bt::models
