// A level being loaded by the viewer, at start-up or after a save, off the frame loop.
#pragma once

#include "importers/textures/missing_textures.h"
#include "renderer/gl/gl_level.h"
#include "viewer/viewer.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace bt {

// A level being loaded, at start-up or after a save: the import and preparation on a worker
// thread (the frames go on showing the current level), then the upload on the frame's thread.
// Rebuilt whole every time, so a failed reload leaves the level on screen untouched.
struct PendingLevel {
  std::unique_ptr<gl::GlLevel> level = std::make_unique<gl::GlLevel>();
  // Where the level's missing textures would be: a texture that appears there reloads it. Found
  // on the worker too (the loose folders are indexed again).
  std::shared_ptr<std::vector<std::string>> missingFiles = std::make_shared<std::vector<std::string>>();
  std::unique_ptr<gl::LevelPreparation> preparation;

  // Its lights as the map gives them: the light-style sliders scale them once it is shown.
  explicit PendingLevel(const ViewerOptions& options)
      : preparation(gl::prepareGlLevel(
            *level,
            [map = options.map, import = options.import, missing = missingFiles](const gl::EntitiesRead& entitiesRead) {
              Scene scene = importScene(map, import, entitiesRead);
              *missing = missingTextureFiles(scene, import.textures);
              return scene;
            },
            gl::glSceneOptions())) {} // a CPU window's bake computes the visapprox boxes as it starts
};

// What to watch when a level never loaded: the file named (an archive's for ARCHIVE:maps/x.bsp).
std::filesystem::path levelFileOf(const std::string& map);

} // namespace bt
