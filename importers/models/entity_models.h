// Entity models: the models the game shows at point entities (items, weapons, monsters, Quake 3
// misc_model), from the game install's files, added to the scene as meshes (MeshKind::Model) so
// that both tracers draw them as they draw Quake 3's triangle soups.
#pragma once

#include "importers/import.h"
#include "scene/scene.h"

#include <string>
#include <string_view>

namespace bt::models {

// The model file a point entity names or its classname gets (model_tables.h), and the .mdl skin;
// empty when it has none. `game` is a game profile name ("quake", "quake2", "quake3").
struct EntityModel {
  std::string path;
  int skin = 0;
};
EntityModel entityModel(const Entity& entity, std::string_view game);

// Adds the model of every point entity that has one, placed at its origin, turned by its angles
// and, for misc_model, scaled by modelscale / modelscale_vec. The game's files are those of
// `levelPath`'s install (importers/game/game_install.h). A model the files lack adds nothing:
// one note says how many were not found; a corrupt one adds a warning naming it.
void addEntityModels(Scene& scene, const std::string& levelPath, const ImportOptions& options);

// That note, for the commands that show it (`render`, `info`: notes are otherwise not shown);
// nullptr when every model was found.
const Diagnostic* missingModelsNote(const Scene& scene);

} // namespace bt::models
