// A model file of the game's, turned into what a Scene draws: triangles (MeshVertex corners in
// model space, st in texels) grouped by the material they are drawn with, the materials added
// to the scene on the way.
#pragma once

#include "importers/game/game_install.h"
#include "importers/import.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace bt::models {

struct ModelPart {
  Face faceTemplate;               // texture, material (an index into the scene's materials)
  std::vector<MeshVertex> corners; // three per triangle, model space
};

struct LoadedModel {
  std::vector<ModelPart> parts;
};

// Reads `path` (".mdl", ".md2", ".md3", ".bsp") from the install's files and loads its skins and
// textures into scene.materials. Throws ImportError naming the file when it is corrupt;
// returns nullopt when the game's files do not hold it.
std::optional<LoadedModel> loadModel(const game::GameInstall& install, const std::string& path, int skin, const ImportOptions& options,
                                     Scene& scene);

} // namespace bt::models
